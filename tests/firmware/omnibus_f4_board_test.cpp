// The Omnibus F4 board table: the IMU's mounting turns known motions into the right body axes
// (x forward, y left, z up, fw/mixer.hpp), the motor map, the battery divider.
#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <cstdint>

#include "fw/drivers/mpu6000.hpp"
#include "fw/drivers/omnibus_f4.hpp"

namespace {

namespace board = fw::drivers::omnibus_f4;
namespace mpu = fw::drivers::mpu6000;
using fw::Vec3f;
using fw::drivers::AxisMap;

// A burst as the chip would send it, from values in the chip's own axes.
std::array<std::uint8_t, 14> burst_from_chip(const Vec3f& accel_mps2, const Vec3f& gyro_radps) {
  std::array<std::uint8_t, 14> b{};
  const float a_lsb = 1.0f / mpu::accel_mps2_per_lsb(board::kImuRange.accel_g);
  const float g_lsb = 1.0f / mpu::gyro_radps_per_lsb(board::kImuRange.gyro_dps);
  auto put = [&b](int at, float value) {
    const auto v = static_cast<std::int16_t>(std::lround(value));
    b[at] = static_cast<std::uint8_t>(static_cast<std::uint16_t>(v) >> 8);
    b[at + 1] = static_cast<std::uint8_t>(static_cast<std::uint16_t>(v) & 0xFF);
  };
  for (int i = 0; i < 3; ++i) {
    put(2 * i, accel_mps2[i] * a_lsb);
    put(8 + 2 * i, gyro_radps[i] * g_lsb);
  }
  b[6] = 0x12;  // some temperature
  return b;
}

fw::ImuSample decode(const std::array<std::uint8_t, 14>& burst, const AxisMap& mounting) {
  mpu::Raw raw;
  REQUIRE(mpu::parse(burst, raw));
  return mpu::to_sample(raw, board::kImuRange, mounting, 0);
}

void check_vec(const Vec3f& got, const Vec3f& want, float tol) {
  for (int i = 0; i < 3; ++i) {
    INFO("axis " << i);
    CHECK(got[i] == Approx(want[i]).margin(tol));
  }
}

constexpr float kG = 9.80665f;
constexpr float kAccelTol = 0.01f;  // a few LSB at 16 g
constexpr float kGyroTol = 0.002f;  // a few LSB at 2000 deg/s

}  // namespace

TEST_CASE("omnibus f4: the chip is turned half a turn, so its x points back and its y right") {
  // Level at rest: the specific force reads +g up, in either frame.
  check_vec(decode(burst_from_chip({0, 0, kG}, {0, 0, 0}), board::kImuMounting).accel_mps2, {0, 0, kG},
            kAccelTol);

  // Nose down by 30 degrees at rest: the body's forward axis dips, so up has a -sin component
  // along body x; the chip, facing backwards, sees it as +sin along its x.
  const float s30 = 0.5f, c30 = std::sqrt(3.0f) / 2.0f;
  check_vec(decode(burst_from_chip({kG * s30, 0, kG * c30}, {0, 0, 0}), board::kImuMounting).accel_mps2,
            {-kG * s30, 0, kG * c30}, kAccelTol);

  // Rolling the left side down (negative about body x: positive roll lifts the left side) at
  // 2 rad/s, pitching nose down (positive about body y, which points left) at 1 rad/s and
  // yawing left (positive about z) at 3 rad/s: about the chip's backward x and rightward y the
  // first two read with the opposite sign.
  const fw::ImuSample motion = decode(burst_from_chip({0, 0, kG}, {2.0f, -1.0f, 3.0f}), board::kImuMounting);
  check_vec(motion.gyro_radps, {-2.0f, 1.0f, 3.0f}, kGyroTol);

  // Accelerating forward at 5 m/s^2 reads +5 on body x (specific force points forward).
  check_vec(decode(burst_from_chip({-5.0f, 0, kG}, {0, 0, 0}), board::kImuMounting).accel_mps2, {5.0f, 0, kG},
            kAccelTol);
}

TEST_CASE("quarter-turn mountings move the axes round") {
  // CW90: the chip's x points right, its y forward. Forward acceleration reads on the chip's y.
  check_vec(decode(burst_from_chip({0, 5.0f, kG}, {0, 0, 0}), fw::drivers::kCw90).accel_mps2, {5.0f, 0, kG},
            kAccelTol);
  // CW270: the chip's x points left, its y back.
  check_vec(decode(burst_from_chip({3.0f, -5.0f, kG}, {0, 0, 0}), fw::drivers::kCw270).accel_mps2,
            {5.0f, 3.0f, kG}, kAccelTol);
}

TEST_CASE("only proper rotations are mountings") {
  CHECK(fw::drivers::is_rotation(board::kImuMounting));
  CHECK_FALSE(fw::drivers::is_rotation(AxisMap{{0, 1, 2}, {1, 1, -1}}));  // a mirror image
  CHECK_FALSE(fw::drivers::is_rotation(AxisMap{{1, 0, 2}, {1, 1, 1}}));   // a swap is a mirror too
  CHECK_FALSE(fw::drivers::is_rotation(AxisMap{{0, 0, 2}, {1, 1, 1}}));   // an axis used twice
  CHECK_FALSE(fw::drivers::is_rotation(AxisMap{{0, 1, 3}, {1, 1, 1}}));
  CHECK_FALSE(fw::drivers::is_rotation(AxisMap{{0, 1, 2}, {1, 0, 1}}));
}

TEST_CASE("every mixer motor drives its own pad, in Betaflight's quad-x positions") {
  bool used[4] = {false, false, false, false};
  for (std::uint8_t pad : board::kMotorPad) {
    REQUIRE(pad < 4);
    CHECK_FALSE(used[pad]);
    used[pad] = true;
  }
  // Mixer 0 front-right -> pad M2, 1 rear-left -> M3, 2 front-left -> M4, 3 rear-right -> M1.
  CHECK(board::kMotorPad[0] + 1 == 2);
  CHECK(board::kMotorPad[1] + 1 == 3);
  CHECK(board::kMotorPad[2] + 1 == 4);
  CHECK(board::kMotorPad[3] + 1 == 1);
}

TEST_CASE("battery millivolts through the 11:1 divider") {
  CHECK(board::battery_mv(0) == 0);
  CHECK(board::battery_mv(4095) == 36300);
  // 16.8 V (a full 4S pack) is 16800 / 11 / 3300 * 4095 = 1895.3 counts.
  CHECK(board::battery_mv(1895) == 16798);
  CHECK(board::battery_mv(0xFFFF) == 36300);  // only 12 bits are a reading
}
