// Processor in the loop without QEMU (hil/sil/emulated_firmware.hpp): the process, the socket,
// the configuration file and the serial framing of the emulated backend, against a stand-in for
// QEMU and the image (pil_stand_in_image.cpp: the core compiled for this host behind the image's
// serial contract). The real image in QEMU is flown by the cortex-m4 preset's
// mps2_pil_flies_one_attempt (firmware/ports/mps2_an386/CMakeLists.txt).
#include <catch2/catch.hpp>

#include <signal.h>

#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "hil/sil/arena.hpp"
#include "hil/sil/emulated_firmware.hpp"
#include "hil/sil/firmware_vehicle.hpp"
#include "hil/trials/cuts.hpp"
#include "hil/trials/series.hpp"

using hil::sil::EmulatedFirmware;
using hil::sil::EmulatedFirmwareError;
using hil::sil::EmulatorConfig;
using Catch::Matchers::Contains;
using pa::proto::Frame;
using pa::proto::Type;

namespace {

// What the stand-in does (its PA_PIL_STAND_IN), for the lifetime of this object.
class StandIn {
 public:
  explicit StandIn(const char* mode) { setenv("PA_PIL_STAND_IN", mode, 1); }
  ~StandIn() { unsetenv("PA_PIL_STAND_IN"); }
  StandIn(const StandIn&) = delete;
  StandIn& operator=(const StandIn&) = delete;
};

EmulatorConfig stand_in(double answer_timeout_s = 10.0) {
  EmulatorConfig c;
  c.qemu = PA_PIL_STAND_IN;
  c.image = PA_PIL_STAND_IN;  // any file: the stand-in runs the core it was built with
  c.icount_shift = 10;
  c.connect_timeout_s = 5.0;
  c.answer_timeout_s = answer_timeout_s;
  return c;
}

fw::VehicleConfig vehicle1() { return hil::sil::firmware_config_for(hil::VehicleConfig{}, pa::kVehicle1); }

// One IMU sample at rest for tick `tick`, as the plant puts it on the bus.
std::vector<Frame> sample(std::uint16_t tick, std::uint8_t node = 1) {
  Frame gyro, accel;
  pa::proto::encode(pa::proto::HilImuGyro{{0.0f, 0.0f, 0.0f}, tick}, node, gyro);
  pa::proto::encode(pa::proto::HilImuAccel{{0.0f, 0.0f, 9.81f}, tick}, node, accel);
  return {gyro, accel};
}

Type type_of(const Frame& f) { return static_cast<Type>(pa::proto::id_type(f.id)); }

bool reaped(pid_t pid) { return kill(pid, 0) == -1 && errno == ESRCH; }

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const EmulatedFirmwareError& e) {
    return e.what();
  }
  return "(no EmulatedFirmwareError)";
}

}  // namespace

TEST_CASE("the emulated firmware answers each tick as the core in process does", "[hil][sil][pil]") {
  StandIn mode("answer");
  EmulatedFirmware image(vehicle1(), stand_in());
  hil::sil::FirmwareVehicle in_process(vehicle1());
  CHECK_FALSE(image.last_tick_instructions());
  // QEMU's folder holds the configuration until the image has answered (it has read it then).
  const std::string folder = image.folder();
  CHECK(std::filesystem::file_size(folder + "/pil_vehicle.cfg") == 8 + sizeof(fw::VehicleConfig));

  for (std::uint16_t tick = 1; tick <= 120; ++tick) {
    const std::vector<Frame> emulated = image.on_bus(sample(tick));
    const std::vector<Frame> host = in_process.on_bus(sample(tick));
    INFO("tick " << tick);
    // HIL_MOTORS first, then the core's frames in its order; HIL_TICK_COST is taken out.
    REQUIRE(emulated.size() == host.size());
    REQUIRE(type_of(emulated.front()) == Type::hil_motors);
    for (std::size_t i = 0; i < host.size(); ++i) {
      CHECK(emulated[i].id == host[i].id);
      // TELEMETRY_STATUS carries the tick's duration on the host's clock, different in each.
      if (type_of(host[i]) != Type::telemetry_status) CHECK(emulated[i].data == host[i].data);
    }
    REQUIRE(image.last_tick_instructions() == 100000u + tick);
  }
  CHECK(image.ticks_answered() == 120);
  CHECK(image.folder().empty());
  CHECK_FALSE(std::filesystem::exists(folder));
  CHECK(image.decoder_stats().crc_errors == 0);

  // Frames that complete no sample of its node are not answered; half a sample waits for its other half.
  CHECK(image.on_bus({sample(121).front()}).empty());
  CHECK(image.on_bus(sample(121, 2)).empty());
  const std::vector<Frame> answer = image.on_bus({sample(121).back()});
  REQUIRE_FALSE(answer.empty());
  CHECK(type_of(answer.front()) == Type::hil_motors);
  CHECK(image.last_tick_instructions() == 100121u);

  // Two samples in one batch: two answers, each in the core's order.
  std::vector<Frame> two = sample(122);
  for (const Frame& f : sample(123)) two.push_back(f);
  std::size_t motors = 0;
  for (const Frame& f : image.on_bus(two)) motors += type_of(f) == Type::hil_motors ? 1 : 0;
  CHECK(motors == 2);
  CHECK(image.last_tick_instructions() == 100123u);
  CHECK(image.observe().mode == pa::proto::Mode::disarmed);
  CHECK(image.setpoint_age_us(123000) == hil::sil::kNoSetpoint);

  const pid_t pid = image.qemu_pid();
  REQUIRE(pid > 0);
}

TEST_CASE("the emulated firmware is stopped and reaped when destroyed", "[hil][sil][pil]") {
  StandIn mode("answer");
  pid_t pid = -1;
  {
    EmulatedFirmware image(vehicle1(), stand_in());
    pid = image.qemu_pid();
    REQUIRE(pid > 0);
    CHECK_FALSE(reaped(pid));
  }
  CHECK(reaped(pid));  // killed and waited for: no zombie
}

TEST_CASE("the emulated firmware says clearly why QEMU did not start, connect or answer", "[hil][sil][pil]") {
  SECTION("no emulator") {
    EmulatorConfig c = stand_in();
    c.qemu = "/nonexistent/qemu-system-arm";
    CHECK_THAT(error_of([&] { EmulatedFirmware image(vehicle1(), c); }),
               Contains("cannot run '/nonexistent/qemu-system-arm'"));
  }
  SECTION("no image") {
    EmulatorConfig c = stand_in();
    c.image = "/nonexistent/fw_mps2_an386_pil.elf";
    CHECK_THAT(error_of([&] { EmulatedFirmware image(vehicle1(), c); }), Contains("no image file"));
  }
  SECTION("QEMU exits before it connects") {
    StandIn mode("exit");
    const std::string e = error_of([&] { EmulatedFirmware image(vehicle1(), stand_in()); });
    CHECK_THAT(e, Contains("exited with status 3 before it connected"));
    CHECK_THAT(e, Contains("stand-in: exiting at once as asked"));  // QEMU's own output
  }
  SECTION("QEMU never connects") {
    StandIn mode("no_connect");
    EmulatorConfig c = stand_in();
    c.connect_timeout_s = 0.5;
    const auto start = std::chrono::steady_clock::now();
    const std::string e = error_of([&] { EmulatedFirmware image(vehicle1(), c); });
    CHECK(std::chrono::steady_clock::now() - start < std::chrono::seconds(5));
    CHECK_THAT(e, Contains("did not connect to the vehicle's serial line within 0.5 s"));
    CHECK_THAT(e, Contains("stand-in: not connecting as asked"));
  }
  SECTION("the image hangs") {
    StandIn mode("hang_after=3");
    EmulatedFirmware image(vehicle1(), stand_in(1.0));
    const pid_t pid = image.qemu_pid();
    for (std::uint16_t tick = 1; tick <= 3; ++tick) REQUIRE_FALSE(image.on_bus(sample(tick)).empty());
    const auto start = std::chrono::steady_clock::now();
    const std::string e = error_of([&] { image.on_bus(sample(4)); });
    CHECK(std::chrono::steady_clock::now() - start < std::chrono::seconds(5));
    CHECK_THAT(e, Contains("emulated firmware of vehicle 1: no answer to tick 4 within 1.0 s"));
    CHECK_THAT(e, Contains("stand-in: hanging after 3 ticks as asked"));
    CHECK(reaped(pid));  // killed at once, not when destroyed
    CHECK_THAT(error_of([&] { image.on_bus(sample(5)); }),
               Contains("no answer to tick 4"));  // and stays failed
  }
  SECTION("the image exits") {
    StandIn mode("exit_after=2");
    EmulatedFirmware image(vehicle1(), stand_in());
    for (std::uint16_t tick = 1; tick <= 2; ++tick) REQUIRE_FALSE(image.on_bus(sample(tick)).empty());
    const std::string e = error_of([&] { image.on_bus(sample(3)); });
    CHECK_THAT(e, Contains("QEMU closed the serial line awaiting tick 3: QEMU exited with status 4"));
    CHECK_THAT(e, Contains("stand-in: exiting after 2 ticks as asked"));
  }
}

TEST_CASE("a series flown by emulated firmware flies as the one in process", "[hil][sil][pil]") {
  StandIn mode("answer");
  struct Flight {
    std::vector<hil::Vec3> positions;
    std::vector<pa::proto::Mode> modes;
    std::vector<gs::mission::Task> tasks;
    std::vector<std::uint32_t> instructions;  // vehicle 2's per step
    std::uint64_t steps = 0;
    float thrust_mps2 = 0.0f;
  };
  const auto fly = [](bool emulated) {
    Flight f;
    hil::trials::SeriesConfig config;
    config.seed = 3;
    if (emulated) config.arena.emulated_firmware = stand_in();
    config.on_step = [&f](const hil::sil::Arena& arena, const gs::runtime::GroundStation&) {
      ++f.steps;
      if (const auto n = arena.vehicle(pa::kVehicle2).last_tick_instructions()) f.instructions.push_back(*n);
    };
    hil::trials::SeriesRunner runner(config);
    runner.run({});  // the take-off only
    runner.hover_for(0.5);
    for (const pa::VehicleId v : pa::kActVehicles) {
      f.positions.push_back(runner.arena().plant().vehicle(v).body.position_m);
      f.modes.push_back(runner.arena().vehicle(v).observe().mode);
      f.tasks.push_back(runner.ground_station().task(v));
    }
    f.thrust_mps2 = runner.arena().vehicle(pa::kVehicle1).observe().setpoint.thrust_mps2;
    return f;
  };
  const Flight host = fly(false);
  const Flight emulated = fly(true);
  REQUIRE(host.tasks == std::vector<gs::mission::Task>{gs::mission::Task::hover, gs::mission::Task::hover});
  CHECK(emulated.tasks == host.tasks);
  CHECK(emulated.positions == host.positions);  // bit for bit: the same frames both ways
  CHECK(emulated.modes == host.modes);
  CHECK(emulated.modes.front() == pa::proto::Mode::flying);
  CHECK(emulated.thrust_mps2 > 5.0f);  // hovering on the setpoints it was handed
  // Every step's tick cost reached on_step: the stand-in's 100000 + that step's tick.
  CHECK(host.instructions.empty());
  REQUIRE(emulated.instructions.size() == emulated.steps);
  for (std::size_t k = 0; k < emulated.instructions.size(); ++k)
    REQUIRE(emulated.instructions[k] == 100000u + (k + 1) % 65536u);
}

TEST_CASE("an arena flown by emulated firmware is not copied, and cuts refuse it", "[hil][sil][pil]") {
  StandIn mode("answer");
  hil::sil::ArenaConfig config;
  config.emulated_firmware = stand_in();
  hil::sil::Arena arena(hil::PlantConfig{}, config, 1);
  CHECK(arena.emulated_firmware());
  arena.step();
  CHECK_THROWS_AS(hil::sil::Arena(arena), std::logic_error);
  CHECK_THROWS_AS(arena.vehicle(pa::kVehicle1).firmware(), std::logic_error);
  CHECK_THROWS_AS(hil::trials::fly_cut(arena, hil::trials::CutLimits{}), std::invalid_argument);
  arena.step();  // the original flies on
  CHECK(arena.vehicle(pa::kVehicle1).last_tick_instructions() == 100002u);
}
