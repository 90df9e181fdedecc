// `hil run`'s stepping logic (hil/run/plant_exchange.hpp) with everything it normally reaches
// over SocketCAN in memory: each vehicle bus an InMemoryBus between the plant and the real
// firmware core (fw::posix::HilVehicleNode, as fw_vehicle runs it), and the ground bus an
// InMemoryBus between the plant's radios and the test standing in for the ground station.
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <optional>
#include <vector>

#include "fw/config.hpp"
#include "groundstation/link/frame_bus.hpp"
#include "groundstation/runtime/ground_station.hpp"
#include "hil/plant/plant_config.hpp"
#include "hil/run/plant_exchange.hpp"
#include "hil/sil/firmware_vehicle.hpp"
#include "hil/sil/ground_station_frame.hpp"
#include "hil_vehicle_node.hpp"
#include "in_memory_bus.hpp"

using namespace pa::proto;

namespace {

constexpr std::size_t kPlantEnd = 0;  // each bus: the plant's endpoint ...
constexpr std::size_t kOtherEnd = 1;  // ... and the firmware's (vehicle buses) or the ground's

// The processes of `hil run`'s scenario, in one: the exchange, two firmware cores on their
// buses, and a ground bus. Each firmware answers only when pump() carries the frames, so the
// test sees what the exchange does between a sample and its answer.
class Rig {
 public:
  // `compensate`: false builds the firmware without its battery compensation (no reference voltage).
  explicit Rig(const hil::RadioConfig& radio, std::size_t vehicles = 2,
               const hil::PlantConfig& plant = hil::PlantConfig{}, bool compensate = true)
      : exchange(plant, radio, 11, vehicles) {
    for (std::size_t i = 0; i < vehicles; ++i) {
      const pa::VehicleId v = pa::kActVehicles[i];
      fw::VehicleConfig c =
          hil::sil::firmware_config_for(plant.vehicle, v, plant.battery.reference_voltage_V);
      if (!compensate) c.battery.reference_voltage_V = 0.0f;
      firmware[i].emplace(c);
    }
  }

  // What the exchange has for the buses goes on them (the edge's writes).
  void write() {
    for (std::size_t i = 0; i < exchange.vehicles(); ++i)
      for (const Frame& f : exchange.take_vehicle_frames(pa::kActVehicles[i]))
        vehicle_bus[i].send(kPlantEnd, f);
    for (const Frame& f : exchange.take_ground_frames()) ground_bus.send(kPlantEnd, f);
  }
  // Each firmware reads its bus and answers; the exchange reads what came back (the edge's reads).
  void pump() {
    Frame f;
    for (std::size_t i = 0; i < exchange.vehicles(); ++i) {
      while (vehicle_bus[i].receive(kOtherEnd, f))
        if (!dead[i])
          firmware[i]->on_frame(f, [&](const Frame& out) { vehicle_bus[i].send(kOtherEnd, out); });
      while (vehicle_bus[i].receive(kPlantEnd, f)) exchange.on_vehicle_frame(pa::kActVehicles[i], f);
    }
    while (ground_bus.receive(kPlantEnd, f)) exchange.on_ground_frame(f);
    while (ground_bus.receive(kOtherEnd, f)) at_ground.push_back(f);
  }
  // One lockstep period: step, write, and let the firmware answer.
  void lockstep() {
    REQUIRE(exchange.answered());
    exchange.step();
    write();
    pump();
  }

  hil::run::PlantExchange exchange;
  std::array<std::optional<fw::posix::HilVehicleNode>, 2> firmware;
  std::array<fw::posix::InMemoryBus<2, 1024>, 2> vehicle_bus{};
  fw::posix::InMemoryBus<2, 1024> ground_bus{};
  std::vector<Frame> at_ground;
  std::array<bool, 2> dead{};  // a firmware process killed: it reads nothing and answers nothing
};

hil::RadioConfig radio_without_jitter() {
  hil::RadioConfig r;
  r.latency_s = 0.008;
  r.jitter_s = 0.0;
  return r;
}

bool is_type(const Frame& f, Type type) { return id_type(f.id) == static_cast<std::uint8_t>(type); }

}  // namespace

TEST_CASE("The plant steps in lockstep with in-memory firmware: each sample answered before the next") {
  Rig rig(radio_without_jitter());
  REQUIRE(rig.exchange.answered());  // nothing sent yet
  rig.exchange.step();
  rig.write();
  // The samples are on the buses but the firmwares have not run: the plant must wait.
  CHECK_FALSE(rig.exchange.answered());
  rig.pump();
  CHECK(rig.exchange.answered());
  for (int k = 1; k < 500; ++k) rig.lockstep();

  CHECK(rig.exchange.t_s() == Approx(0.5));
  for (const pa::VehicleId v : pa::kActVehicles) {
    const hil::run::VehicleExchangeCounters c = rig.exchange.counters(v);
    CHECK(c.samples_sent == 500);
    CHECK(c.answered == 500);
    CHECK(c.missed == 0);
    CHECK(c.late_answers == 0);
    CHECK(c.samples_resent == 0);
    // Disarmed: the firmware answers with its motors off, and the plant holds them off.
    for (double m : rig.exchange.motor_commands(v).command) CHECK(m == 0.0);
    // It sent its heartbeats (50 Hz of its clock) through the radio, none of the HIL exchange.
    CHECK(c.downlink_offered >= 25);
    CHECK(c.not_carried == 0);
  }
  int heartbeats = 0;
  for (const Frame& f : rig.at_ground) {
    CHECK_FALSE(is_type(f, Type::hil_motors));
    CHECK_FALSE(is_type(f, Type::hil_imu_gyro));
    CHECK_FALSE(is_type(f, Type::hil_imu_accel));
    if (is_type(f, Type::vehicle_heartbeat)) ++heartbeats;
  }
  CHECK(heartbeats >= 2 * 24);
}

TEST_CASE("A sample stepped over without its answer is missed, and its commands held; a resend repeats it") {
  Rig rig(radio_without_jitter(), 1);
  rig.exchange.step();
  std::vector<Frame> first = rig.exchange.take_vehicle_frames(pa::kVehicle1);
  REQUIRE(first.size() == 2);
  CHECK(is_type(first[0], Type::hil_imu_gyro));
  CHECK(is_type(first[1], Type::hil_imu_accel));
  // A firmware started late never saw them: the edge asks for them again.
  rig.exchange.resend_unanswered();
  const std::vector<Frame> again = rig.exchange.take_vehicle_frames(pa::kVehicle1);
  REQUIRE(again.size() == 2);
  CHECK(again[0].data == first[0].data);
  CHECK(rig.exchange.counters(pa::kVehicle1).samples_resent == 1);
  // Realtime: the plant steps on regardless; the unanswered sample counts as missed.
  rig.exchange.step();
  CHECK(rig.exchange.counters(pa::kVehicle1).missed == 1);
  // An answer to the old sample now is late and changes nothing.
  Frame late;
  REQUIRE(encode(HilMotors{{0.5f, 0.5f, 0.5f, 0.5f}, 1}, pa::kVehicle1.node(), late));
  rig.exchange.on_vehicle_frame(pa::kVehicle1, late);
  CHECK(rig.exchange.counters(pa::kVehicle1).late_answers == 1);
  CHECK(rig.exchange.motor_commands(pa::kVehicle1).command[0] == 0.0);
  CHECK_FALSE(rig.exchange.answered());
  // The answer to the sample awaited (tick 2) is taken and held.
  Frame answer;
  REQUIRE(encode(HilMotors{{0.25f, 0.25f, 0.25f, 0.25f}, 2}, pa::kVehicle1.node(), answer));
  rig.exchange.on_vehicle_frame(pa::kVehicle1, answer);
  CHECK(rig.exchange.answered());
  CHECK(rig.exchange.motor_commands(pa::kVehicle1).command[0] == Approx(0.25).margin(1e-3));
}

TEST_CASE("The radios carry frames both ways with their latency, and only what a radio carries") {
  Rig rig(radio_without_jitter());
  rig.lockstep();  // t = 1 ms
  // A ground heartbeat to vehicle 2, read from the ground bus at t = 1 ms, and a HIL_IMU sample
  // put on the ground bus by mistake (no radio carries the HIL exchange).
  Frame heartbeat, stray;
  REQUIRE(encode(GsHeartbeat{1, 0x1234, GroundState::idle, 0}, pa::kVehicle2.node(), heartbeat));
  REQUIRE(encode(HilImuGyro{{0.0f, 0.0f, 0.0f}, 0}, pa::kVehicle1.node(), stray));
  rig.ground_bus.send(kOtherEnd, heartbeat);
  rig.ground_bus.send(kOtherEnd, stray);
  rig.pump();
  CHECK(rig.exchange.ground_frames_not_carried() == 1);
  CHECK(rig.exchange.counters(pa::kVehicle2).uplink_offered == 1);
  CHECK(rig.exchange.counters(pa::kVehicle1).uplink_offered == 0);

  // Due at 1 + 8 = 9 ms: it goes on vehicle 2's bus in the step that starts at 9 ms, no earlier.
  std::optional<double> arrived_at;
  for (int k = 0; k < 20 && !arrived_at; ++k) {
    const double start = rig.exchange.t_s();
    rig.exchange.step();
    for (const Frame& f : rig.exchange.take_vehicle_frames(pa::kVehicle2)) {
      if (f.id == heartbeat.id && f.data == heartbeat.data) arrived_at = start;
      rig.vehicle_bus[1].send(kPlantEnd, f);
    }
    for (const Frame& f : rig.exchange.take_vehicle_frames(pa::kVehicle1))
      rig.vehicle_bus[0].send(kPlantEnd, f);
    for (const Frame& f : rig.exchange.take_ground_frames()) rig.ground_bus.send(kPlantEnd, f);
    rig.pump();
  }
  REQUIRE(arrived_at);
  CHECK(*arrived_at == Approx(0.009).margin(1e-9));
  CHECK(rig.exchange.counters(pa::kVehicle2).uplink_delivered == 1);
  CHECK(rig.exchange.counters(pa::kVehicle1).uplink_delivered == 0);

  // Downlink: a frame the vehicle sends at t reaches the ground bus at the end of the first step
  // that ends at or after t + 8 ms.
  rig.at_ground.clear();
  Frame status;
  REQUIRE(encode(VehicleHeartbeat{77, Mode::disarmed, 0, 0, FailsafeReason::none, 0}, pa::kVehicle1.node(),
                 status));
  const double sent_at = rig.exchange.t_s();
  rig.exchange.on_vehicle_frame(pa::kVehicle1, status);
  std::optional<double> reached_ground_at;
  for (int k = 0; k < 20 && !reached_ground_at; ++k) {
    rig.lockstep();
    for (const Frame& f : rig.at_ground)
      if (f.data == status.data && f.id == status.id) reached_ground_at = rig.exchange.t_s();
  }
  REQUIRE(reached_ground_at);
  CHECK(*reached_ground_at - sent_at == Approx(0.008).margin(1e-9));
}

TEST_CASE("Ground frames for the ground's own node or a vehicle not here are carried by no radio") {
  Rig rig(radio_without_jitter());
  Frame f;
  REQUIRE(encode(Command{CommandCode::disarm, 99, 0x5A17, 0}, 3, f));
  rig.exchange.on_ground_frame(f);
  REQUIRE(encode(Command{CommandCode::disarm, 99, 0x5A17, 0}, kGroundNode, f));
  rig.exchange.on_ground_frame(f);
  REQUIRE(encode(GsHeartbeat{1, 0x1234, GroundState::idle, 0}, kBroadcastNode, f));
  rig.exchange.on_ground_frame(f);  // a broadcast: both radios
  CHECK(rig.exchange.ground_frames_not_carried() == 2);
  for (const pa::VehicleId v : pa::kActVehicles) CHECK(rig.exchange.counters(v).uplink_offered == 1);
}

TEST_CASE("With loss 1 nothing arrives either way, and the radios count it") {
  hil::RadioConfig lossy = radio_without_jitter();
  lossy.loss = 1.0;
  Rig rig(lossy);
  Frame heartbeat;
  for (int k = 0; k < 300; ++k) {
    if (k % 20 == 0) {
      for (const pa::VehicleId v : pa::kActVehicles) {
        REQUIRE(encode(GsHeartbeat{static_cast<std::uint32_t>(k), 0x1234, GroundState::idle, 0}, v.node(),
                       heartbeat));
        rig.ground_bus.send(kOtherEnd, heartbeat);
      }
    }
    rig.lockstep();
  }
  CHECK(rig.at_ground.empty());
  for (const pa::VehicleId v : pa::kActVehicles) {
    const hil::run::VehicleExchangeCounters c = rig.exchange.counters(v);
    CHECK(c.uplink_offered == 15);
    CHECK(c.uplink_lost == c.uplink_offered);
    CHECK(c.uplink_delivered == 0);
    // The firmware kept talking: its heartbeats at least.
    CHECK(c.downlink_offered >= 14);
    CHECK(c.downlink_lost == c.downlink_offered);
    CHECK(c.downlink_delivered == 0);
  }
}

TEST_CASE(
    "Silenced, the radios carry nothing more to the vehicles, neither lost nor delivered; the downlink goes on") {
  Rig rig(radio_without_jitter());
  Frame heartbeat;
  REQUIRE(encode(GsHeartbeat{1, 0x1234, GroundState::idle, 0}, pa::kVehicle1.node(), heartbeat));
  rig.ground_bus.send(kOtherEnd, heartbeat);
  rig.lockstep();
  rig.exchange.silence_uplink();  // the heartbeat is still in flight
  rig.ground_bus.send(kOtherEnd, heartbeat);
  for (int k = 0; k < 100; ++k) rig.lockstep();
  const hil::run::VehicleExchangeCounters c = rig.exchange.counters(pa::kVehicle1);
  CHECK(c.uplink_offered == 2);
  CHECK(c.uplink_lost == 0);
  CHECK(c.uplink_delivered == 0);
  CHECK(c.downlink_delivered > 0);
  CHECK_FALSE(rig.at_ground.empty());
}

TEST_CASE(
    "The person hands the pole up once the ground station shows the thrower waiting, still at the origin") {
  Rig rig(radio_without_jitter(), 1);
  hil::run::PlantExchange& exchange = rig.exchange;
  const hil::Vec3 origin(0.5, -0.5, 2.0);
  // Held in the air as the ground station would fly it (the firmware is not run here): the plate's
  // centre `offset` from the origin, moving at `speed`.
  const auto hold = [&](const hil::Vec3& offset, double speed_mps) {
    hil::VehicleState v = exchange.plant().vehicle(pa::kVehicle1);
    v.body.position_m += origin + offset - exchange.plant().plate_centre_m(pa::kVehicle1);
    v.body.velocity_mps = hil::Vec3(speed_mps, 0.0, 0.0);
    exchange.plant().set_vehicle(pa::kVehicle1, v);
    exchange.step();
  };
  exchange.show_waiting_for_pole(pa::kVehicle1, true);
  hold(hil::Vec3::Zero(), 0.0);
  CHECK(exchange.poles_handed() == 0);  // nobody asked
  exchange.hand_pole_to(pa::kVehicle1, origin);
  exchange.show_waiting_for_pole(pa::kVehicle1, false);
  hold(hil::Vec3::Zero(), 0.0);  // there, but still retreating on the ground station
  exchange.show_waiting_for_pole(pa::kVehicle1, true);
  hold(hil::Vec3(0.0, 0.0, 0.15), 0.0);
  hold(hil::Vec3(0.12, 0.0, 0.0), 0.0);
  hold(hil::Vec3::Zero(), 0.3);
  CHECK(exchange.poles_handed() == 0);
  // Within 0.1 m and 0.2 m/s at the start of a step: up, on the plate.
  const hil::Vec3 offset(0.05, 0.0, -0.05);
  hold(offset, 0.1);
  CHECK(exchange.poles_handed() == 1);
  const hil::Vec3 plate_m = origin + offset;
  const hil::PoleConfig& pole_config = exchange.plant().config().pole;
  const hil::PoleState& pole = exchange.plant().pole();
  CHECK(std::min((hil::pole_end_m(pole, pole_config, 0) - plate_m).norm(),
                 (hil::pole_end_m(pole, pole_config, 1) - plate_m).norm()) < 0.01);
  exchange.step();
  CHECK(exchange.poles_handed() == 1);  // once per request
}

TEST_CASE("The exchange refuses a vehicle count the arena does not have") {
  CHECK_THROWS_AS(hil::run::PlantExchange(hil::PlantConfig{}, hil::RadioConfig{}, 1, 0),
                  std::invalid_argument);
  CHECK_THROWS_AS(hil::run::PlantExchange(hil::PlantConfig{}, hil::RadioConfig{}, 1, 3),
                  std::invalid_argument);
  hil::run::PlantExchange one(hil::PlantConfig{}, hil::RadioConfig{}, 1, 1);
  CHECK_THROWS_AS(one.counters(pa::kVehicle2), std::out_of_range);
}

// What the guest scenario (hil/vcan/hil_run_on_vcan.sh) runs as processes, in one: the runtime on
// the ground bus with the simulation keys the firmware cores hold, the motion capture handed to it
// as hil run publishes it, a tick every 1 ms of the ground's clock. That clock runs
// `ground_per_plant` times as fast as the plant's, as `groundstation run`'s does when lockstep
// falls behind the clock (1: the plant keeps up).
class Flight {
 public:
  explicit Flight(double ground_per_plant, const hil::PlantConfig& plant = hil::PlantConfig{},
                  bool compensate = true)
      : rig_(hil::RadioConfig{}, 2, plant, compensate), ground_per_plant_(ground_per_plant) {
    for (const pa::VehicleId v : pa::kActVehicles)
      config_.link.keys.push_back({v, hil::sil::simulation_key(v)});
    // The thrust gain is measured from accelerations on the ground's clock; with the plant slower
    // than it they are not the vehicle's (measured: k 1.21 from 8 windows at half pace, and the
    // vehicles landed 0.5 s early). A real clock runs at one pace; these flights test pacing.
    config_.compensate_thrust_gain = ground_per_plant == 1.0;
    station_.emplace(bus_, config_);
  }

  // The ground-station process killed (nothing more from it), and started again: a new runtime
  // with a new session token, as `groundstation run` draws one per run.
  void kill_ground_station() { station_.reset(); }
  void restart_ground_station(std::uint16_t session) {
    config_.link.session = session;
    bus_.take();
    station_.emplace(bus_, config_);
  }

  // Steps until `done` or `limit_s` of the plant's time; whether `done`.
  template <class Done>
  bool run_until(double limit_s, Done&& done) {
    while (rig_.exchange.t_s() < limit_s && !done()) {
      rig_.lockstep();
      if (!station_) {
        rig_.at_ground.clear();
        rig_.exchange.take_mocap();
        continue;
      }
      const double plant_now = rig_.exchange.t_s();
      const double ground_now = ground_per_plant_ * plant_now;
      for (const Frame& f : rig_.at_ground) station_->on_frame(f, ground_now);
      rig_.at_ground.clear();
      for (const hil::CapturedFrame& m : rig_.exchange.take_mocap()) {
        // Stamped as hil run stamps it: as long before the ground's now as before the plant's.
        gs::estimation::MocapFrame frame = hil::sil::to_ground_station_frame(m);
        frame.t_s = ground_now - (plant_now - m.capture_t_s);
        station_->on_mocap(frame, ground_now);
      }
      for (; next_tick_s_ <= ground_now + 1e-9; next_tick_s_ += 0.001) station_->tick(next_tick_s_);
      // What hil run's person reads of the tasks (the task-change events).
      for (const pa::VehicleId v : pa::kActVehicles)
        rig_.exchange.show_waiting_for_pole(
            v, one(v, gs::mission::Task::hover) || one(v, gs::mission::Task::balance));
      for (const Frame& f : bus_.take()) rig_.ground_bus.send(kOtherEnd, f);
    }
    return done();
  }
  // Take-off on the operator's request, up to both hovering (within 15 s of the plant's time).
  bool take_off() {
    station_->request_take_off();
    return run_until(rig_.exchange.t_s() + 15.0, [&] { return both(gs::mission::Task::hover); });
  }
  bool one(pa::VehicleId v, gs::mission::Task task) const { return station_->task(v) == task; }
  bool both(gs::mission::Task task) const {
    return station_->task(pa::kVehicle1) == task && station_->task(pa::kVehicle2) == task;
  }
  gs::runtime::GroundStation& station() { return *station_; }
  Rig& rig() { return rig_; }

 private:
  Rig rig_;
  double ground_per_plant_;
  gs::link::InMemoryFrameBus bus_;
  gs::runtime::GroundStationConfig config_;
  std::optional<gs::runtime::GroundStation> station_;
  double next_tick_s_ = 0.0;
};

TEST_CASE("Through the exchange, the ground-station runtime takes both vehicles off, hovers and lands them") {
  using gs::mission::Task;
  // 1: the plant keeps up with the clock. 2: it runs steadily at 0.5 of real time, still a flight
  // within hil_run_on_vcan's bounds (which judges it from 0.8, as the guest's pace is irregular).
  const double ground_per_plant = GENERATE(1.0, 2.0);
  CAPTURE(ground_per_plant);
  Flight flight(ground_per_plant);
  Rig& rig = flight.rig();
  flight.run_until(0.5, [] { return false; });
  flight.station().request_take_off();
  REQUIRE(flight.run_until(15.0, [&] { return flight.both(Task::hover); }));
  const double hover_from = rig.exchange.t_s();
  REQUIRE_FALSE(flight.run_until(hover_from + 3.0, [&] { return !flight.both(Task::hover); }));
  flight.station().request_land();
  REQUIRE(flight.run_until(hover_from + 25.0, [&] { return flight.both(Task::parked); }));

  for (const pa::VehicleId v : pa::kActVehicles) {
    const hil::run::VehicleTruthSummary& truth = rig.exchange.truth_summary(v);
    CHECK(truth.highest_m > 0.8);
    CHECK(truth.highest_m < 1.5);
    CHECK(truth.airborne_s >= 3.0);
    CHECK(rig.exchange.plant().vehicle_on_floor(v));
    for (double m : rig.exchange.motor_commands(v).command) CHECK(m == 0.0);
    const hil::run::VehicleExchangeCounters c = rig.exchange.counters(v);
    CHECK(c.missed == 0);
    CHECK(c.answered == c.samples_sent);
  }
}

TEST_CASE(
    "With the plant at a quarter of real time, as in the QEMU guest, the take-off overshoots by half a metre") {
  // Why hil_run_on_vcan is skipped when the plant is slow (docs/hil.md): the ground station flies
  // on its clock a world that moves four times too slowly for it, and even with the plant's pace
  // steady (in the guest most steps also come late) the vehicles climb 0.6 m past the 1 m
  // take-off height, outside the scenario's bounds.
  Flight flight(4.0);
  flight.run_until(0.5, [] { return false; });
  flight.station().request_take_off();
  REQUIRE(flight.run_until(15.0, [&] { return flight.both(gs::mission::Task::hover); }));
  flight.run_until(flight.rig().exchange.t_s() + 3.0, [] { return false; });
  for (const pa::VehicleId v : pa::kActVehicles)
    CHECK(flight.rig().exchange.truth_summary(v).highest_m > 1.5);
}

TEST_CASE("With the ground station on the plant's clock, each step waits for its HIL_CLOCK_DONE as well") {
  Rig rig(radio_without_jitter(), 1);
  rig.exchange.join_ground_clock();
  rig.lockstep();
  // The step's last ground frame is its clock: step 1, no motion capture delivered yet (the
  // first frame is due after the mocap latency).
  REQUIRE_FALSE(rig.at_ground.empty());
  Message clock;
  REQUIRE(decode(rig.at_ground.back(), clock) == DecodeStatus::ok);
  REQUIRE(clock.type == Type::hil_clock);
  CHECK(clock.hil_clock.step == 1);
  CHECK(clock.hil_clock.mocap_frames == 0);
  // The firmware answered; the ground station has not.
  CHECK(rig.exchange.awaiting_ground());
  CHECK_FALSE(rig.exchange.answered());
  // An answer to another step does not count; a resend repeats the clock.
  Frame done;
  REQUIRE(encode(HilClockDone{7}, kGroundNode, done));
  rig.exchange.on_ground_frame(done);
  CHECK_FALSE(rig.exchange.answered());
  rig.exchange.resend_unanswered();
  const std::vector<Frame> again = rig.exchange.take_ground_frames();
  REQUIRE(again.size() == 1);
  CHECK(again[0].data == rig.at_ground.back().data);
  REQUIRE(encode(HilClockDone{1}, kGroundNode, done));
  rig.exchange.on_ground_frame(done);
  CHECK(rig.exchange.answered());
  const hil::run::GroundClockCounters& c = rig.exchange.ground_clock_counters();
  CHECK(c.answered == 1);
  CHECK(c.other_answers == 1);
  CHECK(c.clocks_sent == 2);
  CHECK(rig.exchange.ground_frames_not_carried() == 0);  // the answers are the plant's, not a radio's
  CHECK(rig.exchange.counters(pa::kVehicle1).uplink_offered == 0);

  // The clock counts the motion-capture frames delivered: by 40 ms several.
  for (std::uint32_t k = 2; k <= 40; ++k) {
    rig.at_ground.clear();
    rig.lockstep();
    REQUIRE(decode(rig.at_ground.back(), clock) == DecodeStatus::ok);
    CHECK(clock.hil_clock.step == k);
    REQUIRE(encode(HilClockDone{k}, kGroundNode, done));
    rig.exchange.on_ground_frame(done);
  }
  CHECK(clock.hil_clock.mocap_frames >= 5);
  CHECK(rig.exchange.take_mocap().size() == clock.hil_clock.mocap_frames);

  // A ground station gone (killed) is let go: the plant steps on with the firmware alone and
  // sends its clock still; the first answer from a ground station back has it awaited again.
  rig.lockstep();
  CHECK_FALSE(rig.exchange.answered());
  rig.exchange.release_ground();
  CHECK(rig.exchange.answered());
  for (int k = 0; k < 10; ++k) rig.lockstep();
  REQUIRE(encode(HilClockDone{45}, kGroundNode, done));
  rig.exchange.on_ground_frame(done);  // a restarted ground station, behind
  CHECK_FALSE(rig.exchange.ground_released());
  CHECK_FALSE(rig.exchange.answered());
  CHECK(rig.exchange.ground_clock_counters().released == 1);
}

TEST_CASE("A firmware gone silent is let go: its motors stop and the plant steps on until it answers again") {
  Rig rig(radio_without_jitter());
  for (int k = 0; k < 5; ++k) rig.lockstep();
  CHECK(rig.exchange.vehicle_answered_once(pa::kVehicle2));
  // Vehicle 2's firmware dies: its samples go unanswered.
  rig.exchange.step();
  rig.write();
  Frame f;
  while (rig.vehicle_bus[0].receive(kOtherEnd, f))
    rig.firmware[0]->on_frame(f, [&](const Frame& out) { rig.vehicle_bus[0].send(kOtherEnd, out); });
  while (rig.vehicle_bus[0].receive(kPlantEnd, f)) rig.exchange.on_vehicle_frame(pa::kVehicle1, f);
  while (rig.vehicle_bus[1].receive(kOtherEnd, f)) {
  }
  CHECK(rig.exchange.awaiting_vehicle(pa::kVehicle2));
  CHECK_FALSE(rig.exchange.awaiting_vehicle(pa::kVehicle1));
  CHECK_FALSE(rig.exchange.answered());
  rig.exchange.release_vehicle(pa::kVehicle2);
  CHECK(rig.exchange.vehicle_released(pa::kVehicle2));
  CHECK(rig.exchange.answered());
  rig.exchange.step();
  for (double m : rig.exchange.motor_commands(pa::kVehicle2).command) CHECK(m == 0.0);
  CHECK(rig.exchange.counters(pa::kVehicle2).released == 1);
  CHECK(rig.exchange.counters(pa::kVehicle2).missed == 0);  // not waited for: not missed
  // It answers again (restarted): waited for from then on.
  rig.write();
  rig.pump();
  CHECK_FALSE(rig.exchange.vehicle_released(pa::kVehicle2));
  CHECK(rig.exchange.answered());
  rig.lockstep();
  CHECK(rig.exchange.counters(pa::kVehicle2).answered >= 6);
}

TEST_CASE(
    "The catcher's firmware killed before the throw: the ground station has it lost and calls the catch off") {
  using gs::mission::Task;
  Flight flight(1.0);
  Rig& rig = flight.rig();
  flight.run_until(0.5, [] { return false; });
  REQUIRE(flight.take_off());
  gs::runtime::AttemptRequest request;
  REQUIRE(flight.station().request_attempt(request));
  rig.exchange.hand_pole_to(pa::kVehicle1, flight.station().throw_frame(pa::kVehicle1).origin_m);
  // The pole on the thrower, balanced: then vehicle 2's firmware process dies.
  REQUIRE(
      flight.run_until(rig.exchange.t_s() + 15.0, [&] { return flight.one(pa::kVehicle1, Task::balance); }));
  REQUIRE(flight.station().attempt_phase() == gs::runtime::AttemptPhase::preparing);
  rig.dead[1] = true;
  rig.exchange.release_vehicle(pa::kVehicle2);  // as hil run does after 1 s without an answer
  const double killed_at = rig.exchange.t_s();
  REQUIRE(flight.run_until(killed_at + 2.0, [&] { return !flight.station().attempts().empty(); }));

  const gs::runtime::AttemptReport& report = flight.station().attempts().front();
  CHECK_FALSE(report.caught);
  CHECK(report.catcher_end == gs::mission::Reason::vehicle_lost);
  CHECK_FALSE(report.launch_s);
  CHECK(flight.station().link().status(pa::kVehicle2).lost);
  CHECK(flight.one(pa::kVehicle2, Task::failsafe));
  // Lost within the link's vehicle timeout (0.3 s) and a heartbeat period, and called off then.
  CHECK(rig.exchange.t_s() - killed_at < 0.3 + 0.03);
  // The thrower keeps the pole balanced; vehicle 2, its motors stopped, falls.
  flight.run_until(rig.exchange.t_s() + 2.0, [] { return false; });
  CHECK(flight.one(pa::kVehicle1, Task::balance));
  CHECK(rig.exchange.plant().vehicle_on_floor(pa::kVehicle2));
}

TEST_CASE(
    "After a landing the ground station takes the vehicles off again: DISARM clears landed before ARM") {
  using gs::mission::Task;
  Flight flight(1.0);
  Rig& rig = flight.rig();
  flight.run_until(0.5, [] { return false; });
  for (int flight_number = 1; flight_number <= 2; ++flight_number) {
    CAPTURE(flight_number);
    REQUIRE(flight.take_off());
    flight.station().request_land();
    REQUIRE(flight.run_until(rig.exchange.t_s() + 15.0, [&] { return flight.both(Task::parked); }));
    for (const pa::VehicleId v : pa::kActVehicles)
      CHECK(flight.station().link().status(v).mode == pa::proto::Mode::landed);
  }
}

TEST_CASE("The ground station killed in flight and started again: the vehicles land alone, and fly again") {
  using gs::mission::Task;
  Flight flight(1.0);
  Rig& rig = flight.rig();
  flight.run_until(0.5, [] { return false; });
  REQUIRE(flight.take_off());
  flight.kill_ground_station();
  const double killed_at = rig.exchange.t_s();
  // Levelled hover 20 ms after the last setpoint, 0.5 s of it, then the descent at 0.5 m/s from 1 m.
  flight.run_until(killed_at + 6.0, [] { return false; });
  for (const pa::VehicleId v : pa::kActVehicles) {
    CHECK(rig.exchange.plant().vehicle_on_floor(v));
    for (double m : rig.exchange.motor_commands(v).command) CHECK(m == 0.0);
  }
  flight.restart_ground_station(0x5A5A);
  REQUIRE(flight.run_until(rig.exchange.t_s() + 5.0, [&] {
    return flight.both(Task::parked) && !flight.station().link().status(pa::kVehicle1).lost &&
           !flight.station().link().status(pa::kVehicle2).lost;
  }));
  flight.run_until(rig.exchange.t_s() + 1.0, [] { return false; });
  REQUIRE(flight.take_off());
}

TEST_CASE(
    "Through the exchange, the firmware reads the plant's battery and keeps the thrust gain at full charge") {
  // Both packs drain from full over the hover: 60 mAh, the plant's battery law at 35 times the
  // speed of the 2.1 Ah pack, so 40 s of hover take them from 12.45 V to about 11.4 V under load.
  hil::PlantConfig plant{};
  plant.battery.enabled = 1;
  plant.battery.capacity_Ah = 0.06;
  struct Drift {
    double k_start = 0, k_end = 0, v_start = 0, v_end = 0;
    std::uint16_t firmware_mv = 0;
  };
  const auto hover = [&](bool compensate) {
    Flight flight(1.0, plant, compensate);
    Rig& rig = flight.rig();
    flight.run_until(0.5, [] { return false; });
    flight.station().request_take_off();
    REQUIRE(flight.run_until(15.0, [&] { return flight.both(gs::mission::Task::hover); }));
    // k settles on its first windows of hover.
    REQUIRE_FALSE(
        flight.run_until(rig.exchange.t_s() + 5.0, [&] { return !flight.both(gs::mission::Task::hover); }));
    Drift d;
    d.k_start = flight.station().thrust_gain(pa::kVehicle1).gain();
    d.v_start = rig.exchange.plant().battery(pa::kVehicle1).voltage_V;
    REQUIRE_FALSE(
        flight.run_until(rig.exchange.t_s() + 40.0, [&] { return !flight.both(gs::mission::Task::hover); }));
    d.k_end = flight.station().thrust_gain(pa::kVehicle1).gain();
    d.v_end = rig.exchange.plant().battery(pa::kVehicle1).voltage_V;
    d.firmware_mv = rig.firmware[0]->vehicle().battery().filtered_mv();
    return d;
  };
  const Drift on = hover(true);
  const Drift off = hover(false);
  for (const auto& [name, d] : {std::pair{"compensated", on}, std::pair{"uncompensated", off}})
    std::printf("hil run exchange, 40 s hover on a draining pack, %s: %.2f V -> %.2f V; k %.4f -> %.4f\n",
                name, d.v_start, d.v_end, d.k_start, d.k_end);
  CHECK(on.v_end < on.v_start - 0.6);
  // The HIL_BATTERY frames reach the fw_vehicle node through the exchange.
  CHECK(double(on.firmware_mv) == Approx(on.v_end * 1000.0).margin(30.0));
  CHECK(off.firmware_mv == 0);
  // With the compensation k stays at its full-charge value; without, it follows (V / V_ref)^2.
  CHECK(on.k_end == Approx(on.k_start).margin(0.02));
  CHECK(off.k_end / off.k_start == Approx(std::pow(off.v_end / off.v_start, 2.0)).epsilon(0.03));
}
