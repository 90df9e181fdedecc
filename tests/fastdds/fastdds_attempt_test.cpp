// An attempt flown on motion capture that Fast DDS publishes: the ground station's process core
// (groundstation/service/process.hpp) flies the lockstep arena (hil/sil/arena.hpp: the truth
// plant, both firmware cores, the radios) from take-off through a throw to the catch, and every
// pose it flies on came to it from a Fast DDS participant on rt/poses.
//
//   arena's motion capture ──Cyclone, rt/poses, domain 143──▶ fastdds_peer relay-poses
//     ──Fast DDS, rt/poses, sensor QoS, domain 144──▶ the Process's Cyclone reader
//
// So a frame crosses between the two implementations twice (Fast DDS reads what Cyclone wrote,
// Cyclone reads what Fast DDS wrote), over UDP on 127.0.0.1. In lockstep as `groundstation run
// --hil-clock` runs: every 1 ms step the arena's ground frames go to on_frame, the frames its
// motion capture delivered are stamped with their delivery (as motion_capture_tracking stamps
// arrival at its node) and published, the Process waits for them to come back through Fast DDS
// (await_mocap, at most 2 s each), then steps. The take-off and the throw are operator commands
// on pa_operator_commands; the person with the pole reads pa_events, as `hil run` does.
//
// Labelled `interop` (not unit: some seconds of wall clock; not in the sanitizer preset). Every
// wait is bounded and the relay is killed if it outlives the test.
#include <catch2/catch.hpp>
#include <chrono>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "../dds/peer_process.hpp"
#include "groundstation/dds/dds.hpp"
#include "groundstation/dds/event_detail.hpp"
#include "groundstation/dds/mocap_conversion.hpp"
#include "groundstation/service/process.hpp"
#include "hil/sil/arena.hpp"
#include "hil/sil/firmware_vehicle.hpp"
#include "hil/sil/ground_station_frame.hpp"

using namespace std::chrono_literals;
using gs::mission::Task;

namespace {

constexpr dds_domainid_t kCameras = 143;
constexpr dds_domainid_t kArena = 144;
constexpr double kGiveUp_s = 90.0;  // of simulated time: take-off, hover, throw and catch take ~30

// The Process's ground bus: what it sends goes to the arena's radios after the step.
class ArenaBus final : public gs::link::FrameBus {
 public:
  bool send(const pa::proto::Frame& frame) override {
    frames_.push_back(frame);
    return true;
  }
  void carry_to(hil::sil::Arena& arena) {
    for (const pa::proto::Frame& f : frames_) arena.send_from_ground(f);
    frames_.clear();
  }

 private:
  std::vector<pa::proto::Frame> frames_;
};

gs::runtime::GroundStationConfig simulation_keys() {
  gs::runtime::GroundStationConfig c;
  for (const pa::VehicleId v : pa::kActVehicles) c.link.keys.push_back({v, hil::sil::simulation_key(v)});
  return c;
}

// Ends the relay however the test ends.
struct RelayProcess {
  explicit RelayProcess(pid_t pid) : pid(pid) {}
  ~RelayProcess() {
    if (pid <= 0) return;
    kill(pid, SIGTERM);
    dds_test::wait_exit(pid, 10s);
  }
  pid_t pid;
};

}  // namespace

TEST_CASE("The ground station flies an attempt on poses Fast DDS publishes", "[fastdds]") {
  gs::dds::Domain cameras_domain(kCameras, gs::dds::loopback_config());
  gs::dds::Participant cameras_side(cameras_domain);
  gs::dds::Writer<gs::dds::NamedPoseArray> cameras(cameras_side);
  gs::dds::Domain arena_domain(kArena, gs::dds::loopback_config());
  gs::dds::Participant station_side(arena_domain);
  gs::dds::Participant console(arena_domain);

  hil::sil::Arena arena(hil::PlantConfig{}, hil::sil::ArenaConfig{}, 1);
  ArenaBus bus;
  gs::service::Process process(bus, station_side, simulation_keys());
  gs::dds::Writer<pa_arena_OperatorCommand> commands(console);
  gs::dds::Reader<pa_arena_Event> events(console);

  const RelayProcess relay(
      dds_test::start_peer({"relay-poses", "--from-domain", std::to_string(kCameras), "--domain",
                            std::to_string(kArena), "--qos", "sensor", "--seconds", "300"}));
  REQUIRE(relay.pid > 0);
  REQUIRE(cameras.wait_for_readers(1, 20s));
  REQUIRE(commands.wait_for_readers(1, 20s));

  // Until the relay's writer has matched the Process's reader, frames fall on the floor: an
  // empty frame (no bodies: nothing for the estimator) until one comes through. Counted as the
  // plant counts its frames: await_mocap takes the count it is given after a frame that did not
  // come, so that the count stays the number published.
  gs::dds::MocapMessage message;
  std::uint64_t published = 0;
  const auto matched_by = std::chrono::steady_clock::now() + 20s;
  while (process.counters().mocap_frames == 0 && std::chrono::steady_clock::now() < matched_by) {
    message.clear(0);
    cameras.write(message.message());
    process.await_mocap(++published, 0.0, 50ms);
  }
  REQUIRE(process.counters().mocap_frames >= 1);

  const auto command = [&](pa_arena_CommandKind kind, std::uint8_t target, std::uint32_t sequence) {
    pa_arena_OperatorCommand c{};
    c.kind = kind;
    c.target = target;
    c.sequence_number = sequence;
    commands.write(c);
  };
  command(pa_arena_command_take_off, 0, 1);

  std::uint64_t late = 0;
  bool throw_sent = false;
  std::optional<bool> caught;
  std::string outcome;
  const auto wall_start = std::chrono::steady_clock::now();
  while (!caught && arena.t_s() < kGiveUp_s) {
    arena.step();
    const double now = arena.t_s();
    for (const pa::proto::Frame& f : arena.take_ground_frames()) process.on_frame(f, now);
    for (const hil::CapturedFrame& m : arena.take_mocap()) {
      gs::dds::mocap_frame_to_dds(hil::sil::to_ground_station_frame(m),
                                  gs::dds::to_nanoseconds(m.delivery_t_s), gs::dds::MocapBodyNames{},
                                  message);
      cameras.write(message.message());
      ++published;
    }
    if (!process.await_mocap(published, now, 2s)) ++late;
    process.step(now);
    bus.carry_to(arena);

    // The person with the pole and the operator read the events.
    while (const pa_arena_Event* e = events.take()) {
      const auto kind = gs::dds::raw_enum(e->kind);
      const pa::VehicleId vehicle(e->vehicle);
      if (kind == pa_arena_event_pole_wanted && pa::is_act_vehicle(vehicle)) {
        if (const std::optional<bool> waiting = gs::dds::pole_wanted(e->detail))
          arena.show_waiting_for_pole(vehicle, *waiting);
      } else if (kind == pa_arena_event_attempt && pa::is_act_vehicle(vehicle)) {
        if (const auto origin = gs::dds::attempt_event_origin(e->detail))
          arena.hand_pole_to(vehicle, *origin);
      } else if (kind == pa_arena_event_catch_success || kind == pa_arena_event_catch_miss) {
        caught = kind == pa_arena_event_catch_success;
        outcome = e->detail;
      } else if (kind == pa_arena_event_command_refused) {
        FAIL("a command was refused: " << e->detail);
      }
    }
    const gs::runtime::GroundStation& station = process.ground_station();
    if (!throw_sent && station.task(pa::kVehicle1) == Task::hover &&
        station.task(pa::kVehicle2) == Task::hover) {
      command(pa_arena_command_throw, pa::kVehicle1.node(), 2);
      throw_sent = true;
    }
  }
  const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  std::printf("%.1f s of simulated time in %.1f s: %s\n%s", arena.t_s(), wall_s, outcome.c_str(),
              process.summary().c_str());
  CHECK(throw_sent);
  REQUIRE(caught.has_value());
  CHECK(*caught);
  CHECK(late == 0);
  const gs::service::ProcessCounters& c = process.counters();
  CHECK(c.mocap_unknown_bodies == 0);
  CHECK(c.mocap_invalid_poses == 0);
  CHECK(c.mocap_implausible_stamps == 0);
}
