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

#include "groundstation/adaptation/throw_record.hpp"

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
         a.waiting_xy_m == b.waiting_xy_m && same(a.target_xy_m, b.target_xy_m) &&
         same_point(a.predicted, b.predicted) && same_point(a.actual, b.actual) && optimal_same &&
         same(a.catcher_at_impact_xy_m, b.catcher_at_impact_xy_m) &&
         a.energy_after_impact_J == b.energy_after_impact_J && a.note == b.note;
}

}  // namespace adaptation_test
