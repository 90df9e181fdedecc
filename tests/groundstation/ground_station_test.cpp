// The runtime (groundstation/runtime/ground_station.hpp) on its own, on an in-memory bus with no
// vehicle behind it: which attempts it accepts and why it refuses the others. (Its flights are
// tested in the lockstep arena, tests/hil/series_test.cpp.)
#include <catch2/catch.hpp>

#include <optional>
#include <vector>

#include "groundstation/link/frame_bus.hpp"
#include "groundstation/runtime/ground_station.hpp"

namespace {

using gs::runtime::AttemptRequest;
using gs::runtime::GroundStation;
using gs::runtime::GroundStationConfig;

// Every vehicle of the act with a key (the link refuses to start without).
GroundStationConfig keyed() {
  GroundStationConfig c;
  for (const pa::VehicleId v : pa::kActVehicles) {
    gs::link::VehicleKey key{v, {}};
    key.key.fill(static_cast<std::uint8_t>(0x30 + v.node()));  // an all-zero key is no key
    c.link.keys.push_back(key);
  }
  return c;
}

}  // namespace

TEST_CASE("An attempt is accepted once at a time, only for a vehicle of the act") {
  gs::link::InMemoryFrameBus bus;
  GroundStation station(bus, keyed());
  CHECK(station.request_attempt(AttemptRequest{}));
  CHECK(station.refusal().empty());
  CHECK(station.current_attempt().number == 1);
  CHECK_FALSE(station.request_attempt(AttemptRequest{}));
  CHECK(station.refusal() == "an attempt is running");
  CHECK(station.refusal_kind() == GroundStation::Refusal::busy);
  CHECK(station.current_attempt().number == 1);

  GroundStation other(bus, keyed());
  AttemptRequest stranger;
  stranger.thrower = pa::VehicleId(7);
  CHECK_FALSE(other.request_attempt(stranger));
  CHECK(other.refusal() == "vehicle 7 is not of the act");
}

TEST_CASE("A vehicle too weak for its part is refused the attempt, with the numbers") {
  gs::link::InMemoryFrameBus bus;
  GroundStationConfig config = keyed();
  // Both vehicles start from a measured gain of 0.6: 0.6 a_full = 14.8 m/s^2 at most, where the
  // throw peaks at 17.1 m/s^2 (0.9 of it needed: 15.4) and the catch needs 0.9 (g + a_max) = 12.6.
  config.thrust_gain.initial_gain = 0.6;
  GroundStation weak(bus, config);
  CHECK_FALSE(weak.request_attempt(AttemptRequest{}));
  CAPTURE(weak.refusal());
  CHECK(weak.refusal().find("vehicle 1 is too weak to throw: thrust gain 0.60 gives 14.8 m/s^2 at most") !=
        std::string::npos);
  CHECK(weak.refusal_kind() == GroundStation::Refusal::too_weak);
  CHECK(GroundStation::refusal_name(weak.refusal_kind()) == "vehicle_too_weak");
  CHECK(weak.attempt_phase() == gs::runtime::AttemptPhase::idle);
  CHECK(weak.current_attempt().number == 0);
  // At 0.85 both parts fit (measured: 19 of 19 caught with every motor at 0.85).
  config.thrust_gain.initial_gain = 0.85;
  GroundStation able(bus, config);
  CHECK(able.request_attempt(AttemptRequest{}));
  // The same gain on a pack sagged to 10.5 V: the motors' ceiling falls by (10.5 / 12.6)^2.
  GroundStation sagging(bus, config);
  pa::proto::Frame status;
  REQUIRE(pa::proto::encode(pa::proto::TelemetryStatus{500, 10500, 0, 0, 0}, pa::kVehicle1.node(), status));
  sagging.on_frame(status, 0.1);
  CHECK_FALSE(sagging.request_attempt(AttemptRequest{}));
  CAPTURE(sagging.refusal());
  CHECK(sagging.refusal().find(
            "vehicle 1 is too weak to throw: thrust gain 0.85 at 10.50 V gives 14.5 m/s^2") !=
        std::string::npos);
}

TEST_CASE("A throw that would leave the arena's volume is refused before it is flown") {
  gs::link::InMemoryFrameBus bus;
  GroundStationConfig config = keyed();
  // The Fig. 5 throw from the configured origin: the thrower dips about 1.1 m and the pole's end
  // rises at most 4.4 m above the origin (`groundstation plan-throw` prints the reach).
  gs::runtime::ArenaVolume volume;
  volume.min_m = Eigen::Vector3d(-4.0, -4.0, 0.0);
  volume.max_m = Eigen::Vector3d(8.0, 4.0, 9.0);
  config.arena_volume = volume;
  GroundStation roomy(bus, config);
  CHECK(roomy.request_attempt(AttemptRequest{}));

  config.arena_volume->max_m.z() = config.throw_origin_m.z() + 4.0;
  GroundStation low(bus, config);
  CHECK_FALSE(low.request_attempt(AttemptRequest{}));
  CAPTURE(low.refusal());
  CHECK(low.refusal_kind() == GroundStation::Refusal::outside_volume);
  CHECK(low.refusal().find("the throw reaches z = ") == 0);
  CHECK(low.current_attempt().number == 0);
}

namespace {

template <class M>
pa::proto::Frame from_vehicle1(const M& message) {
  pa::proto::Frame f;
  REQUIRE(pa::proto::encode(message, pa::kVehicle1.node(), f));
  return f;
}

// A vehicle 1 on the floor that speaks to the link (heartbeats, its session), hears the ground
// station and is seen by the motion capture, for `seconds` from `t_s` at 200 Hz; returns the frames the station sent.
std::vector<pa::proto::Frame> sit_on_the_floor(GroundStation& station, gs::link::InMemoryFrameBus& bus,
                                               double& t_s, double seconds) {
  std::vector<pa::proto::Frame> sent;
  for (const double end = t_s + seconds; t_s < end; t_s += 0.005) {
    pa::proto::VehicleHeartbeat heartbeat{};
    heartbeat.uptime_ms = static_cast<std::uint32_t>(1e3 * t_s);
    heartbeat.mode = pa::proto::Mode::disarmed;
    heartbeat.flags = pa::proto::kFlagGroundHeartbeatOk;  // it hears the ground; its IMU is not ok
    station.on_frame(from_vehicle1(heartbeat), t_s);
    station.on_frame(from_vehicle1(pa::proto::LinkSession{0xC0FFEE, 0}), t_s);
    gs::estimation::MocapFrame frame;
    frame.t_s = t_s;
    frame.vehicle[0] = gs::estimation::MocapPose{};
    station.on_mocap(frame, t_s);
    station.tick(t_s);
    for (const pa::proto::Frame& f : bus.take()) sent.push_back(f);
  }
  return sent;
}

}  // namespace

TEST_CASE("A vehicle that refuses ARM is parked again, and the event says what it answered") {
  gs::link::InMemoryFrameBus bus;
  GroundStation station(bus, keyed());
  double t = 1.0;
  sit_on_the_floor(station, bus, t, 0.5);
  station.take_events();
  station.request_take_off(pa::kVehicle1);
  std::optional<pa::proto::Command> arm;
  for (const pa::proto::Frame& f : sit_on_the_floor(station, bus, t, 0.05)) {
    pa::proto::Message m;
    if (pa::proto::decode(f, m) == pa::proto::DecodeStatus::ok && m.type == pa::proto::Type::command)
      arm = m.command;
  }
  REQUIRE(station.task(pa::kVehicle1) == gs::mission::Task::arming);
  REQUIRE(arm);
  REQUIRE(arm->code == pa::proto::CommandCode::arm);
  // Its IMU is missing: ARM refused.
  station.on_frame(from_vehicle1(pa::proto::CommandAck{
                       arm->seq, pa::proto::CommandCode::arm, pa::proto::AckResult::refused,
                       pa::proto::Mode::disarmed, pa::proto::RefuseReason::imu_unhealthy}),
                   t);
  sit_on_the_floor(station, bus, t, 0.05);
  CHECK(station.task(pa::kVehicle1) == gs::mission::Task::parked);
  bool told = false;
  for (const gs::runtime::MissionEvent& e : station.take_events()) {
    if (e.vehicle != pa::kVehicle1 || e.to != gs::mission::Task::parked) continue;
    CHECK(e.reason == gs::mission::Reason::arm_failed);
    CHECK(e.why == "ARM refused: imu_unhealthy");
    told = true;
  }
  CHECK(told);
}
