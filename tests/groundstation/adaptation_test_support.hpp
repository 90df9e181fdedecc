// Shared by the adaptation tests: a deterministic throw record per id (so a process that reopens
// a store can check every row against what the writer meant to write), exact record comparison
// and a scratch directory.
#pragma once

#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <random>
#include <string>

#include "groundstation/adaptation/adaptation_law.hpp"
#include "groundstation/adaptation/identification_record.hpp"
#include "groundstation/adaptation/throw_record.hpp"
#include "groundstation/model/impact.hpp"

namespace adaptation_test {

using gs::adaptation::CatchPoint;
using gs::adaptation::kAllThrowOutcomes;
using gs::adaptation::OptimalCatch;
using gs::adaptation::ThrowOutcome;
using gs::adaptation::ThrowRecord;

// A removed-on-exit directory under the system's temporary directory.
class ScratchDir {
 public:
  explicit ScratchDir(const std::string& name) {
    path_ = std::filesystem::temp_directory_path() /
            (name + "-" + std::to_string(::getpid()) + "-" + std::to_string(counter()++));
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~ScratchDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;
  std::string file(const std::string& name) const { return (path_ / name).string(); }

 private:
  static int& counter() {
    static int n = 0;
    return n;
  }
  std::filesystem::path path_;
};

// Throw `id` (1, 2, ...): every outcome in turn, optional figures present or absent in patterns
// that cover all combinations over a few dozen ids, values from a seeded generator.
inline ThrowRecord make_record(std::int64_t id) {
  std::mt19937_64 rng(static_cast<std::uint64_t>(id) * 0x9E3779B97F4A7C15ull + 17u);
  std::normal_distribution<double> n(0.0, 1.0);
  ThrowRecord r;
  r.time_s = 1000.0 + 60.0 * static_cast<double>(id) + n(rng);
  r.outcome = kAllThrowOutcomes[static_cast<std::size_t>(id) % std::size(kAllThrowOutcomes)];
  r.launch = {1.5 + 0.02 * n(rng), 2.0 + 0.02 * n(rng),  0.3 + 0.05 * n(rng),
              5.5 + 0.05 * n(rng), 0.48 + 0.02 * n(rng), 2.5 + 0.1 * n(rng)};
  r.launch_y_m = 0.02 * n(rng);
  r.launch_vy_mps = 0.05 * n(rng);
  r.catch_height_used_m = 1.34 + 0.05 * n(rng);
  r.waiting_xy_m = {0.64 + 0.1 * n(rng), 0.1 * n(rng)};
  if (id % 5 != 0) r.target_xy_m = Eigen::Vector2d(0.64 + 0.15 * n(rng), 0.13 * n(rng));
  if (id % 3 != 0) r.predicted = CatchPoint{{0.64 + 0.15 * n(rng), 0.13 * n(rng)}, 0.8 + 0.02 * n(rng)};
  if (id % 4 != 1) r.actual = CatchPoint{{0.64 + 0.15 * n(rng), 0.13 * n(rng)}, 0.8 + 0.02 * n(rng)};
  if (id % 6 != 2) {
    r.optimal =
        OptimalCatch{0.81 + 0.03 * n(rng), 1.343 + 0.08 * n(rng), {0.64 + 0.15 * n(rng), 0.13 * n(rng)}};
  }
  if (id % 7 != 3) r.catcher_at_impact_xy_m = Eigen::Vector2d(0.64 + 0.15 * n(rng), 0.13 * n(rng));
  if (id % 2 == 0) r.energy_after_impact_J = 0.196 + 0.01 * n(rng);
  if (id % 9 != 4) r.thrower = pa::kActVehicles[static_cast<std::size_t>(id) % 2];
  r.note = (id % 8 == 0) ? "pilot's note, with \"quotes\", a comma\nand a line break"
                         : "throw " + std::to_string(id);
  return r;
}

inline bool same(const std::optional<Eigen::Vector2d>& a, const std::optional<Eigen::Vector2d>& b) {
  return a.has_value() == b.has_value() && (!a || *a == *b);
}

// Field by field, exactly (a stored double must come back bit for bit).
inline bool same_record(const ThrowRecord& a, const ThrowRecord& b) {
  auto same_point = [](const std::optional<CatchPoint>& p, const std::optional<CatchPoint>& q) {
    return p.has_value() == q.has_value() && (!p || (p->xy_m == q->xy_m && p->t_s == q->t_s));
  };
  const bool optimal_same =
      a.optimal.has_value() == b.optimal.has_value() &&
      (!a.optimal || (a.optimal->t_s == b.optimal->t_s && a.optimal->height_m == b.optimal->height_m &&
                      a.optimal->xy_m == b.optimal->xy_m));
  return a.time_s == b.time_s && a.outcome == b.outcome && a.launch.x_m == b.launch.x_m &&
         a.launch.z_m == b.launch.z_m && a.launch.vx_mps == b.launch.vx_mps &&
         a.launch.vz_mps == b.launch.vz_mps && a.launch.alpha_rad == b.launch.alpha_rad &&
         a.launch.alpha_dot_radps == b.launch.alpha_dot_radps && a.launch_y_m == b.launch_y_m &&
         a.launch_vy_mps == b.launch_vy_mps && a.catch_height_used_m == b.catch_height_used_m &&
         a.waiting_xy_m == b.waiting_xy_m && same(a.target_xy_m, b.target_xy_m) && a.thrower == b.thrower &&
         same_point(a.predicted, b.predicted) && same_point(a.actual, b.actual) && optimal_same &&
         same(a.catcher_at_impact_xy_m, b.catcher_at_impact_xy_m) &&
         a.energy_after_impact_J == b.energy_after_impact_J && a.note == b.note;
}

// The nominal values of a store for the tests: catching height 1.40 m, waiting point (0.70, 0) m,
// E* of the default pole.
inline gs::adaptation::AdaptationSettings nominal_settings() {
  gs::adaptation::AdaptationSettings s;
  s.nominal_catch_height_m = 1.40;
  s.nominal_waiting_xy_m = {0.70, 0.0};
  s.target_energy_J = gs::model::upright_energy_J(gs::model::PoleParams{});
  return s;
}

// Identification `id` (1, 2, ...): vehicles 1 and 2 in turn, every third refused (each refusal
// in turn), every fourth without a thrust gain, figures from a seeded generator. Through id 9:
// vehicle 1's last accepted is 7 and its latest (9) refused; vehicle 2's last accepted is 8.
inline gs::adaptation::IdentificationRecord make_identification(std::int64_t id) {
  std::mt19937_64 rng(static_cast<std::uint64_t>(id) * 0x9E3779B97F4A7C15ull + 5u);
  std::normal_distribution<double> n(0.0, 1.0);
  gs::adaptation::IdentificationRecord r;
  r.vehicle = id % 2 == 1 ? pa::kVehicle1 : pa::kVehicle2;
  r.time_s = 10.0 + 30.0 * static_cast<double>(id) + n(rng);
  if (id % 3 == 0) {
    const auto& refusals = gs::estimation::kAllIdentificationRefusals;
    r.result.refusal = refusals[static_cast<std::size_t>(id / 3) % std::size(refusals)];
  } else {
    gs::estimation::MotorIdentification m;
    m.time_constant_s = 0.03 + 0.01 * std::abs(n(rng));
    m.time_constant_low_s = m.time_constant_s * (1.0 - 0.05 * std::abs(n(rng)));
    m.time_constant_high_s = m.time_constant_s * (1.0 + 0.05 * std::abs(n(rng)));
    m.inertia_gain = 1.0 + 0.1 * n(rng);
    m.round_trip_s = 0.02 + 0.002 * std::abs(n(rng));
    m.rms_radps = 0.05 + 0.01 * std::abs(n(rng));
    m.samples = 250 + static_cast<int>(id);
    r.result.identified = m;
  }
  if (id % 4 != 0) r.thrust_gain = 1.0 + 0.05 * n(rng);
  return r;
}

// Field by field, exactly.
inline bool same_identification(const gs::adaptation::IdentificationRecord& a,
                                const gs::adaptation::IdentificationRecord& b) {
  const auto& p = a.result.identified;
  const auto& q = b.result.identified;
  const bool fit_same =
      p.has_value() == q.has_value() &&
      (!p ||
       (p->time_constant_s == q->time_constant_s && p->time_constant_low_s == q->time_constant_low_s &&
        p->time_constant_high_s == q->time_constant_high_s && p->inertia_gain == q->inertia_gain &&
        p->round_trip_s == q->round_trip_s && p->rms_radps == q->rms_radps && p->samples == q->samples));
  return a.vehicle == b.vehicle && a.time_s == b.time_s && a.result.refusal == b.result.refusal && fit_same &&
         a.thrust_gain == b.thrust_gain;
}

}  // namespace adaptation_test
