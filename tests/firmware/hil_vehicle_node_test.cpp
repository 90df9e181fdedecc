// The POSIX port's in-process path: a vehicle on an in-memory bus, driven by HIL_IMU frames as
// the plant drives it, allocating nothing once running.
#include <catch2/catch.hpp>

#include <atomic>
#include <cstdlib>
#include <new>

#include "hil_vehicle_node.hpp"
#include "in_memory_bus.hpp"

using namespace pa::proto;

namespace {
std::atomic<long> g_allocations{0};
}

// Counting replacements of the global allocation functions: the loop must not call them.
// AddressSanitizer owns these functions in the sanitizer build, where the count is not taken
// (the host build runs this test too).
#ifndef __SANITIZE_ADDRESS__
#define PA_COUNT_ALLOCATIONS 1
void* operator new(std::size_t n) {
  ++g_allocations;
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t n) {
  ++g_allocations;
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
#endif

TEST_CASE("a vehicle on the in-memory bus answers every IMU sample with its motors, allocating nothing") {
  enum { kPlant = 0, kVehicle = 1, kGround = 2 };
  static fw::posix::InMemoryBus<3, 512> bus;
  fw::VehicleConfig config{};
  config.link.vehicle = pa::kVehicle1;
  config.link.key = pa::auth::Key{9, 8, 7, 6, 5, 4, 3, 2, 1, 0, 1, 2, 3, 4, 5, 6};
  config.link.session_nonce = 99;
  static fw::posix::HilVehicleNode node(config);
  static pa::auth::Signer ground(config.link.key);
  ground.start_session(config.link.session_nonce, 0);

  const long before = g_allocations.load();
  int motor_frames = 0, undecodable = 0, motors_on = 0;
  std::uint16_t last_tick = 0;
  for (std::uint16_t tick = 0; tick < 2000; ++tick) {
    Frame f;
    encode(HilImuGyro{{0, 0, 0}, tick}, 1, f);
    bus.send(kPlant, f);
    encode(HilImuAccel{{0, 0, 9.81f}, tick}, 1, f);
    bus.send(kPlant, f);
    Frame auth;
    if (tick % 20 == 0 &&
        encode(GsHeartbeat{tick, 7, GroundState::active, static_cast<std::uint8_t>(tick / 20)}, 1, f) &&
        ground.sign(f, auth)) {
      bus.send(kGround, f);
      bus.send(kGround, auth);
    }
    while (bus.receive(kVehicle, f)) node.on_frame(f, [&](const Frame& out) { bus.send(kVehicle, out); });
    while (bus.receive(kPlant, f)) {
      Message m;
      if (decode(f, m) != DecodeStatus::ok) ++undecodable;
      if (m.type == Type::hil_motors) {
        ++motor_frames;
        last_tick = m.hil_motors.tick;
        if (m.hil_motors.command[0] != 0.0f) ++motors_on;  // disarmed: motors off
      }
    }
    while (bus.receive(kGround, f)) {
    }
  }
  // No Catch2 assertion runs inside the loop, so any allocation counted is the port's.
#ifdef PA_COUNT_ALLOCATIONS
  CHECK(g_allocations.load() == before);
#endif
  CHECK(undecodable == 0);
  CHECK(motors_on == 0);
  CHECK(motor_frames == 2000);
  CHECK(last_tick == 1999);
  CHECK(node.vehicle().link().heartbeat_live(1999000));
  CHECK(bus.overruns(kVehicle) == 0);
}

TEST_CASE("a lost IMU half costs one sample, never a mixed one") {
  fw::HilImuAssembler imu;
  fw::ImuSample s;
  Message g, a;
  g.type = Type::hil_imu_gyro;
  g.hil_imu_gyro = HilImuGyro{{1, 2, 3}, 10};
  a.type = Type::hil_imu_accel;
  a.hil_imu_accel = HilImuAccel{{0, 0, 9.81f}, 11};
  CHECK_FALSE(imu.on_message(g, s));
  CHECK_FALSE(imu.on_message(a, s));  // tick 11's accel with tick 10's gyro: not a sample
  g.hil_imu_gyro.tick = 11;
  REQUIRE(imu.on_message(g, s));
  CHECK(s.gyro_radps[0] == 1.0f);
  CHECK(s.t_us == 11000);
  // The 16-bit tick wraps; the clock keeps counting.
  g.hil_imu_gyro.tick = 65535;
  a.hil_imu_accel.tick = 65535;
  imu.on_message(g, s);
  REQUIRE(imu.on_message(a, s));
  g.hil_imu_gyro.tick = 0;
  a.hil_imu_accel.tick = 0;
  imu.on_message(g, s);
  REQUIRE(imu.on_message(a, s));
  CHECK(s.t_us == 65536u * 1000u);
}
