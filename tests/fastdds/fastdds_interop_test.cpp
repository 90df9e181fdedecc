// The ground station's motion capture fed by another DDS implementation: fastdds_peer (Fast DDS,
// ROS 2's default middleware, types from fastddsgen) publishes NamedPoseArray on rt/poses as
// motion_capture_tracking does, in both of its QoS modes; the ground station's Cyclone reader
// receives it over UDP on 127.0.0.1 (gs::dds::loopback_config()) and converts it. Checked: the
// type and topic match across implementations (nothing arrives otherwise), every field arrives
// bit for bit (names, positions, ROS's (x, y, z, w) quaternions, the stamp), names map to
// vehicles as configured, and an arena's junk (unknown and overlong names, a NaN orientation)
// is counted and skipped. Then the ground station's process core takes the same frames. And
// back: a Fast DDS subscriber, as rviz2 would be, receives the ground station's ROS 2 poses
// (geometry_msgs/PoseStamped on rt/pa/vehicle2/pose and rt/pa/pole/pose), which it matches only
// if the topic names, type name and QoS agree across the implementations.
//
// Domains 140-149, with the loopback configuration, so another run on this host could share
// them: this run's frames are told apart by body names made of its process id. Every wait is
// bounded, and the peer is killed if it outlives its wait.
#include <time.h>

#include <array>
#include <catch2/catch.hpp>
#include <chrono>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "../dds/peer_process.hpp"
#include "fastdds_poses.hpp"
#include "groundstation/dds/dds.hpp"
#include "groundstation/dds/mocap_conversion.hpp"
#include "groundstation/service/process.hpp"

using namespace std::chrono_literals;

namespace {

// Discovery across implementations takes a few SPDP rounds; a generous bound that a passing run
// never approaches (it takes well under a second).
constexpr auto kDiscovery = 20s;

gs::dds::MocapBodyNames run_names() {
  const std::string tag = std::to_string(getpid());
  return {"cf1_" + tag, "cf2_" + tag, "stick_" + tag};
}

std::string names_argument(const gs::dds::MocapBodyNames& n) {
  return n.vehicle1 + "," + n.vehicle2 + "," + n.pole;
}

std::int64_t realtime_ns() {
  timespec t{};
  clock_gettime(CLOCK_REALTIME, &t);
  return static_cast<std::int64_t>(t.tv_sec) * 1'000'000'000 + t.tv_nsec;
}

double monotonic_s() {
  timespec t{};
  clock_gettime(CLOCK_MONOTONIC, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

void check_pose(const gs::dds::NamedPose& got, const fastdds_test::Pose& want) {
  CHECK(got.pose.position.x == want.position[0]);
  CHECK(got.pose.position.y == want.position[1]);
  CHECK(got.pose.position.z == want.position[2]);
  CHECK(got.pose.orientation.x == want.orientation_xyzw[0]);
  CHECK(got.pose.orientation.y == want.orientation_xyzw[1]);
  CHECK(got.pose.orientation.z == want.orientation_xyzw[2]);
  CHECK(got.pose.orientation.w == want.orientation_xyzw[3]);
}

void check_estimate(const gs::estimation::MocapPose& got, const fastdds_test::Pose& want) {
  CHECK(got.p_m.x() == want.position[0]);
  CHECK(got.p_m.y() == want.position[1]);
  CHECK(got.p_m.z() == want.position[2]);
  // Eigen's quaternion is (w, x, y, z): the conversion must not mix ROS's order up.
  const Eigen::Quaterniond q(want.orientation_xyzw[3], want.orientation_xyzw[0], want.orientation_xyzw[1],
                             want.orientation_xyzw[2]);
  CHECK(got.q.isApprox(q, 1e-14));
}

// Receives frames from a Fast DDS peer started with `qos` and checks the first of this run's.
void receive_from_fast_dds(dds_domainid_t domain, const char* qos) {
  const gs::dds::MocapBodyNames names = run_names();
  gs::dds::Domain dds_domain(domain, gs::dds::loopback_config());
  gs::dds::Participant participant(dds_domain);
  gs::dds::Reader<gs::dds::NamedPoseArray> reader(participant);

  const pid_t peer = dds_test::start_peer({"publish-poses", "--domain", std::to_string(domain), "--qos", qos,
                                           "--names", names_argument(names), "--junk", "--seconds", "20"});
  REQUIRE(peer > 0);
  const std::int64_t started_ns = realtime_ns();

  bool heard = false;
  const auto end = std::chrono::steady_clock::now() + kDiscovery;
  while (!heard && std::chrono::steady_clock::now() < end) {
    const gs::dds::NamedPoseArray* m = reader.wait_take(100ms);
    if (m == nullptr || m->poses._length != 6 || names.vehicle1 != m->poses._buffer[0].name) continue;
    heard = true;
    const long k = fastdds_test::frame_of(m->poses._buffer[0].pose.position.x);
    INFO("frame " << k);
    CHECK(std::string(m->header.frame_id) == "world");
    const std::int64_t stamp_ns = gs::dds::stamp_nanoseconds(m->header.stamp);
    CHECK(stamp_ns >= started_ns);
    CHECK(stamp_ns <= realtime_ns());
    CHECK(m->header.stamp.nanosec < 1'000'000'000u);
    CHECK(std::string(m->poses._buffer[1].name) == names.vehicle2);
    CHECK(std::string(m->poses._buffer[2].name) == names.pole);
    CHECK(std::string(m->poses._buffer[3].name) == fastdds_test::kUnknownBody);
    CHECK(std::string(m->poses._buffer[4].name) == std::string(200, 'n'));
    for (int body = 0; body < 3; ++body) check_pose(m->poses._buffer[body], fastdds_test::pose(body, k));

    // Names mapped to vehicles as configured; the junk counted and skipped.
    const gs::dds::MocapFrameIn in = gs::dds::mocap_frame_from_dds(*m, names);
    CHECK(in.stamp_ns == stamp_ns);
    CHECK(in.unknown_bodies == 3);
    CHECK(in.first_unknown == fastdds_test::kUnknownBody);
    REQUIRE(in.frame.vehicle[0]);
    REQUIRE(in.frame.vehicle[1]);
    REQUIRE(in.frame.pole);
    check_estimate(*in.frame.vehicle[pa::act_slot(pa::kVehicle1)], fastdds_test::pose(0, k));
    check_estimate(*in.frame.vehicle[pa::act_slot(pa::kVehicle2)], fastdds_test::pose(1, k));
    check_estimate(*in.frame.pole, fastdds_test::pose(2, k));

    // The position-only body's NaN orientation arrives as NaN, and is refused as a pose.
    const gs::dds::MocapBodyNames marker_as_vehicle2{names.vehicle1, fastdds_test::kPositionOnlyBody,
                                                     names.pole};
    const gs::dds::MocapFrameIn marker = gs::dds::mocap_frame_from_dds(*m, marker_as_vehicle2);
    CHECK(marker.invalid_poses == 1);
    CHECK_FALSE(marker.frame.vehicle[1]);
  }
  CHECK(heard);

  // What discovery says of the Fast DDS writer, not this project's strings: ROS 2's topic and
  // type names, and motion_capture_tracking's QoS in the mode asked for.
  std::array<dds_instance_handle_t, 4> writers{};
  const dds_return_t n = dds_get_matched_publications(reader.handle(), writers.data(), writers.size());
  REQUIRE(n == 1);
  dds_builtintopic_endpoint_t* writer = dds_get_matched_publication_data(reader.handle(), writers[0]);
  REQUIRE(writer != nullptr);
  CHECK(std::string(writer->topic_name) == "rt/poses");
  CHECK(std::string(writer->type_name) == "motion_capture_tracking_interfaces::msg::dds_::NamedPoseArray_");
  dds_reliability_kind_t reliability{};
  dds_duration_t blocking = 0;
  REQUIRE(dds_qget_reliability(writer->qos, &reliability, &blocking));
  const bool sensor = std::string(qos) == "sensor";
  CHECK(reliability == (sensor ? DDS_RELIABILITY_BEST_EFFORT : DDS_RELIABILITY_RELIABLE));
  dds_duration_t deadline = 0;
  if (dds_qget_deadline(writer->qos, &deadline)) CHECK(deadline == (sensor ? DDS_MSECS(10) : DDS_INFINITY));
  dds_builtintopic_free_endpoint(writer);

  // The peer ends on its own once its 20 s are up; it has done its part, so it is ended now.
  kill(peer, SIGTERM);
  dds_test::wait_exit(peer, 5s);
}

}  // namespace

TEST_CASE("Cyclone receives Fast DDS's NamedPoseArray on rt/poses, sensor QoS", "[fastdds]") {
  receive_from_fast_dds(140, "sensor");
}

TEST_CASE("Cyclone receives Fast DDS's NamedPoseArray on rt/poses, reliable QoS", "[fastdds]") {
  receive_from_fast_dds(141, "reliable");
}

TEST_CASE("The ground station's process flies on Fast DDS's poses", "[fastdds]") {
  gs::service::ProcessConfig config;
  config.mocap.names = run_names();
  gs::runtime::GroundStationConfig station;
  for (const pa::VehicleId v : pa::kActVehicles) {
    gs::link::VehicleKey key{v, {}};
    key.key.fill(static_cast<std::uint8_t>(0x30 + v.node()));  // any key: no vehicle is on the bus
    station.link.keys.push_back(key);
  }
  gs::link::InMemoryFrameBus bus;
  gs::dds::Domain domain(142, gs::dds::loopback_config());
  gs::dds::Participant participant(domain);
  gs::service::Process process(bus, participant, station, config);

  const pid_t peer = dds_test::start_peer({"publish-poses", "--domain", "142", "--qos", "sensor", "--names",
                                           names_argument(config.mocap.names), "--junk", "--frames", "40",
                                           "--seconds", "20"});
  REQUIRE(peer > 0);
  // The loop of groundstation run: a step every 1 ms on CLOCK_MONOTONIC, the stamps the system
  // clock's.
  const auto end = std::chrono::steady_clock::now() + kDiscovery;
  while (process.counters().mocap_frames < 20 && std::chrono::steady_clock::now() < end) {
    process.set_stamp_offset(realtime_ns() - gs::dds::to_nanoseconds(monotonic_s()));
    process.step(monotonic_s());
    std::this_thread::sleep_for(1ms);
  }
  const gs::service::ProcessCounters& c = process.counters();
  CHECK(c.mocap_frames >= 20);
  // Each frame's junk: the unknown and overlong names and the position-only body.
  CHECK(c.mocap_unknown_bodies == 3 * c.mocap_frames);
  CHECK(c.mocap_invalid_poses == 0);
  // One host, one clock: every stamp is explained, and arrives within a few milliseconds.
  CHECK(c.mocap_implausible_stamps == 0);
  CHECK(c.mocap_delay_max_s < 0.5);
  const gs::estimation::StateEstimator& estimator = process.ground_station().estimator();
  REQUIRE(estimator.vehicle_initialised(pa::kVehicle1));
  REQUIRE(estimator.vehicle_initialised(pa::kVehicle2));
  // Vehicle 2 hovers still at (-1, 2 + k/1000, 1): the estimate is within a few centimetres.
  CHECK(estimator.vehicle(pa::kVehicle2).state.p_m.x() == Approx(-1.0).margin(0.05));
  CHECK(estimator.vehicle(pa::kVehicle2).state.p_m.z() == Approx(1.0).margin(0.05));
  CHECK(estimator.vehicle(pa::kVehicle1).state.p_m.y() == Approx(-2.0).margin(0.05));
  std::printf("%s", process.summary().c_str());
  CHECK(dds_test::wait_exit(peer, 20s) == 0);
}

namespace {

// A line of fastdds_peer subscribe-pose's file.
struct ReceivedPose {
  std::string frame_id;
  std::int64_t stamp_ns = 0;
  Eigen::Vector3d p_m = Eigen::Vector3d::Zero();
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
};

std::vector<ReceivedPose> read_poses(const std::string& path) {
  std::vector<ReceivedPose> poses;
  std::ifstream in(path);
  for (std::string line; std::getline(in, line);) {
    std::istringstream fields(line);
    ReceivedPose r;
    long long sec = 0;
    unsigned long nanosec = 0;
    double qx = 0, qy = 0, qz = 0, qw = 0;
    if (!(fields >> r.frame_id >> sec >> nanosec >> r.p_m.x() >> r.p_m.y() >> r.p_m.z() >> qx >> qy >> qz >>
          qw))
      continue;
    r.stamp_ns = sec * 1'000'000'000 + static_cast<long long>(nanosec);
    r.q = Eigen::Quaterniond(qw, qx, qy, qz);
    poses.push_back(r);
  }
  return poses;
}

gs::estimation::MocapPose mocap_pose(const Eigen::Vector3d& p, const Eigen::Quaterniond& q) {
  gs::estimation::MocapPose pose;
  pose.p_m = p;
  pose.q = q;
  return pose;
}

}  // namespace

TEST_CASE("Fast DDS receives the ground station's poses as ROS 2 PoseStamped", "[fastdds]") {
  gs::runtime::GroundStationConfig station;
  for (const pa::VehicleId v : pa::kActVehicles) {
    gs::link::VehicleKey key{v, {}};
    key.key.fill(static_cast<std::uint8_t>(0x30 + v.node()));
    station.link.keys.push_back(key);
  }
  gs::link::InMemoryFrameBus bus;
  gs::dds::Domain domain(145, gs::dds::loopback_config());
  gs::dds::Participant station_side(domain);
  gs::dds::Participant cameras_side(domain);
  gs::service::Process process(bus, station_side, station);
  gs::dds::Writer<gs::dds::NamedPoseArray> cameras(cameras_side);

  const std::string tag = std::to_string(getpid());
  const std::string vehicle_file = "fastdds_vehicle2_pose_" + tag + ".txt";
  const std::string pole_file = "fastdds_pole_pose_" + tag + ".txt";
  // Vehicle 2's as rviz2 subscribes (reliable), the pole's as a sensor-data subscriber.
  const pid_t vehicle_peer = dds_test::start_peer(
      {"subscribe-pose", "--domain", "145", "--topic", gs::dds::vehicle_pose_topic(pa::kVehicle2), "--qos",
       "reliable", "--out", vehicle_file, "--frames", "10", "--seconds", "20"});
  const pid_t pole_peer =
      dds_test::start_peer({"subscribe-pose", "--domain", "145", "--topic", gs::dds::kPolePoseTopic, "--qos",
                            "sensor", "--out", pole_file, "--frames", "10", "--seconds", "20"});
  REQUIRE(vehicle_peer > 0);
  REQUIRE(pole_peer > 0);
  REQUIRE(cameras.wait_for_readers(1, 5s));

  // Vehicle 2 parked at (1, 2, 0.1) facing 0.5 rad; the pole upright-ish at (0, 0, 1).
  const Eigen::Vector3d vehicle_p(1.0, 2.0, 0.1);
  const Eigen::Quaterniond vehicle_q(Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitZ()));
  const Eigen::Vector3d pole_p(0.0, 0.0, 1.0);
  const Eigen::Quaterniond pole_q(Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitX()));
  const std::int64_t started_ns = realtime_ns();
  gs::dds::MocapMessage message;
  int exits = 0, vehicle_exit = -1, pole_exit = -1;
  const auto end = std::chrono::steady_clock::now() + kDiscovery;
  while (exits < 2 && std::chrono::steady_clock::now() < end) {
    const std::int64_t offset_ns = realtime_ns() - gs::dds::to_nanoseconds(monotonic_s());
    process.set_stamp_offset(offset_ns);
    gs::estimation::MocapFrame frame;
    frame.vehicle[pa::act_slot(pa::kVehicle2)] = mocap_pose(vehicle_p, vehicle_q);
    frame.pole = mocap_pose(pole_p, pole_q);
    gs::dds::mocap_frame_to_dds(frame, realtime_ns(), gs::dds::MocapBodyNames{}, message);
    cameras.write(message.message());
    std::this_thread::sleep_for(5ms);
    process.step(monotonic_s());
    int status = 0;
    if (vehicle_exit < 0 && waitpid(vehicle_peer, &status, WNOHANG) == vehicle_peer) {
      vehicle_exit = WIFEXITED(status) ? WEXITSTATUS(status) : 100;
      ++exits;
    }
    if (pole_exit < 0 && waitpid(pole_peer, &status, WNOHANG) == pole_peer) {
      pole_exit = WIFEXITED(status) ? WEXITSTATUS(status) : 100;
      ++exits;
    }
  }
  if (vehicle_exit < 0) vehicle_exit = dds_test::wait_exit(vehicle_peer, 1s);
  if (pole_exit < 0) pole_exit = dds_test::wait_exit(pole_peer, 1s);
  CHECK(vehicle_exit == 0);
  CHECK(pole_exit == 0);
  CHECK(process.counters().ros_poses_published > 0);

  const std::vector<ReceivedPose> vehicle = read_poses(vehicle_file);
  const std::vector<ReceivedPose> pole = read_poses(pole_file);
  std::remove(vehicle_file.c_str());
  std::remove(pole_file.c_str());
  REQUIRE(vehicle.size() == 10);
  REQUIRE(pole.size() == 10);
  for (const ReceivedPose& r : vehicle) {
    CHECK(r.frame_id == "world");
    CHECK(r.stamp_ns >= started_ns);
    CHECK(r.stamp_ns <= realtime_ns());
    CHECK((r.p_m - vehicle_p).norm() < 0.05);
    CHECK(r.q.norm() == Approx(1.0).margin(1e-9));
    CHECK(r.q.angularDistance(vehicle_q) < 0.05);
  }
  for (const ReceivedPose& r : pole) {
    CHECK(r.frame_id == "world");
    // A pole held still in the air is, to the estimator, a pole in free flight that the frames
    // keep catching up with: on a loaded machine the steps' gaps let it fall a little between them.
    CHECK((r.p_m - pole_p).norm() < 0.5);
    // The pose's z-axis is the pole's axis.
    CHECK((r.q * Eigen::Vector3d::UnitZ() - pole_q * Eigen::Vector3d::UnitZ()).norm() < 0.05);
  }
  // Stamped in order, at the telemetry's 50 Hz.
  for (std::size_t i = 1; i < vehicle.size(); ++i) CHECK(vehicle[i].stamp_ns > vehicle[i - 1].stamp_ns);
}
