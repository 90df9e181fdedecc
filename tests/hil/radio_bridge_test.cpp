#include <catch2/catch.hpp>

#include <stdexcept>

#include "hil/radio/radio_bridge.hpp"

using hil::RadioBridge;
using hil::RadioConfig;
using hil::Side;

namespace {
pa::proto::Frame numbered(std::uint8_t n) {
  pa::proto::Frame f;
  f.id = 0x123;
  f.len = 1;
  f.data[0] = n;
  return f;
}
}  // namespace

TEST_CASE("the radio delays frames by its latency and jitter, in order, each way on its own") {
  RadioBridge radio(RadioConfig{0.010, 0.004, 0.0, 7});
  for (std::uint8_t n = 0; n < 50; ++n) radio.offer(Side::ground, numbered(n), 0.001 * n);
  radio.offer(Side::vehicle, numbered(200), 0.0);
  pa::proto::Frame f;
  CHECK_FALSE(radio.deliver(Side::vehicle, 0.0099, f));  // nothing before the latency
  CHECK(radio.deliver(Side::ground, 0.0141, f));         // the other direction has its own queue
  CHECK(f.data[0] == 200);
  std::uint8_t expected = 0;
  for (double t = 0.0; t < 0.1; t += 0.0005) {
    while (radio.deliver(Side::vehicle, t, f)) {
      CHECK(f.data[0] == expected);  // never reordered
      CHECK(t >= 0.001 * expected + 0.010);
      CHECK(t <= 0.001 * expected + 0.014 + 0.0005 + 0.004);  // jitter, step, and waiting for the one before
      ++expected;
    }
  }
  CHECK(expected == 50);
}

TEST_CASE("the radio loses about the configured fraction, reproducibly for a seed") {
  auto run = [](std::uint32_t seed) {
    RadioBridge radio(RadioConfig{0.0, 0.0, 0.2, seed});
    for (int i = 0; i < 10000; ++i) radio.offer(Side::ground, numbered(0), 0.0);
    return radio.lost(Side::ground);
  };
  const auto lost = run(3);
  CHECK(lost > 1800);
  CHECK(lost < 2200);
  CHECK(run(3) == lost);
}

TEST_CASE("a radio configuration outside its ranges is refused with a reason") {
  CHECK_THROWS_AS(RadioBridge(RadioConfig{-0.001, 0.0, 0.0, 1}), std::invalid_argument);
  CHECK_THROWS_AS(RadioBridge(RadioConfig{0.01, 0.0, 1.5, 1}), std::invalid_argument);
  CHECK_THROWS_WITH(RadioBridge(RadioConfig{0.01, -1.0, 0.0, 1}), Catch::Contains("jitter"));
}

TEST_CASE("a radio with outages loses everything in 100 ms stretches, 20 % of the time, both ways at once") {
  RadioConfig config{0.0, 0.0, 0.2, 5, 0.1};
  RadioBridge radio(config);
  // A frame each way every millisecond for 200 s.
  int lost_before = 0;
  int outages = 0, longest_ms = 0, run_ms = 0;
  for (int k = 0; k < 200000; ++k) {
    const double t = 0.001 * k;
    radio.offer(Side::ground, numbered(0), t);
    const int lost_now = static_cast<int>(radio.lost(Side::ground));
    const bool lost = lost_now > lost_before;
    lost_before = lost_now;
    radio.offer(Side::vehicle, numbered(0), t);
    run_ms = lost ? run_ms + 1 : 0;
    if (run_ms == 1) ++outages;
    if (run_ms > longest_ms) longest_ms = run_ms;
  }
  // Both directions lose the same frames: the outage is the link's.
  CHECK(radio.lost(Side::ground) == radio.lost(Side::vehicle));
  const double fraction = static_cast<double>(radio.lost(Side::ground)) / 200000.0;
  CHECK(fraction > 0.17);
  CHECK(fraction < 0.23);
  // 20 % of 200 s in 0.1 s outages: about 400 of them (adjacent ones merge), none longer than
  // two back to back with this seed.
  CHECK(outages > 300);
  CHECK(outages < 420);
  CHECK(longest_ms <= 200);
  CHECK(longest_ms >= 100);
}
