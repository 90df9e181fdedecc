// The MPU-6000 driver's pure part against a fake register bus: the identity check, the
// initialisation sequence, a missing and a wrong device, and the decoding of a burst.
#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "fw/drivers/mpu6000.hpp"
#include "fw/drivers/omnibus_f4.hpp"

namespace {

namespace mpu = fw::drivers::mpu6000;
namespace reg = mpu::reg;

// A register file that records every transfer. `absent` models a bus nobody drives (MISO
// pulled up reads 0xFF, floating or held low reads 0x00); `ignore_writes_to` a register
// that does not take its value.
struct FakeBus {
  enum class Op { read, write, delay };
  struct Event {
    Op op;
    std::uint8_t reg;
    std::uint32_t value;
  };

  std::array<std::uint8_t, 128> regs{};
  bool absent = false;
  std::uint8_t absent_value = 0x00;
  int ignore_writes_to = -1;
  int fail_transfer_at = -1;  // index of the transfer that fails
  std::vector<Event> events;

  FakeBus() { regs[reg::who_am_i] = mpu::kWhoAmI; }

  bool read(std::uint8_t r, std::uint8_t* data, std::size_t n) {
    events.push_back({Op::read, r, static_cast<std::uint32_t>(n)});
    if (static_cast<int>(transfers()) - 1 == fail_transfer_at) return false;
    for (std::size_t i = 0; i < n; ++i) data[i] = absent ? absent_value : regs[(r + i) & 0x7F];
    return true;
  }
  bool write(std::uint8_t r, std::uint8_t value) {
    events.push_back({Op::write, r, value});
    if (static_cast<int>(transfers()) - 1 == fail_transfer_at) return false;
    if (!absent && r != ignore_writes_to)
      regs[r] = r == reg::pwr_mgmt_1 ? (value & 0x7F) : value;  // reset self-clears
    return true;
  }
  void delay_ms(std::uint32_t ms) { events.push_back({Op::delay, 0, ms}); }

  std::size_t transfers() const {
    std::size_t n = 0;
    for (const Event& e : events) n += e.op != Op::delay ? 1 : 0;
    return n;
  }
  std::size_t writes() const {
    std::size_t n = 0;
    for (const Event& e : events) n += e.op == Op::write ? 1 : 0;
    return n;
  }
};

constexpr mpu::Range kRange{2000, 16};

}  // namespace

TEST_CASE("mpu6000 initialisation: identity first, then the register sequence in order") {
  FakeBus bus;
  const mpu::InitResult r = mpu::init(bus, kRange);
  REQUIRE(r.status == mpu::Status::ok);
  CHECK(r.who_am_i == 0x68);

  using Op = FakeBus::Op;
  const std::vector<FakeBus::Event> expected_start = {
      {Op::read, reg::who_am_i, 1},
      {Op::write, reg::pwr_mgmt_1, 0x80},
      {Op::delay, 0, 100},
      {Op::write, reg::signal_path_reset, 0x07},
      {Op::delay, 0, 100},
      {Op::write, reg::pwr_mgmt_1, 0x03},
      {Op::write, reg::user_ctrl, 0x10},
      {Op::write, reg::pwr_mgmt_2, 0x00},
      {Op::write, reg::smplrt_div, 0x00},
      {Op::write, reg::config, 0x01},
      {Op::write, reg::gyro_config, 0x18},   // FS_SEL 3: 2000 deg/s
      {Op::write, reg::accel_config, 0x18},  // AFS_SEL 3: 16 g
      {Op::write, reg::int_pin_cfg, 0x10},
  };
  REQUIRE(bus.events.size() >= expected_start.size());
  for (std::size_t i = 0; i < expected_start.size(); ++i) {
    INFO("event " << i);
    CHECK(static_cast<int>(bus.events[i].op) == static_cast<int>(expected_start[i].op));
    CHECK(bus.events[i].reg == expected_start[i].reg);
    CHECK(bus.events[i].value == expected_start[i].value);
  }
  // Then every configuration register is read back, and data ready is enabled last.
  std::size_t readbacks = 0;
  for (std::size_t i = expected_start.size(); i + 1 < bus.events.size(); ++i)
    readbacks += bus.events[i].op == Op::read ? 1 : 0;
  CHECK(readbacks == 8);
  CHECK(bus.events.back().op == Op::write);
  CHECK(bus.events.back().reg == reg::int_enable);
  CHECK(bus.events.back().value == 0x01);
  CHECK(bus.regs[reg::int_enable] == 0x01);
}

TEST_CASE("the ranges select the chip's full-scale settings") {
  CHECK(mpu::init_sequence({250, 2})[7].value == 0x00);
  CHECK(mpu::init_sequence({500, 4})[7].value == 0x08);
  CHECK(mpu::init_sequence({1000, 8})[8].value == 0x10);
  FakeBus bus;
  CHECK(mpu::init(bus, {300, 16}).status == mpu::Status::bad_range);
  CHECK(mpu::init(bus, {2000, 12}).status == mpu::Status::bad_range);
  CHECK(bus.events.empty());  // nothing touched the chip
}

TEST_CASE("a missing mpu6000 is reported and nothing is written") {
  for (std::uint8_t idle : {std::uint8_t{0x00}, std::uint8_t{0xFF}}) {
    FakeBus bus;
    bus.absent = true;
    bus.absent_value = idle;
    const mpu::InitResult r = mpu::init(bus, kRange);
    CHECK(r.status == mpu::Status::no_response);
    CHECK(r.who_am_i == idle);
    CHECK(bus.writes() == 0);
    CHECK(std::string(mpu::to_string(r.status)) == "no_response");
  }
}

TEST_CASE("a wrong device is reported with its identity and not configured") {
  FakeBus bus;
  bus.regs[reg::who_am_i] = 0x70;  // an MPU-6500
  const mpu::InitResult r = mpu::init(bus, kRange);
  CHECK(r.status == mpu::Status::wrong_identity);
  CHECK(r.who_am_i == 0x70);
  CHECK(bus.writes() == 0);
}

TEST_CASE("a register that does not take its value fails the initialisation, data ready stays off") {
  FakeBus bus;
  bus.ignore_writes_to = reg::accel_config;
  const mpu::InitResult r = mpu::init(bus, kRange);
  CHECK(r.status == mpu::Status::config_rejected);
  CHECK(r.failed_register == reg::accel_config);
  CHECK(bus.regs[reg::int_enable] == 0x00);
}

TEST_CASE("a failed transfer is a bus error naming the register") {
  FakeBus bus;
  bus.fail_transfer_at = 3;  // who_am_i, reset, signal path reset, then PWR_MGMT_1 = PLL
  const mpu::InitResult r = mpu::init(bus, kRange);
  CHECK(r.status == mpu::Status::bus_error);
  CHECK(r.failed_register == reg::pwr_mgmt_1);
}

TEST_CASE("a burst decodes to scaled body-frame values") {
  // ax = +2048 (1 g), ay = -4096 (-2 g), az = 1024 (0.5 g), temp = 0x0102,
  // gx = 16384 (1000 deg/s), gy = -32768 (-2000 deg/s), gz = 1.
  const std::array<std::uint8_t, 14> burst = {0x08, 0x00, 0xF0, 0x00, 0x04, 0x00, 0x01,
                                              0x02, 0x40, 0x00, 0x80, 0x00, 0x00, 0x01};
  mpu::Raw raw;
  REQUIRE(mpu::parse(burst, raw));
  CHECK(raw.accel == std::array<std::int16_t, 3>{2048, -4096, 1024});
  CHECK(raw.temperature == 0x0102);
  CHECK(raw.gyro == std::array<std::int16_t, 3>{16384, -32768, 1});

  const fw::ImuSample s = mpu::to_sample(raw, kRange, fw::drivers::kCw0, 1234);
  CHECK(s.t_us == 1234);
  CHECK(s.accel_mps2[0] == Approx(9.80665f));
  CHECK(s.accel_mps2[1] == Approx(-2 * 9.80665f));
  CHECK(s.accel_mps2[2] == Approx(0.5f * 9.80665f));
  const float deg = 3.14159265f / 180.0f;
  CHECK(s.gyro_radps[0] == Approx(1000 * deg));
  CHECK(s.gyro_radps[1] == Approx(-2000 * deg));
  CHECK(s.gyro_radps[2] == Approx(2000.0f / 32768.0f * deg));
}

TEST_CASE("a burst nobody drove is rejected") {
  mpu::Raw raw;
  std::array<std::uint8_t, 14> burst{};
  CHECK_FALSE(mpu::parse(burst, raw));
  burst.fill(0xFF);
  CHECK_FALSE(mpu::parse(burst, raw));
}
