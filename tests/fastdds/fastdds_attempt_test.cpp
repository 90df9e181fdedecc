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
// (pa_msgs/OperatorCommand on rt/pa/operator_commands); the person with the pole reads the
// events (pa_msgs/Event on rt/pa/events), as `hil run` does.
//
// And the events go to ROS 2 too: fastdds_peer subscribe-events, a Fast DDS subscriber of
// rt/pa/events with the topic's QoS as a ROS 2 node creates it, writes down every event until the
// catch. Checked: discovery says the reader is ROS 2's (topic rt/pa/events, type
// pa_msgs::msg::dds_::Event_, transient local), it received the attempt and the catch, and the
// catch's detail, stamp and vehicle are what the Cyclone side read.
//
// Labelled `interop` (not unit: some seconds of wall clock; not in the sanitizer preset). Every
// wait is bounded and the peers are killed if they outlive the test.
#include <unistd.h>

#include <array>
#include <catch2/catch.hpp>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <utility>
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

// Ends a fastdds_peer however the test ends.
struct PeerProcess {
  explicit PeerProcess(pid_t pid) : pid(pid) {}
  PeerProcess(const PeerProcess&) = delete;
  PeerProcess& operator=(const PeerProcess&) = delete;
  ~PeerProcess() {
    if (pid <= 0) return;
    kill(pid, SIGTERM);
    dds_test::wait_exit(pid, 10s);
  }
  // Waits up to `timeout` for the peer to end on its own: its exit code, -1 when it had to be
  // killed.
  int wait_exit(std::chrono::seconds timeout) {
    const int code = dds_test::wait_exit(pid, timeout);
    pid = -1;
    return code;
  }
  pid_t pid;
};

// A file the test has a peer write, removed however the test ends.
struct TemporaryFile {
  explicit TemporaryFile(std::string path) : path(std::move(path)) {}
  TemporaryFile(const TemporaryFile&) = delete;
  TemporaryFile& operator=(const TemporaryFile&) = delete;
  ~TemporaryFile() { std::remove(path.c_str()); }
  std::string path;
};

// A line of fastdds_peer subscribe-events' file.
struct ReceivedEvent {
  std::int32_t sec = 0;
  std::uint32_t nanosec = 0;
  unsigned kind = 0;
  unsigned vehicle = 0;
  std::string detail;
};

std::vector<ReceivedEvent> read_events(const std::string& path) {
  std::vector<ReceivedEvent> events;
  std::ifstream in(path);
  for (std::string line; std::getline(in, line);) {
    std::istringstream fields(line);
    ReceivedEvent e;
    if (!(fields >> e.sec >> e.nanosec >> e.kind >> e.vehicle)) continue;
    std::getline(fields, e.detail);
    if (!e.detail.empty() && e.detail.front() == ' ') e.detail.erase(0, 1);  // the separator
    events.push_back(e);
  }
  return events;
}

bool same_guid(const dds_guid_t& a, const dds_guid_t& b) { return std::memcmp(a.v, b.v, sizeof a.v) == 0; }

// What discovery says of a matched endpoint, freed with it.
using Endpoint = std::unique_ptr<dds_builtintopic_endpoint_t, decltype(&dds_builtintopic_free_endpoint)>;

// The readers `writer` has matched that belong to none of `ours` (this process's participants):
// other processes' readers.
std::vector<Endpoint> foreign_readers(dds_entity_t writer, const std::vector<dds_guid_t>& ours) {
  std::array<dds_instance_handle_t, 16> handles{};
  const dds_return_t n = dds_get_matched_subscriptions(writer, handles.data(), handles.size());
  std::vector<Endpoint> readers;
  for (dds_return_t i = 0; i < n && i < static_cast<dds_return_t>(handles.size()); ++i) {
    Endpoint r(dds_get_matched_subscription_data(writer, handles[static_cast<std::size_t>(i)]),
               &dds_builtintopic_free_endpoint);
    if (r == nullptr) continue;
    bool own = false;
    for (const dds_guid_t& g : ours) own = own || same_guid(r->participant_key, g);
    if (!own) readers.push_back(std::move(r));
  }
  return readers;
}

dds_guid_t guid_of(dds_entity_t entity) {
  dds_guid_t guid{};
  REQUIRE(dds_get_guid(entity, &guid) == DDS_RETCODE_OK);
  return guid;
}

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
  gs::dds::Writer<gs::dds::OperatorCommand> commands(console);
  gs::dds::Reader<gs::dds::Event> events(console);

  const PeerProcess relay(
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

  // The ROS 2 subscriber of the events, until the catch.
  const TemporaryFile events_file("fastdds_events_" + std::to_string(getpid()) + ".txt");
  PeerProcess subscriber(dds_test::start_peer(
      {"subscribe-events", "--domain", std::to_string(kArena), "--out", events_file.path, "--until",
       std::to_string(gs::dds::event_kind::kCatchSuccess), "--seconds", "300"}));
  REQUIRE(subscriber.pid > 0);
  {
    // What discovery says of the Fast DDS reader, not this project's strings: a writer of the
    // events in the console (it writes nothing) matches it, beside this process's own reader (the
    // console's), told apart by its participant. No other process in this domain reads the events
    // (the relay's participant here only writes poses): the one foreign reader is the peer's.
    const gs::dds::Writer<gs::dds::Event> probe(console);
    const std::vector<dds_guid_t> ours{guid_of(station_side.get()), guid_of(console.get())};
    std::vector<Endpoint> readers;
    const auto end = std::chrono::steady_clock::now() + 20s;
    while ((readers = foreign_readers(probe.handle(), ours)).empty() &&
           std::chrono::steady_clock::now() < end)
      std::this_thread::sleep_for(10ms);
    REQUIRE(readers.size() == 1);
    const dds_builtintopic_endpoint_t* reader = readers[0].get();
    CHECK(std::string(reader->topic_name) == "rt/pa/events");
    CHECK(std::string(reader->type_name) == "pa_msgs::msg::dds_::Event_");
    dds_durability_kind_t durability{};
    REQUIRE(dds_qget_durability(reader->qos, &durability));
    CHECK(durability == DDS_DURABILITY_TRANSIENT_LOCAL);
    dds_reliability_kind_t reliability{};
    dds_duration_t blocking = 0;
    REQUIRE(dds_qget_reliability(reader->qos, &reliability, &blocking));
    CHECK(reliability == DDS_RELIABILITY_RELIABLE);
  }

  const auto command = [&](std::uint8_t kind, std::uint8_t target, std::uint32_t sequence) {
    gs::dds::OperatorCommand c{};
    c.kind = kind;
    c.target = target;
    c.sequence_number = sequence;
    commands.write(c);
  };
  command(gs::dds::command_kind::kTakeOff, 0, 1);

  std::uint64_t late = 0;
  bool throw_sent = false;
  std::optional<bool> caught;
  std::string outcome;
  gs::dds::Event catch_event{};  // as the Cyclone side read it
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
    while (const gs::dds::Event* e = events.take()) {
      const std::uint8_t kind = e->kind;
      const pa::VehicleId vehicle(e->vehicle);
      if (kind == gs::dds::event_kind::kPoleWanted && pa::is_act_vehicle(vehicle)) {
        if (const std::optional<bool> waiting = gs::dds::pole_wanted(e->detail))
          arena.show_waiting_for_pole(vehicle, *waiting);
      } else if (kind == gs::dds::event_kind::kAttempt && pa::is_act_vehicle(vehicle)) {
        if (const auto origin = gs::dds::attempt_event_origin(e->detail))
          arena.hand_pole_to(vehicle, *origin);
      } else if (kind == gs::dds::event_kind::kCatchSuccess || kind == gs::dds::event_kind::kCatchMiss) {
        caught = kind == gs::dds::event_kind::kCatchSuccess;
        outcome = e->detail;
        catch_event = *e;
      } else if (kind == gs::dds::event_kind::kCommandRefused) {
        FAIL("a command was refused: " << e->detail);
      }
    }
    const gs::runtime::GroundStation& station = process.ground_station();
    if (!throw_sent && station.task(pa::kVehicle1) == Task::hover &&
        station.task(pa::kVehicle2) == Task::hover) {
      command(gs::dds::command_kind::kThrow, pa::kVehicle1.node(), 2);
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

  // The ROS 2 subscriber ends on the catch it was waiting for (a miss does not end it: it is
  // killed after its wait).
  const int subscriber_exit = subscriber.wait_exit(*caught ? 20s : 2s);
  const std::vector<ReceivedEvent> received = read_events(events_file.path);
  CHECK(subscriber_exit == 0);
  std::printf("fastdds_peer subscribe-events received %zu events\n", received.size());
  bool attempt = false;
  std::optional<ReceivedEvent> received_catch;
  for (const ReceivedEvent& e : received) {
    attempt = attempt || e.kind == unsigned{gs::dds::event_kind::kAttempt};
    if (e.kind == unsigned{catch_event.kind}) received_catch = e;
  }
  CHECK(attempt);
  REQUIRE(received_catch.has_value());
  CHECK(received_catch->detail == outcome);
  CHECK(received_catch->sec == catch_event.stamp.sec);
  CHECK(received_catch->nanosec == catch_event.stamp.nanosec);
  CHECK(received_catch->vehicle == unsigned{catch_event.vehicle});
}
