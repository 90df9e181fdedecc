// `groundstation op` and `watch` as an operator runs them, against a ground station's process core stepped by
// this test on the host's loopback DDS (domains 127 and 128, used by no other test): the answer
// is printed and gives the exit code; watch prints what the core publishes. A concurrent run on the host may share the domain; op's
// random sequence number keeps its answer apart, so nothing here counts the process's commands.
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <chrono>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "groundstation/service/process.hpp"

extern char** environ;

using namespace std::chrono_literals;

namespace {

struct Outcome {
  int exit_code = -1;  // -1: killed after the time limit
  std::string output;  // stdout and stderr
};

// Runs `groundstation <args>` while `step` is called, until it exits (at most 10 s).
template <class Step>
Outcome run_groundstation(const std::vector<std::string>& args, Step step) {
  const std::string output_path = "op_command_test_" + std::to_string(getpid()) + ".txt";
  std::vector<std::string> words{PA_GROUNDSTATION};
  words.insert(words.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& w : words) argv.push_back(w.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t files;
  posix_spawn_file_actions_init(&files);
  posix_spawn_file_actions_addopen(&files, STDOUT_FILENO, output_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC,
                                   0644);
  posix_spawn_file_actions_adddup2(&files, STDOUT_FILENO, STDERR_FILENO);
  pid_t child = -1;
  const int spawned = posix_spawn(&child, PA_GROUNDSTATION, &files, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&files);
  REQUIRE(spawned == 0);

  Outcome outcome;
  int status = 0;
  const auto end = std::chrono::steady_clock::now() + 10s;
  while (waitpid(child, &status, WNOHANG) == 0) {
    if (std::chrono::steady_clock::now() > end) {
      kill(child, SIGKILL);
      waitpid(child, &status, 0);
      break;
    }
    step();
    usleep(2000);
  }
  if (WIFEXITED(status)) outcome.exit_code = WEXITSTATUS(status);
  std::stringstream text;
  text << std::ifstream(output_path).rdbuf();
  outcome.output = text.str();
  std::remove(output_path.c_str());
  return outcome;
}

gs::runtime::GroundStationConfig keyed_config() {
  gs::runtime::GroundStationConfig c;
  for (const pa::VehicleId v : pa::kActVehicles) c.link.keys.push_back({v, pa::auth::Key{0x5a}});
  return c;
}

// A ground station's process core on loopback DDS domain 127, stepped 2 ms of its clock at a time.
struct SteppedStation {
  void step() {
    process.step(now_s);
    now_s += 0.002;
  }
  gs::link::InMemoryFrameBus bus;
  const gs::dds::Domain domain{127, gs::dds::loopback_config()};
  const gs::dds::Participant participant{domain};
  gs::service::Process process{bus, participant, keyed_config()};
  double now_s = 0.0;
};

}  // namespace

TEST_CASE("groundstation op prints the ground station's answer; accepted exits 0, refused 1") {
  SteppedStation station;
  const auto step = [&] { station.step(); };

  const Outcome accepted = run_groundstation({"op", "take-off", "--domain", "127", "--timeout", "5"}, step);
  INFO(accepted.output);
  CHECK(accepted.exit_code == 0);
  CHECK(accepted.output.find("accepted: command ") == 0);
  CHECK(accepted.output.find("take-off requested") != std::string::npos);

  const Outcome refused =
      run_groundstation({"op", "land", "--vehicle", "2", "--domain", "127", "--timeout", "5"}, step);
  INFO(refused.output);
  CHECK(refused.exit_code == 1);
  CHECK(refused.output.find("refused: command ") == 0);
  CHECK(refused.output.find("acts on both vehicles") != std::string::npos);
}

TEST_CASE("groundstation op without a ground station on the domain says so and exits 3") {
  const Outcome none = run_groundstation({"op", "kill", "--domain", "128", "--timeout", "0.5"}, [] {});
  INFO(none.output);
  CHECK(none.exit_code == 3);
  CHECK(none.output.find("no ground station on DDS domain 128") != std::string::npos);
}

TEST_CASE("groundstation watch --once prints the view of what a ground station publishes") {
  SteppedStation station;
  const Outcome watched = run_groundstation({"watch", "--domain", "127", "--once"}, [&] { station.step(); });
  INFO(watched.output);
  CHECK(watched.exit_code == 0);
  CHECK(watched.output.find("vehicle 1  link unheard") != std::string::npos);
  CHECK(watched.output.find("vehicle 2  link unheard") != std::string::npos);
  CHECK(watched.output.find("pole       not seen") != std::string::npos);
}
