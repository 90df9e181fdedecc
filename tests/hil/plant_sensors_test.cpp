// The plant's sensors: the IMU (rate, bias, noise, range) and the motion capture (rate,
// latency, noise, dropouts, the pole's quaternion).
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "hil/plant/plant.hpp"
#include "plant_test_configs.hpp"

using hil::MotorCommands;
using hil::Plant;
using hil::PlantConfig;
using hil::Vec3;

namespace {

PlantConfig noiseless() { return plant_test::without_mocap_noise(plant_test::without_imu_errors()); }

const MotorCommands kOff{};

double mean(const std::vector<double>& x) {
  double s = 0.0;
  for (const double v : x) s += v;
  return s / static_cast<double>(x.size());
}

double stddev(const std::vector<double>& x) {
  const double m = mean(x);
  double s = 0.0;
  for (const double v : x) s += (v - m) * (v - m);
  return std::sqrt(s / static_cast<double>(x.size() - 1));
}

}  // namespace

TEST_CASE("the IMU samples at its rate, on its ticks, every sample once") {
  PlantConfig c = noiseless();
  c.imu.rate_Hz = 1000;
  Plant plant(c);
  // Steps that do not line up with the samples: they still come at every 1 ms.
  std::vector<hil::ImuSample> samples;
  for (int k = 0; k < 300; ++k) {
    plant.step(0.0007, kOff, kOff);
    hil::ImuSample s;
    while (plant.pop_imu(pa::kVehicle1, s)) samples.push_back(s);
  }
  REQUIRE(samples.size() == 210);
  for (std::size_t i = 0; i < samples.size(); ++i) {
    CHECK(samples[i].tick == i + 1);
    CHECK(samples[i].t_s == Approx(0.001 * static_cast<double>(i + 1)).margin(1e-12));
  }
  // A parked vehicle's IMU reads +g along body z and nothing else.
  CHECK(samples.back().accel_mps2.isApprox(Vec3(0, 0, 9.81), 1e-9));
  CHECK(samples.back().gyro_radps.norm() < 1e-12);
}

TEST_CASE("the IMU adds its per-run bias and white noise of the configured size") {
  PlantConfig c;
  c.imu.accel_noise_mps2 = 0.05;
  c.imu.gyro_noise_radps = 0.003;
  c.imu.accel_bias_sigma_mps2 = 0.1;
  c.imu.gyro_bias_sigma_radps = 0.005;
  Plant plant(c, 42);
  plant.set_vehicle(pa::kVehicle1, plant.hovering_vehicle(Vec3(0, 0, 2), 0.0));
  std::vector<double> az;
  std::vector<double> gx;
  for (int k = 0; k < 4000; ++k) {
    plant.step(0.001, plant.hover_commands(pa::kVehicle1), kOff);
    hil::ImuSample s;
    while (plant.pop_imu(pa::kVehicle1, s)) {
      az.push_back(s.accel_mps2.z());
      gx.push_back(s.gyro_radps.x());
    }
  }
  const hil::ImuModel& imu = plant.imu_model(pa::kVehicle1);
  // The biases are drawn from the seed; one draw is not zero.
  CHECK(imu.accel_bias_mps2().norm() > 1e-4);
  CHECK(mean(az) == Approx(9.81 + imu.accel_bias_mps2().z()).margin(0.005));
  CHECK(mean(gx) == Approx(imu.gyro_bias_radps().x()).margin(0.0003));
  CHECK(stddev(az) == Approx(0.05).epsilon(0.05));
  CHECK(stddev(gx) == Approx(0.003).epsilon(0.05));
  // The two vehicles' IMUs are independent.
  CHECK((plant.imu_model(pa::kVehicle2).accel_bias_mps2() - imu.accel_bias_mps2()).norm() > 1e-4);
}

TEST_CASE("the IMU clips at its range") {
  PlantConfig c = noiseless();
  c.imu.accel_range_mps2 = 5.0;
  c.imu.gyro_range_radps = 34.9;
  Plant plant(c);
  hil::VehicleState v = plant.hovering_vehicle(Vec3(0, 0, 5), 0.0);
  v.body.rate_body_radps = Vec3(0, 0, 50.0);  // spinning fast about z
  plant.set_vehicle(pa::kVehicle1, v);
  plant.step(0.001, plant.hover_commands(pa::kVehicle1), kOff);
  const hil::ImuSample& s = plant.latest_imu(pa::kVehicle1);
  CHECK(s.accel_mps2.z() == 5.0);
  CHECK(s.gyro_radps.z() == 34.9);
}

TEST_CASE("motion capture: 200 Hz frames of the true poses, delivered after the latency") {
  PlantConfig c = noiseless();
  c.mocap.latency_s = 0.0123;
  Plant plant(c);
  plant.set_vehicle(pa::kVehicle1, plant.hovering_vehicle(Vec3(0.1, 0.2, 1.0), 0.3));
  // A tumbling pole: the frame must hold its pose at the capture time, not at delivery.
  plant.set_pole(Plant::make_pole(Vec3(0, 0, 20), Vec3(0.2, 0.1, 1.0), Vec3(0.3, 0, 4), Vec3(1.0, 3.0, 0.5)));
  std::vector<hil::PoleState> truth{plant.pole()};  // at t = k ms
  std::vector<hil::CapturedFrame> frames;
  std::vector<double> seen_at;
  for (int k = 0; k < 1000; ++k) {
    plant.step(0.001, plant.hover_commands(pa::kVehicle1), kOff);
    truth.push_back(plant.pole());
    hil::CapturedFrame f;
    while (plant.pop_mocap(f)) {
      frames.push_back(f);
      seen_at.push_back(plant.t_s());
    }
  }
  REQUIRE(frames.size() >= 195);
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const hil::CapturedFrame& f = frames[i];
    INFO("frame " << i);
    CHECK(f.index == i);
    CHECK(f.capture_t_s == Approx(0.005 * static_cast<double>(i)).margin(1e-12));
    CHECK(f.delivery_t_s == Approx(f.capture_t_s + 0.0123).margin(1e-12));
    // Visible no earlier than its delivery, and at the first step that reaches it.
    CHECK(seen_at[i] >= f.delivery_t_s - 1e-12);
    CHECK(seen_at[i] < f.delivery_t_s + 0.001);
    const hil::PoleState& p = truth[static_cast<std::size_t>(std::llround(f.capture_t_s * 1000))];
    const hil::CapturedPose& pose = f.pose[static_cast<int>(hil::Body::pole)];
    CHECK(pose.seen);
    CHECK((pose.position_m - p.body.position_m).norm() < 1e-12);
    // The pole's quaternion turns body z into the pole's axis n.
    CHECK((pose.attitude * Vec3::UnitZ() - p.axis()).norm() < 1e-12);
    const hil::CapturedPose& v1 = f.pose[static_cast<int>(hil::Body::vehicle1)];
    CHECK((v1.position_m - Vec3(0.1, 0.2, 1.0)).norm() < 1e-9);
  }
}

TEST_CASE("motion capture noise has the configured size") {
  PlantConfig c;
  c.mocap.position_noise_m = 0.001;
  c.mocap.attitude_noise_rad = 0.002;
  Plant plant(c, 7);
  plant.set_vehicle(pa::kVehicle1, plant.parked_vehicle(0.5, 0.5, 0.0));
  const hil::RigidBodyState truth = plant.vehicle(pa::kVehicle1).body;
  std::vector<double> dx;
  std::vector<double> angle2;
  for (int k = 0; k < 10000; ++k) {
    plant.step(0.001, kOff, kOff);
    hil::CapturedFrame f;
    while (plant.pop_mocap(f)) {
      const hil::CapturedPose& p = f.pose[0];
      dx.push_back(p.position_m.x() - truth.position_m.x());
      const double a = p.attitude.angularDistance(truth.attitude);
      angle2.push_back(a * a);
    }
  }
  CHECK(stddev(dx) == Approx(0.001).epsilon(0.1));
  CHECK(std::abs(mean(dx)) < 0.0002);
  // A rotation of three independent components of 2 mrad each: 2 sqrt(3) mrad rms.
  CHECK(std::sqrt(mean(angle2)) == Approx(0.002 * std::sqrt(3.0)).epsilon(0.1));
}

TEST_CASE("motion capture loses bodies at the dropout rate, and jitter keeps frames in order") {
  PlantConfig c = noiseless();
  c.mocap.dropout_probability = 0.3;
  c.mocap.jitter_s = 0.008;
  Plant plant(c, 3);
  int bodies = 0;
  int lost = 0;
  double last_delivery = -1.0;
  bool in_order = true;
  for (int k = 0; k < 10000; ++k) {
    plant.step(0.001, kOff, kOff);
    hil::CapturedFrame f;
    while (plant.pop_mocap(f)) {
      in_order = in_order && f.delivery_t_s >= last_delivery;
      last_delivery = f.delivery_t_s;
      CHECK(f.delivery_t_s >= f.capture_t_s + c.mocap.latency_s);
      for (const hil::CapturedPose& p : f.pose) {
        ++bodies;
        if (!p.seen) ++lost;
      }
    }
  }
  CHECK(in_order);
  CHECK(static_cast<double>(lost) / bodies == Approx(0.3).margin(0.03));

  c.mocap.dropout_probability = 1.0;
  Plant blind(c, 3);
  for (int k = 0; k < 100; ++k) blind.step(0.001, kOff, kOff);
  hil::CapturedFrame f;
  int frames = 0;
  while (blind.pop_mocap(f)) {
    ++frames;
    for (const hil::CapturedPose& p : f.pose) CHECK_FALSE(p.seen);
  }
  CHECK(frames > 10);
}

TEST_CASE("motion capture with dropout outages hides each body for 100 ms stretches") {
  PlantConfig c = noiseless();
  c.mocap.dropout_probability = 0.1;
  c.mocap.dropout_outage_s = 0.1;
  Plant plant(c, 4);
  std::array<int, 3> run{}, longest{}, outages{}, hidden{};
  int frames = 0;
  for (int k = 0; k < 60000; ++k) {
    plant.step(0.001, kOff, kOff);
    hil::CapturedFrame f;
    while (plant.pop_mocap(f)) {
      ++frames;
      for (std::size_t b = 0; b < 3; ++b) {
        run[b] = f.pose[b].seen ? 0 : run[b] + 1;
        if (run[b] == 1) ++outages[b];
        if (!f.pose[b].seen) ++hidden[b];
        longest[b] = std::max(longest[b], run[b]);
      }
    }
  }
  for (std::size_t b = 0; b < 3; ++b) {
    CAPTURE(b);
    // 10 % of 60 s in 0.1 s outages (20 frames at 200 Hz): about 60 each, each body on its own.
    CHECK(static_cast<double>(hidden[b]) / frames == Approx(0.1).margin(0.03));
    CHECK(outages[b] > 35);
    CHECK(outages[b] < 70);
    CHECK(longest[b] >= 20);
  }
  CHECK(hidden[0] != hidden[2]);
}
