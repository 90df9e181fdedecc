// The authenticated link: the firmware's SipHash-2-4 against the published vectors and against
// libsodium (the ground station's), and the vehicle's guard against forged and replayed frames.
#include <catch2/catch.hpp>

#include <sodium.h>

#include <array>
#include <cstdint>
#include <random>
#include <vector>

#include "fw/link_guard.hpp"
#include "pa/link_auth.hpp"

using namespace pa::proto;
using pa::auth::Key;

namespace {

constexpr Key kKey{0x10, 0x32, 0x54, 0x76, 0x98, 0xBA, 0xDC, 0xFE,
                   0x01, 0x23, 0x45, 0x67, 0x89, 0xAB, 0xCD, 0xEF};
constexpr std::uint32_t kNonce = 0xC0FFEE;

std::uint64_t sodium_siphash24(const Key& key, const std::uint8_t* message, std::size_t length) {
  unsigned char out[crypto_shorthash_siphash24_BYTES];
  crypto_shorthash_siphash24(out, message, length, key.data());
  std::uint64_t v = 0;
  for (int i = 0; i < 8; ++i) v |= static_cast<std::uint64_t>(out[i]) << (8 * i);
  return v;
}

fw::LinkConfig link_config(const Key& key = kKey, std::uint32_t nonce = kNonce) {
  fw::LinkConfig c;
  c.key = key;
  c.session_nonce = nonce;
  return c;
}

Frame setpoint(std::uint8_t seq, float thrust = 9.81f) {
  Frame f;
  REQUIRE(encode(RateThrust{{0.1f, -0.2f, 0.0f}, thrust, seq}, 1, f));
  return f;
}

struct Signed {
  Frame frame;
  Frame auth;
};

Signed sign(pa::auth::Signer& signer, const Frame& f) {
  Signed s{f, {}};
  REQUIRE(signer.sign(f, s.auth));
  return s;
}

// A frame as the vehicle hands it to its guard: decoded, an AUTH apart.
void hand(fw::LinkGuard& guard, const Frame& f) {
  Message m;
  REQUIRE(decode(f, m) == DecodeStatus::ok);
  if (m.type == Type::auth) guard.on_auth(f);
  else guard.on_frame(f, m, 0);
}

// The guard's ticks for one frame: the check's steps run in consecutive ticks.
bool verify(fw::LinkGuard& guard, Message& out) {
  std::uint32_t received_us = 0;
  for (int step = 0; step < pa::auth::TagCheck::kSteps; ++step)
    if (guard.verify_next(out, received_us)) return true;
  return false;
}

// Hands the pair to the guard (its queue empty) and runs the check.
bool deliver(fw::LinkGuard& guard, const Signed& s) {
  hand(guard, s.frame);
  hand(guard, s.auth);
  Message out;
  return verify(guard, out);
}

}  // namespace

TEST_CASE("SipHash-2-4 matches the published test vectors (key 00..0f, message 00..len-1)") {
  // From the SipHash paper's reference implementation (vectors.h), as 64-bit little-endian values.
  const std::vector<std::pair<std::size_t, std::uint64_t>> vectors = {
      {0, 0x726fdb47dd0e0e31ull}, {1, 0x74f839c593dc67fdull}, {2, 0x0d6c8009d9a94f5aull},
      {3, 0x85676696d7fb7e2dull}, {4, 0xcf2794e0277187b7ull}, {5, 0x18765564cd99a68dull},
      {6, 0xcbc9466e58fee3ceull}, {7, 0xab0200f58b01d137ull}, {8, 0x93f5f5799a932462ull},
      {9, 0x9e0082df0ba9e4b0ull}, {15, 0xa129ca6149be45e5ull}};
  Key key{};
  std::array<std::uint8_t, 64> message{};
  for (std::size_t i = 0; i < key.size(); ++i) key[i] = static_cast<std::uint8_t>(i);
  for (std::size_t i = 0; i < message.size(); ++i) message[i] = static_cast<std::uint8_t>(i);
  for (const auto& [length, expected] : vectors) {
    INFO("length " << length);
    CHECK(pa::auth::siphash24(key, message.data(), length) == expected);
  }
}

TEST_CASE("SipHash-2-4 of the firmware equals libsodium's on random keys and messages of 0..64 bytes") {
  REQUIRE(sodium_init() >= 0);
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> byte(0, 255);
  for (int trial = 0; trial < 2000; ++trial) {
    Key key;
    std::array<std::uint8_t, 64> message;
    for (auto& b : key) b = static_cast<std::uint8_t>(byte(rng));
    for (auto& b : message) b = static_cast<std::uint8_t>(byte(rng));
    const std::size_t length = static_cast<std::size_t>(trial % 65);
    REQUIRE(pa::auth::siphash24(key, message.data(), length) ==
            sodium_siphash24(key, message.data(), length));
  }
  // And so do session keys and tags computed with either.
  CHECK(pa::auth::session_key(kKey, kNonce) == pa::auth::session_key(kKey, kNonce, sodium_siphash24));
  const Key session = pa::auth::session_key(kKey, kNonce);
  CHECK(pa::auth::tag(session, 12345, setpoint(3)) ==
        pa::auth::tag(session, 12345, setpoint(3), sodium_siphash24));
}

TEST_CASE("the vehicle's three-step tag check computes the same tag as libsodium, for every frame length") {
  REQUIRE(sodium_init() >= 0);
  std::mt19937 rng(11);
  const Key session = pa::auth::session_key(kKey, kNonce, sodium_siphash24);
  pa::auth::TagCheck check(session);
  for (int trial = 0; trial < 5000; ++trial) {
    Frame f;
    f.id = static_cast<std::uint16_t>(rng() & 0x7FF);
    f.len = static_cast<std::uint8_t>(trial % 9);
    for (auto& b : f.data) b = static_cast<std::uint8_t>(rng());
    const std::uint32_t counter = static_cast<std::uint32_t>(rng());
    const std::uint64_t expected = pa::auth::tag(session, counter, f, sodium_siphash24);
    check.start(counter, pa::auth::TagCheck::words(f), expected);
    check.advance();
    REQUIRE(check.finish());
    check.start(counter, pa::auth::TagCheck::words(f), expected ^ 1u);
    check.advance();
    REQUIRE_FALSE(check.finish());
  }
}

TEST_CASE("frames signed by the ground (libsodium) pass the vehicle's guard, in order and with gaps") {
  fw::LinkGuard guard(link_config());
  pa::auth::Signer ground(kKey, sodium_siphash24);
  ground.start_session(kNonce, 0);
  for (std::uint8_t i = 0; i < 100; ++i) {
    const Signed s = sign(ground, setpoint(i & 0x0F));
    hand(guard, s.frame);
    hand(guard, s.auth);
    Message out;
    std::uint32_t received_us = 0;
    CHECK_FALSE(guard.verify_next(out, received_us));  // the check's first two steps
    CHECK_FALSE(guard.verify_next(out, received_us));
    REQUIRE(guard.verify_next(out, received_us));
    CHECK(out.type == Type::rate_thrust);
    CHECK(out.rate_thrust.seq == (i & 0x0F));
  }
  CHECK(guard.last_counter() == 100);
  // Frames lost on the radio: the counter may skip up to 32,768.
  for (int i = 0; i < 32767; ++i) sign(ground, setpoint(0));
  CHECK(deliver(guard, sign(ground, setpoint(1))));
  CHECK(guard.last_counter() == 100 + 32768);
  CHECK(guard.rejected() == 0);
}

TEST_CASE("a changed payload, a frame without its AUTH and an AUTH alone are refused and counted") {
  fw::LinkGuard guard(link_config());
  pa::auth::Signer ground(kKey);
  ground.start_session(kNonce, 0);
  Signed s = sign(ground, setpoint(1, 5.0f));
  s.frame.data[6] ^= 0x01;  // a thrust bit
  CHECK_FALSE(deliver(guard, s));
  CHECK(guard.forged() == 1);

  hand(guard, setpoint(2));  // no AUTH: replaced by the next frame
  const Signed good = sign(ground, setpoint(3));
  CHECK(deliver(guard, good));
  CHECK(guard.forged() == 2);
  hand(guard, good.auth);  // an AUTH with nothing before it
  CHECK(guard.forged() == 3);
  Message out;
  CHECK_FALSE(verify(guard, out));
}

TEST_CASE("2^24 forged frames: none accepted, every one counted") {
  fw::LinkGuard guard(link_config());
  std::mt19937_64 rng(2024);
  const std::array<Frame, 3> frames = {setpoint(1, 0.0f), setpoint(2, 40.0f), [] {
                                         Frame f;
                                         encode(Kill{0, KillReason::operator_request}, 1, f);
                                         return f;
                                       }()};
  constexpr std::uint32_t kForgeries = 1u << 24;
  std::array<Message, 3> decoded;
  for (std::size_t k = 0; k < frames.size(); ++k) REQUIRE(decode(frames[k], decoded[k]) == DecodeStatus::ok);
  std::uint32_t accepted = 0;
  for (std::uint32_t i = 0; i < kForgeries; ++i) {
    const std::uint64_t r = rng();
    Frame auth;
    encode(Auth{static_cast<std::uint16_t>(r >> 48), r & pa::auth::kTagMask}, 1, auth);
    guard.on_frame(frames[i % frames.size()], decoded[i % frames.size()], 0);
    guard.on_auth(auth);
    Message out;
    if (verify(guard, out)) ++accepted;
  }
  CHECK(accepted == 0);
  CHECK(guard.forged() + guard.replayed() == kForgeries);
  CHECK(guard.forged() > kForgeries / 3);  // about half carry a counter ahead and cost a MAC
  CHECK(guard.last_counter() == 0);
}

TEST_CASE("every captured frame replayed, in this boot or the next: none accepted, all counted") {
  fw::LinkGuard guard(link_config());
  pa::auth::Signer ground(kKey);
  ground.start_session(kNonce, 0);
  std::vector<Signed> captured;
  for (int i = 0; i < 2000; ++i) {
    captured.push_back(sign(ground, setpoint(static_cast<std::uint8_t>(i & 0x0F))));
    REQUIRE(deliver(guard, captured.back()));
  }
  int accepted = 0;
  for (const Signed& s : captured) accepted += deliver(guard, s) ? 1 : 0;
  CHECK(accepted == 0);
  CHECK(guard.replayed() == 2000);

  // The vehicle reboots and draws a new nonce: the old tags are worth nothing.
  fw::LinkGuard rebooted(link_config(kKey, kNonce + 1));
  for (const Signed& s : captured) accepted += deliver(rebooted, s) ? 1 : 0;
  CHECK(accepted == 0);
  CHECK(rebooted.forged() == 2000);
  // Its ground station starts signing in the new session and is heard at once.
  pa::auth::Signer restarted(kKey);
  restarted.start_session(kNonce + 1, rebooted.last_counter());
  CHECK(deliver(rebooted, sign(restarted, setpoint(1))));
}

TEST_CASE("a vehicle without a key accepts nothing, even correctly signed frames") {
  for (const Key& key : {Key{}, [] {
                           Key k;
                           k.fill(0xFF);
                           return k;
                         }()}) {
    fw::LinkGuard guard(link_config(key));
    CHECK_FALSE(guard.provisioned());
    pa::auth::Signer ground(key);
    ground.start_session(kNonce, 0);
    CHECK_FALSE(deliver(guard, sign(ground, setpoint(1))));
  }
}

TEST_CASE("the latest KILL is verified first and supersedes the frames queued before it") {
  fw::LinkGuard guard(link_config());
  pa::auth::Signer ground(kKey);
  ground.start_session(kNonce, 0);
  Frame kill;
  REQUIRE(encode(Kill{0, KillReason::operator_request}, 1, kill));
  for (const Frame& f : {setpoint(1), setpoint(2), kill}) {
    const Signed s = sign(ground, f);
    hand(guard, s.frame);
    hand(guard, s.auth);
  }
  REQUIRE(guard.queued() == 3);
  Message out;
  REQUIRE(verify(guard, out));
  CHECK(out.type == Type::kill);
  CHECK(guard.queued() == 0);

  // A forged KILL costs its own turn only: the frames before it keep their order.
  const Signed a = sign(ground, setpoint(3));
  hand(guard, a.frame);
  hand(guard, a.auth);
  Frame forged_auth;
  encode(Auth{static_cast<std::uint16_t>(ground.next_counter()), 0x123456789ABCull}, 1, forged_auth);
  hand(guard, kill);
  hand(guard, forged_auth);
  CHECK_FALSE(verify(guard, out));
  CHECK(guard.forged() == 1);
  REQUIRE(verify(guard, out));
  CHECK(out.type == Type::rate_thrust);
  CHECK(out.rate_thrust.seq == 3);
}

TEST_CASE("a full queue drops the newest frame, but never a KILL") {
  fw::LinkGuard guard(link_config());
  pa::auth::Signer ground(kKey);
  ground.start_session(kNonce, 0);
  for (std::uint8_t i = 0; i < fw::LinkGuard::kQueue + 2; ++i) {
    const Signed s = sign(ground, setpoint(i));
    hand(guard, s.frame);
    hand(guard, s.auth);
  }
  CHECK(guard.queued() == fw::LinkGuard::kQueue);
  CHECK(guard.queue_full() == 2);
  Frame kill;
  REQUIRE(encode(Kill{0, KillReason::operator_request}, 1, kill));
  const Signed k = sign(ground, kill);
  hand(guard, k.frame);
  hand(guard, k.auth);
  CHECK(guard.queued() == fw::LinkGuard::kQueue);
  CHECK(guard.queue_full() == 3);  // the newest setpoint made way
  Message out;
  REQUIRE(verify(guard, out));
  CHECK(out.type == Type::kill);
}

TEST_CASE("counters: replays are behind, gaps up to 32,768 ahead, and a spent session ends") {
  std::uint32_t out = 0;
  using pa::auth::CounterCheck;
  CHECK(pa::auth::expand_counter(0, 1, out) == CounterCheck::fresh);
  CHECK(out == 1);
  CHECK(pa::auth::expand_counter(0xFFF0, 0x0005, out) == CounterCheck::fresh);
  CHECK(out == 0x10005);
  CHECK(pa::auth::expand_counter(100, 100, out) == CounterCheck::replayed);
  CHECK(pa::auth::expand_counter(100, 99, out) == CounterCheck::replayed);
  CHECK(pa::auth::expand_counter(100, static_cast<std::uint16_t>(100 + 0x8000), out) == CounterCheck::fresh);
  CHECK(pa::auth::expand_counter(100, static_cast<std::uint16_t>(100 + 0x8001), out) ==
        CounterCheck::replayed);
  CHECK(pa::auth::expand_counter(0xFFFFFFFEu, 0xFFFF, out) == CounterCheck::fresh);
  CHECK(pa::auth::expand_counter(0xFFFFFFFFu, 0x0000, out) == CounterCheck::spent);
}
