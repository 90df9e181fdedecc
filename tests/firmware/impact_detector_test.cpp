// Impact detector: synthetic 1 kHz IMU streams with seeded noise. The "truth" vehicle below is
// written independently of the detector: double precision, the exact exponential motor lag,
// an IMU slightly off the centre of gravity, contact pulses as half-sines.
#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <limits>
#include <random>
#include <vector>

#include "fw/config.hpp"
#include "fw/impact_detector.hpp"
#include "pa/sequence.hpp"

namespace {

using fw::ImpactDetector;
using fw::ImpactEvent;
using fw::ImpactInput;
using fw::ImpactStage;
using pa::proto::ImpactClass;
using D3 = std::array<double, 3>;

constexpr double kPi = 3.14159265358979323846;
constexpr double kG = 9.81;

// A contact: a half-sine of specific force along `direction` (normalised here), and a change of
// body rate that builds up over the contact and then stays.
struct Pulse {
  double onset_s = 0;
  double duration_s = 0.005;
  double peak_mps2 = 30;
  D3 direction{0, 0, -1};
  D3 rate_change_radps{0, 0, 0};

  double shape(double t_s) const {
    const double tau = t_s - onset_s;
    if (tau <= 0 || tau >= duration_s) return 0;
    return std::sin(kPi * tau / duration_s);
  }
  double kick(double t_s) const {
    const double tau = t_s - onset_s;
    if (tau <= 0) return 0;
    if (tau >= duration_s) return 1;
    return 0.5 * (1 - std::cos(kPi * tau / duration_s));
  }
  D3 unit() const {
    const double n =
        std::sqrt(direction[0] * direction[0] + direction[1] * direction[1] + direction[2] * direction[2]);
    return D3{direction[0] / n, direction[1] / n, direction[2] / n};
  }
};

struct Report {
  std::uint32_t tick_us;  // the sample that produced the report
  double tick_s;          // the same, as stream time
  ImpactEvent event;
};

D3 cross(const D3& a, const D3& b) {
  return D3{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

// The truth vehicle and its IMU.
struct Sim {
  explicit Sim(std::uint32_t seed) : rng(seed) {}

  std::uint32_t t0_us = 1000000;  // vehicle clock at stream time 0
  double motor_tau_s = 0.03;      // the real motors' lag
  double thrust_scale = 1.0;      // real thrust / commanded (a mis-identified thrust map)
  std::function<double(double)> force_offset_mps2 = [](double) { return 0.0; };  // e.g. a mass mismatch
  double accel_noise_mps2 = 0.05;
  double gyro_noise_radps = 0.005;
  D3 imu_offset_m{0.01, 0.005, 0.01};  // IMU position relative to the centre of gravity
  std::function<double(double)> command_mps2 = [](double) { return kG; };
  std::function<D3(double)> rates_radps = [](double) { return D3{0, 0, 0}; };
  std::function<bool(double)> catch_expected = [](double) { return false; };
  // The floor: while it carries the vehicle the specific force is at least g.
  std::function<bool(double)> on_floor = [](double) { return false; };
  std::vector<Pulse> pulses;
  // Optional tampering with the input just before the detector sees it (non-finite tests).
  std::mt19937 rng;
  std::normal_distribution<double> normal{0.0, 1.0};

  ImpactInput sample(int k, double& thrust_true, double& last_command) {
    const double dt = 1e-3;
    const double t = k * dt;
    if (k == 0) {
      last_command = command_mps2(0);
      thrust_true = last_command;
    } else {
      // Exact zero-order-hold step of the first-order lag with the command of the last interval.
      thrust_true += (1 - std::exp(-dt / motor_tau_s)) * (last_command - thrust_true);
    }
    const D3 w = rates_radps(t);
    const D3 w_prev = rates_radps(t - dt);
    const D3 w_dot{(w[0] - w_prev[0]) / dt, (w[1] - w_prev[1]) / dt, (w[2] - w_prev[2]) / dt};
    // Specific force at the IMU: thrust, the rigid-body terms of an off-centre IMU, contacts.
    D3 f{0, 0, thrust_scale * thrust_true + force_offset_mps2(t)};
    if (on_floor(t) && f[2] < kG) f[2] = kG;
    const D3 tangential = cross(w_dot, imu_offset_m);
    const D3 centripetal = cross(w, cross(w, imu_offset_m));
    D3 gyro = w;
    for (int i = 0; i < 3; ++i) f[i] += tangential[i] + centripetal[i];
    for (const Pulse& p : pulses) {
      const D3 u = p.unit();
      for (int i = 0; i < 3; ++i) {
        f[i] += p.peak_mps2 * p.shape(t) * u[i];
        gyro[i] += p.rate_change_radps[i] * p.kick(t);
      }
    }
    ImpactInput in;
    in.t_us = t0_us + static_cast<std::uint32_t>(k) * 1000u;
    for (int i = 0; i < 3; ++i) {
      in.accel_mps2[i] = static_cast<float>(f[i] + accel_noise_mps2 * normal(rng));
      in.gyro_radps[i] = static_cast<float>(gyro[i] + gyro_noise_radps * normal(rng));
    }
    in.commanded_thrust_mps2 = static_cast<float>(last_command);  // applied since the last sample
    in.catch_expected = catch_expected(t);
    last_command = command_mps2(t);
    return in;
  }

  std::vector<Report> run(ImpactDetector& detector, double duration_s) {
    std::vector<Report> reports;
    double thrust = 0, command = 0;
    const int n = static_cast<int>(duration_s * 1000.0 + 0.5);
    for (int k = 0; k < n; ++k) {
      const ImpactInput in = sample(k, thrust, command);
      ImpactEvent e;
      if (detector.update(in, e)) reports.push_back(Report{in.t_us, k * 1e-3, e});
    }
    return reports;
  }

  // Stream time (s) of a vehicle clock reading, wrap-safe (streams shorter than 2^31 us).
  double stream_s(std::uint32_t t_us) const { return pa::elapsed_us(t_us, t0_us) * 1e-6; }
};

ImpactDetector make_detector() { return ImpactDetector(fw::ImpactDetectorConfig{}, fw::AirframeConfig{}); }

// A ground-station style command: a smooth profile held for 5 ms at a time (200 Hz frames).
std::function<double(double)> staircase(std::function<double(double)> profile) {
  return [profile](double t) { return profile(std::floor(t / 0.005) * 0.005); };
}

double blend(double t, double t0, double t1, double a, double b) {
  if (t <= t0) return a;
  if (t >= t1) return b;
  return a + (b - a) * 0.5 * (1 - std::cos(kPi * (t - t0) / (t1 - t0)));
}

// The throw (paper Section III-A, Fig. 5): collective from hover up to 20 m/s^2, down to the
// launch value 4.5 m/s^2 and back, over 2.5 s, with pitch-rate manoeuvres up to 10 rad/s.
double throw_thrust(double t) {
  if (t < 1.5) return blend(t, 0.5, 1.5, kG, 20.0);
  if (t < 2.0) return 20.0;
  if (t < 2.4) return blend(t, 2.0, 2.4, 20.0, 4.5);
  if (t < 3.0) return 4.5;
  return blend(t, 3.0, 3.5, 4.5, kG);
}
D3 throw_rates(double t) {
  if (t < 0.5 || t > 3.0) return D3{0, 0, 0};
  const double s = std::sin(2 * kPi * (t - 0.5) / 2.5);
  return D3{3.0 * s * s, 10.0 * std::sin(4 * kPi * (t - 0.5) / 2.5), 1.5 * s};
}

}  // namespace

TEST_CASE("hover with sensor noise starts no event", "[impact]") {
  ImpactDetector detector = make_detector();
  Sim sim(1);
  SECTION("nominal IMU noise, 60 s") { CHECK(sim.run(detector, 60.0).empty()); }
  SECTION("ten times the IMU noise, 20 s") {
    sim.accel_noise_mps2 = 0.5;
    sim.gyro_noise_radps = 0.05;
    CHECK(sim.run(detector, 20.0).empty());
  }
  CHECK(detector.count() == 0);
}

TEST_CASE("a throw manoeuvre starts no event", "[impact]") {
  ImpactDetector detector = make_detector();
  Sim sim(2);
  sim.command_mps2 = staircase(throw_thrust);
  sim.rates_radps = throw_rates;
  sim.catch_expected = [](double) { return true; };  // even when a catch would be believed
  SECTION("motors as modelled") {}
  SECTION("motors 50 % slower than modelled") { sim.motor_tau_s = 0.045; }
  SECTION("thrust 10 % below the command") { sim.thrust_scale = 0.9; }
  SECTION("thrust 10 % above the command and twice the IMU noise") {
    sim.thrust_scale = 1.1;
    sim.accel_noise_mps2 = 0.1;
  }
  CHECK(sim.run(detector, 4.0).empty());
}

TEST_CASE("a take-off from the floor starts no event", "[impact]") {
  ImpactDetector detector = make_detector();
  Sim sim(3);
  // Motors off on the floor, then a 12 m/s^2 step: the floor carries the vehicle until the
  // thrust exceeds its weight, so the residual falls from +g to zero through the motor lag.
  sim.command_mps2 = [](double t) { return t < 0.5 ? 0.0 : 12.0; };
  sim.on_floor = [](double t) { return t < 0.7; };
  CHECK(sim.run(detector, 1.5).empty());
}

TEST_CASE("slow changes of the specific force start no event", "[impact]") {
  ImpactDetector detector = make_detector();
  Sim sim(4);
  SECTION("mass mismatch: hover force 1.5 m/s^2 above the command") {
    sim.force_offset_mps2 = [](double) { return 1.5; };
  }
  SECTION("mass mismatch: hover force 1.5 m/s^2 below the command") {
    sim.force_offset_mps2 = [](double) { return -1.5; };
  }
  SECTION("8 m/s^2 of extra load appearing over 0.2 s") {
    sim.force_offset_mps2 = [](double t) { return blend(t, 2.0, 2.2, 0.0, -8.0); };
  }
  CHECK(sim.run(detector, 20.0).empty());
}

TEST_CASE("catch impacts are detected within 5 ms, timed within 1 ms and measured within 10 %", "[impact]") {
  double worst_latency_s = 0, worst_onset_error_s = 0, worst_peak_error = 0;
  int cases = 0;
  for (double duration_ms : {3.0, 5.0, 8.0, 12.0, 15.0}) {
    for (double peak : {15.0, 25.0, 35.0, 50.0, 65.0}) {
      for (double phase_ms : {0.0, 0.25, 0.5, 0.75}) {
        ++cases;
        ImpactDetector detector = make_detector();
        Sim sim(static_cast<std::uint32_t>(100 + cases));
        Pulse p;
        p.onset_s = 0.3 + phase_ms * 1e-3;
        p.duration_s = duration_ms * 1e-3;
        p.peak_mps2 = peak;
        p.direction = D3{0.15, 0.05, -1.0};        // friction at the plate: a little lateral force
        p.rate_change_radps = D3{1.5, -1.0, 0.2};  // off-centre contact
        sim.pulses.push_back(p);
        sim.catch_expected = [](double t) { return t > 0.1 && t < 0.5; };
        const std::vector<Report> reports = sim.run(detector, 0.5);

        INFO("pulse " << duration_ms << " ms, " << peak << " m/s^2, phase " << phase_ms << " ms");
        REQUIRE(reports.size() == 2);
        const Report& detected = reports[0];
        const Report& classified = reports[1];
        CHECK(detected.event.stage == ImpactStage::detected);
        CHECK(detected.event.classification == ImpactClass::catch_impact);
        CHECK(classified.event.stage == ImpactStage::classified);
        CHECK(classified.event.classification == ImpactClass::catch_impact);
        CHECK(classified.tick_s > detected.tick_s);
        CHECK(classified.event.t_us == detected.event.t_us);
        CHECK(classified.event.count == 1);
        CHECK(detected.event.detected_us == detected.tick_us);

        const double latency_s = detected.tick_s - p.onset_s;
        const double onset_error_s = sim.stream_s(detected.event.t_us) - p.onset_s;
        const double peak_error = static_cast<double>(classified.event.peak_mps2) / peak - 1.0;
        CHECK(latency_s > 0.0);
        CHECK(latency_s <= 0.005);
        CHECK(std::fabs(onset_error_s) <= 0.001);
        CHECK(std::fabs(peak_error) <= 0.10);
        worst_latency_s = std::max(worst_latency_s, latency_s);
        worst_onset_error_s = std::max(worst_onset_error_s, std::fabs(onset_error_s));
        worst_peak_error = std::max(worst_peak_error, std::fabs(peak_error));
      }
    }
  }
  std::printf(
      "impact detector over %d catch pulses: worst detection latency %.2f ms, worst onset error %.2f ms, "
      "worst peak error %.1f %%\n",
      cases, worst_latency_s * 1e3, worst_onset_error_s * 1e3, worst_peak_error * 100.0);
}

TEST_CASE("a catch-like impact while no catch is expected is unexpected", "[impact]") {
  ImpactDetector detector = make_detector();
  Sim sim(5);
  Pulse p;
  p.onset_s = 0.4003;
  p.duration_s = 0.006;
  p.peak_mps2 = 30;
  p.rate_change_radps = D3{1.0, 0, 0};
  sim.pulses.push_back(p);
  SECTION("never expected") {}
  SECTION("the window closed before the impact") {
    sim.catch_expected = [](double t) { return t < 0.39; };
  }
  const std::vector<Report> reports = sim.run(detector, 0.6);
  REQUIRE(reports.size() == 2);
  CHECK(reports[0].event.classification == ImpactClass::unexpected_impact);
  CHECK(reports[1].event.classification == ImpactClass::unexpected_impact);
  CHECK(reports[1].event.peak_mps2 == Approx(30).epsilon(0.1));
}

TEST_CASE("an upward bump is never a catch", "[impact]") {
  ImpactDetector detector = make_detector();
  Sim sim(6);
  Pulse p;  // a gentle touch-down: the floor pushes up
  p.onset_s = 0.3;
  p.duration_s = 0.008;
  p.peak_mps2 = 20;
  p.direction = D3{0.1, 0, 1};
  sim.pulses.push_back(p);
  sim.catch_expected = [](double) { return true; };
  const std::vector<Report> reports = sim.run(detector, 0.5);
  REQUIRE(reports.size() == 2);
  CHECK(reports[1].event.classification == ImpactClass::unexpected_impact);
}

TEST_CASE("a pole caught askew, pushing sideways through the plate's friction, is a catch", "[impact]") {
  // Met at 50-60 degrees of tilt, a pole pushes the plate down and sideways by up to the plate's
  // friction (0.7 here): the lateral part alone (35 m/s^2) is above crash_lateral_mps2.
  ImpactDetector detector = make_detector();
  Sim sim(8);
  Pulse p;
  p.onset_s = 0.3;
  p.duration_s = 0.008;
  p.peak_mps2 = 50;
  p.direction = D3{0.7, 0.0, -1.0};
  p.rate_change_radps = D3{0, 3, 0};
  sim.pulses.push_back(p);
  SECTION("in a catch window: a catch") {
    sim.catch_expected = [](double) { return true; };
    const std::vector<Report> reports = sim.run(detector, 0.5);
    REQUIRE(reports.size() == 2);
    CHECK(reports[1].event.classification == ImpactClass::catch_impact);
  }
  SECTION("outside one: a crash, as any strong sideways push") {
    const std::vector<Report> reports = sim.run(detector, 0.5);
    REQUIRE(reports.size() == 2);
    CHECK(reports[1].event.classification == ImpactClass::crash);
  }
}

TEST_CASE("crashes are told apart from catches", "[impact]") {
  ImpactDetector detector = make_detector();
  Sim sim(7);
  sim.catch_expected = [](double) { return true; };  // a crash stays a crash inside a catch window
  Pulse p;
  p.onset_s = 0.3002;
  SECTION("striking the floor: large upward peak, lateral part, spin") {
    p.duration_s = 0.006;
    p.peak_mps2 = 120;
    p.direction = D3{0.3, 0.1, 1};
    p.rate_change_radps = D3{25, -30, 5};
  }
  SECTION("a sideways hit: the lateral part alone") {
    p.duration_s = 0.008;
    p.peak_mps2 = 35;
    p.direction = D3{1, 0.2, 0.15};
    p.rate_change_radps = D3{0, 4, 0};
  }
  SECTION("an arm strikes an obstacle: moderate force, large spin") {
    p.duration_s = 0.006;
    p.peak_mps2 = 25;
    p.direction = D3{0.1, 0, -1};
    p.rate_change_radps = D3{28, 0, 3};
  }
  SECTION("a hard push down, far above any pole") {
    p.duration_s = 0.005;
    p.peak_mps2 = 90;
    p.direction = D3{0, 0, -1};
  }
  sim.pulses.push_back(p);
  const std::vector<Report> reports = sim.run(detector, 0.5);
  REQUIRE(reports.size() == 2);
  CHECK(reports[0].event.stage == ImpactStage::detected);
  CHECK(reports[0].tick_s - p.onset_s <= 0.005);
  CHECK(reports[1].event.stage == ImpactStage::classified);
  CHECK(reports[1].event.classification == ImpactClass::crash);
  // A crash is classified as soon as a threshold is crossed, not at the end of the contact.
  CHECK(reports[1].tick_s <= p.onset_s + p.duration_s);
}

TEST_CASE("while a landing is expected, the floor's push is a crash only above the touchdown peak",
          "[impact]") {
  // Stiff feet touching down at the failsafe descent's rate: a short, hard push up the body
  // z-axis, above crash_peak_mps2 (80) but below touchdown_crash_peak_mps2 (250).
  Pulse touchdown;
  touchdown.onset_s = 0.3002;
  touchdown.duration_s = 0.004;
  touchdown.peak_mps2 = 100;
  touchdown.direction = D3{0.1, 0, 1};
  touchdown.rate_change_radps = D3{1, -1, 0};
  Sim sim(11);
  sim.on_floor = [](double t) { return t >= 0.302; };
  sim.command_mps2 = [](double) { return 8.0; };  // descending: a little under hover thrust
  bool landing = true;
  SECTION("a touchdown while landing is an unexpected impact") {}
  SECTION("the same push without a landing expected is a crash") { landing = false; }
  SECTION("a touchdown above the touchdown peak is a crash") { touchdown.peak_mps2 = 300; }
  SECTION("a touchdown that tips the vehicle over is a crash") { touchdown.rate_change_radps = D3{25, 0, 0}; }
  SECTION("the floor's friction on drifting feet adds a lateral part: still a touchdown") {
    touchdown.direction = D3{0.5, 0, 1};  // 45 m/s^2 sideways, above crash_lateral_mps2 (25)
  }
  SECTION("a sideways hit while landing is a crash") {
    touchdown.peak_mps2 = 40;
    touchdown.direction = D3{1, 0, 0.2};
  }
  SECTION("a push down while landing is not a touchdown") { touchdown.direction = D3{0, 0, -1}; }
  sim.pulses.push_back(touchdown);
  ImpactDetector detector = make_detector();
  // The flag is raised from the start: the vehicle has been descending.
  const std::vector<Report> reports = [&] {
    std::vector<Report> out;
    double thrust = 0, command = 0;
    for (int k = 0; k < 500; ++k) {
      ImpactInput in = sim.sample(k, thrust, command);
      in.landing_expected = landing;
      ImpactEvent e;
      if (detector.update(in, e)) out.push_back(Report{in.t_us, k * 1e-3, e});
    }
    return out;
  }();
  REQUIRE(reports.size() == 2);
  CHECK(std::fabs(sim.stream_s(reports[0].event.t_us) - touchdown.onset_s) <= 0.001);
  const bool upward = touchdown.direction[2] > 0 && touchdown.direction[0] < 1;
  const bool expect_crash =
      !landing || !upward || touchdown.peak_mps2 > 250 || touchdown.rate_change_radps[0] > 15;
  CHECK((reports[1].event.classification == ImpactClass::crash) == expect_crash);
  if (!expect_crash) CHECK(reports[1].event.classification == ImpactClass::unexpected_impact);
  // A touchdown is what the vehicle treats as meeting the floor (vehicle.cpp).
  CHECK(reports[1].event.touchdown == (landing && upward && !expect_crash));
}

TEST_CASE("a lasting step is one event, not a train of them", "[impact]") {
  ImpactDetector detector = make_detector();
  Sim sim(8);
  sim.force_offset_mps2 = [](double t) { return t < 0.3 ? 0.0 : -10.0; };  // something heavy lands and stays
  const std::vector<Report> reports = sim.run(detector, 3.0);
  REQUIRE(reports.size() == 2);
  CHECK(reports[0].event.stage == ImpactStage::detected);
  CHECK(reports[1].event.stage == ImpactStage::classified);
  CHECK(reports[1].event.classification == ImpactClass::unexpected_impact);
  // Never released: classified when the event window closes.
  CHECK(sim.stream_s(reports[1].tick_us) - sim.stream_s(reports[1].event.t_us) ==
        Approx(0.020).margin(0.0011));
  CHECK(reports[1].event.peak_mps2 == Approx(10.0).epsilon(0.1));
}

TEST_CASE("the clock may wrap during an event", "[impact]") {
  ImpactDetector detector = make_detector();
  Sim sim(9);
  sim.t0_us = 0xFFFFFFFFu - 300000u + 1u;  // stream time 0.3 s is vehicle time 0
  Pulse p;
  p.onset_s = 0.2995;  // 0.5 ms before the wrap
  p.duration_s = 0.008;
  p.peak_mps2 = 25;
  sim.pulses.push_back(p);
  sim.catch_expected = [](double) { return true; };
  const std::vector<Report> reports = sim.run(detector, 1.0);
  REQUIRE(reports.size() == 2);
  CHECK(reports[0].event.t_us > 0xFFFF0000u);  // the onset lies before the wrap ...
  CHECK(reports[0].tick_us < 0x10000u);        // ... the detection after it
  CHECK(std::fabs(sim.stream_s(reports[0].event.t_us) - p.onset_s) <= 0.001);
  CHECK(reports[0].tick_s - p.onset_s <= 0.005);
  CHECK(reports[1].event.classification == ImpactClass::catch_impact);
  CHECK(reports[1].event.peak_mps2 == Approx(25).epsilon(0.1));
}

TEST_CASE("non-finite input is ignored and leaves the state untouched", "[impact]") {
  ImpactDetector clean = make_detector();
  ImpactDetector fed = make_detector();
  Sim sim(10);
  Pulse p;
  p.onset_s = 0.2002;
  p.duration_s = 0.010;
  p.peak_mps2 = 30;
  sim.pulses.push_back(p);
  sim.catch_expected = [](double) { return true; };

  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  double thrust = 0, command = 0;
  std::vector<ImpactEvent> from_clean, from_fed;
  for (int k = 0; k < 400; ++k) {
    const ImpactInput in = sim.sample(k, thrust, command);
    // Before the pulse, on its rising edge and at its peak, the second detector also gets a
    // broken copy of the sample.
    if (k % 50 == 0 || k == 201 || k == 203 || k == 205) {
      ImpactInput bad = in;
      ImpactEvent untouched{};
      untouched.t_us = 12345;
      ImpactEvent e = untouched;
      switch ((k / 50 + k) % 4) {
        case 0: bad.accel_mps2[2] = nan; break;
        case 1: bad.gyro_radps[0] = inf; break;
        case 2: bad.commanded_thrust_mps2 = nan; break;
        default: bad.accel_mps2[0] = -inf; break;
      }
      CHECK_FALSE(fed.update(bad, e));
      CHECK(e.t_us == 12345);  // `out` not written
    }
    ImpactEvent a, b;
    const bool ra = clean.update(in, a);
    const bool rb = fed.update(in, b);
    REQUIRE(ra == rb);
    CHECK(clean.expected_thrust_mps2() == fed.expected_thrust_mps2());
    CHECK(clean.residual_mps2() == fed.residual_mps2());
    if (ra) {
      from_clean.push_back(a);
      from_fed.push_back(b);
    }
  }
  REQUIRE(from_clean.size() == 2);
  for (std::size_t i = 0; i < from_clean.size(); ++i) {
    CHECK(from_clean[i].t_us == from_fed[i].t_us);
    CHECK(from_clean[i].peak_mps2 == from_fed[i].peak_mps2);
    CHECK(from_clean[i].classification == from_fed[i].classification);
  }
}

TEST_CASE("after an event only a crash-level change starts another for the refractory period", "[impact]") {
  ImpactDetector detector = make_detector();
  Sim sim(11);
  sim.catch_expected = [](double) { return true; };
  Pulse catch1;  // ends at 0.31 s
  catch1.onset_s = 0.300;
  catch1.duration_s = 0.010;
  catch1.peak_mps2 = 30;
  Pulse bounce = catch1;  // the absorber's rebound 40 ms later: not a second impact
  bounce.onset_s = 0.350;
  bounce.peak_mps2 = 20;
  Pulse crash;  // but a crash 70 ms after the catch still is
  crash.onset_s = 0.380;
  crash.duration_s = 0.005;
  crash.peak_mps2 = 100;
  crash.direction = D3{0.2, 0, 1};
  Pulse catch2 = catch1;  // long after the refractory period: a new event
  catch2.onset_s = 0.700;
  sim.pulses = {catch1, bounce, crash, catch2};
  const std::vector<Report> reports = sim.run(detector, 1.0);
  REQUIRE(reports.size() == 6);
  CHECK(reports[0].event.count == 1);
  CHECK(reports[1].event.classification == ImpactClass::catch_impact);
  CHECK(reports[2].event.count == 2);
  CHECK(std::fabs(sim.stream_s(reports[2].event.t_us) - crash.onset_s) <= 0.001);
  CHECK(reports[3].event.classification == ImpactClass::crash);
  CHECK(reports[4].event.count == 3);
  CHECK(std::fabs(sim.stream_s(reports[4].event.t_us) - catch2.onset_s) <= 0.001);
  CHECK(reports[5].event.classification == ImpactClass::catch_impact);
  CHECK(detector.count() == 3);
}

TEST_CASE("reset forgets the signal but keeps the count since boot", "[impact]") {
  ImpactDetector detector = make_detector();
  Sim sim(12);
  Pulse p;
  p.onset_s = 0.2;
  p.peak_mps2 = 30;
  sim.pulses.push_back(p);
  REQUIRE(sim.run(detector, 0.205).size() == 1);  // detected, not yet classified
  CHECK(detector.in_event());
  detector.reset();
  CHECK_FALSE(detector.in_event());
  CHECK(detector.count() == 1);
  CHECK(detector.residual_mps2() == fw::Vec3f{});
  // A new stream from scratch: the next impact is number 2.
  Sim again(13);
  again.pulses.push_back(p);
  const std::vector<Report> reports = again.run(detector, 0.4);
  REQUIRE(reports.size() == 2);
  CHECK(reports[1].event.count == 2);
}

TEST_CASE("the expected thrust follows the command through the motor lag", "[impact]") {
  fw::AirframeConfig airframe;
  airframe.motor_time_constant_s = 0.03f;
  ImpactDetector detector(fw::ImpactDetectorConfig{}, airframe);
  ImpactEvent e;
  ImpactInput in;
  in.accel_mps2 = fw::Vec3f{0, 0, 0};
  in.commanded_thrust_mps2 = 0;
  detector.update(in, e);
  in.commanded_thrust_mps2 = 10;
  for (int k = 1; k <= 30; ++k) {
    in.t_us = static_cast<std::uint32_t>(k) * 1000u;
    detector.update(in, e);
  }
  // One time constant after the step: 1 - 1/e of it.
  CHECK(detector.expected_thrust_mps2() == Approx(10.0 * (1.0 - std::exp(-1.0))).epsilon(0.005));
  // A negative command is zero thrust.
  in.commanded_thrust_mps2 = -50;
  for (int k = 31; k <= 1000; ++k) {
    in.t_us = static_cast<std::uint32_t>(k) * 1000u;
    detector.update(in, e);
  }
  CHECK(detector.expected_thrust_mps2() == Approx(0.0).margin(1e-3));
}

TEST_CASE("forty minutes after an event the detector is as sensitive as before", "[impact]") {
  // Longer than 2^31 us: a clock difference to the first event's end would have wrapped.
  ImpactDetector detector = make_detector();
  Sim sim(14);
  sim.catch_expected = [](double) { return true; };
  Pulse first;
  first.onset_s = 0.3;
  first.duration_s = 0.008;
  first.peak_mps2 = 25;
  Pulse second = first;
  second.onset_s = 2400.3;
  sim.pulses = {first, second};
  const std::vector<Report> reports = sim.run(detector, 2400.5);
  REQUIRE(reports.size() == 4);
  CHECK(reports[3].event.classification == ImpactClass::catch_impact);
  CHECK(reports[2].tick_s - second.onset_s <= 0.005);
  // Stream time of the onset, from the report's own tick (the stream is longer than int32 us).
  const double onset_s = reports[2].tick_s + pa::elapsed_us(reports[2].event.t_us, reports[2].tick_us) * 1e-6;
  CHECK(std::fabs(onset_s - second.onset_s) <= 0.001);
}
