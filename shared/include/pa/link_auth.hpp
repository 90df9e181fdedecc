// The authenticated link: who may command a vehicle. docs/security.md says what it defends
// against and what it does not.
//
// Each vehicle has a 128-bit key, provisioned at flashing time. At boot the vehicle draws a
// 32-bit session nonce and announces it, with the last counter it accepted, in LINK_SESSION.
// Every ground frame the vehicle acts on is followed by an AUTH frame to the same node that
// carries the low 16 bits of a counter and a 48-bit tag: SipHash-2-4 under the session key
// (derived from the key and the nonce) over the full 32-bit counter and the frame's identifier,
// length and payload. The vehicle accepts a frame only with a valid tag and a counter above the
// last one it accepted (and at most 32,768 above); there is no clock and no time window. A replay from an earlier boot
// fails the tag (other nonce), one from this boot fails the counter.
//
// The hash is SipHash-2-4 (Aumasson and Bernstein, 2012): a keyed PRF designed for short
// messages, 8 rounds for our 14 bytes. The firmware uses siphash24() below; the ground station
// uses libsodium's crypto_shorthash_siphash24, and tests check that both agree and that this one
// matches the published test vectors. Freestanding: no heap, no exceptions, no OS.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "pa/protocol.hpp"

namespace pa::auth {

using Key = std::array<std::uint8_t, 16>;
// A function computing SipHash-2-4 (ground: libsodium's; vehicle: siphash24()).
using MacFunction = std::uint64_t (*)(const Key& key, const std::uint8_t* message, std::size_t length);

inline constexpr std::uint64_t kTagMask = 0xFFFFFFFFFFFFull;  // 48-bit tags
inline constexpr std::size_t kTagInputBytes = 14;             // counter, identifier and length, payload

// An all-zero or all-ones (erased flash) key is no key: such a vehicle accepts no frame.
inline bool provisioned(const Key& key) {
  bool zeros = true;
  bool ones = true;
  for (std::uint8_t b : key) {
    zeros = zeros && b == 0x00;
    ones = ones && b == 0xFF;
  }
  return !zeros && !ones;
}

namespace detail {
inline std::uint64_t rotl(std::uint64_t x, int b) { return (x << b) | (x >> (64 - b)); }
inline std::uint64_t load_u64(const std::uint8_t* p) {
  std::uint64_t v = 0;
  for (int i = 0; i < 8; ++i)
    v |= static_cast<std::uint64_t>(p[i]) << (8 * i);  // a load on a little-endian MCU
  return v;
}
struct SipState {
  std::uint64_t v0, v1, v2, v3;
  void round() {
    v0 += v1;
    v1 = rotl(v1, 13);
    v1 ^= v0;
    v0 = rotl(v0, 32);
    v2 += v3;
    v3 = rotl(v3, 16);
    v3 ^= v2;
    v0 += v3;
    v3 = rotl(v3, 21);
    v3 ^= v0;
    v2 += v1;
    v1 = rotl(v1, 17);
    v1 ^= v2;
    v2 = rotl(v2, 32);
  }
  void compress(std::uint64_t m) {
    v3 ^= m;
    round();
    round();
    v0 ^= m;
  }
};
}  // namespace detail

// SipHash-2-4 with a 64-bit output, as specified in the SipHash paper (section 2).
inline std::uint64_t siphash24(const Key& key, const std::uint8_t* message, std::size_t length) {
  const std::uint64_t k0 = detail::load_u64(key.data());
  const std::uint64_t k1 = detail::load_u64(key.data() + 8);
  detail::SipState s{k0 ^ 0x736f6d6570736575ull, k1 ^ 0x646f72616e646f6dull, k0 ^ 0x6c7967656e657261ull,
                     k1 ^ 0x7465646279746573ull};
  std::size_t i = 0;
  for (; i + 8 <= length; i += 8) s.compress(detail::load_u64(message + i));
  std::uint64_t last = static_cast<std::uint64_t>(length) << 56;
  for (std::size_t j = 0; i + j < length; ++j) last |= static_cast<std::uint64_t>(message[i + j]) << (8 * j);
  s.compress(last);
  s.v2 ^= 0xFF;
  s.round();
  s.round();
  s.round();
  s.round();
  return s.v0 ^ s.v1 ^ s.v2 ^ s.v3;
}

// The session key: two outputs of the PRF keyed with the vehicle's key, over the nonce and a
// label, so that every boot has its own key and nothing of an earlier boot verifies.
inline Key session_key(const Key& key, std::uint32_t nonce, MacFunction mac = siphash24) {
  Key out{};
  for (std::uint8_t half = 0; half < 2; ++half) {
    const std::array<std::uint8_t, 6> label{static_cast<std::uint8_t>(nonce),
                                            static_cast<std::uint8_t>(nonce >> 8),
                                            static_cast<std::uint8_t>(nonce >> 16),
                                            static_cast<std::uint8_t>(nonce >> 24),
                                            'S',
                                            half};
    const std::uint64_t h = mac(key, label.data(), label.size());
    for (int b = 0; b < 8; ++b) out[8 * half + b] = static_cast<std::uint8_t>(h >> (8 * b));
  }
  return out;
}

// The 14 bytes a tag covers: the counter, the identifier with the length in bits 12-15, and the
// payload (beyond the frame's length it counts as zeros, so bytes a sender never wrote cannot
// change it).
inline std::array<std::uint8_t, kTagInputBytes> tag_input(std::uint32_t counter, const proto::Frame& frame) {
  std::array<std::uint8_t, kTagInputBytes> in{};
  const std::uint8_t length = frame.len > proto::kMaxPayload ? proto::kMaxPayload : frame.len;
  proto::detail::put_u32(&in[0], counter);
  proto::detail::put_u16(&in[4], static_cast<std::uint16_t>((frame.id & 0x7FFu) | (length << 12)));
  for (std::uint8_t i = 0; i < length; ++i) in[6 + i] = frame.data[i];
  return in;
}

// The 48-bit tag of `frame` sent with `counter`.
inline std::uint64_t tag(const Key& session, std::uint32_t counter, const proto::Frame& frame,
                         MacFunction mac = siphash24) {
  const std::array<std::uint8_t, kTagInputBytes> in = tag_input(counter, frame);
  return mac(session, in.data(), in.size()) & kTagMask;
}

// The vehicle's tag check, cut for a 1 kHz tick: the same SipHash-2-4 over the same 14 bytes
// (tests check it against tag()), with the keyed initial state computed once per session, the
// message words of a frame prepared when it arrives (words()), and the eight rounds spread over
// three steps (2, 3 and 3 rounds), run in consecutive ticks.
class TagCheck {
 public:
  static constexpr int kSteps = 3;

  // The frame's two message words, the counter left out of the first (it is known only when
  // the check starts).
  struct Words {
    std::uint64_t first = 0;
    std::uint64_t second = 0;
  };
  static Words words(const proto::Frame& frame) {
    const std::uint8_t length = frame.len > proto::kMaxPayload ? proto::kMaxPayload : frame.len;
    const std::uint64_t payload =
        detail::load_u64(frame.data.data()) & (length == 8 ? ~0ull : (1ull << (8 * length)) - 1u);
    const std::uint64_t id_len = (frame.id & 0x7FFu) | (static_cast<std::uint64_t>(length) << 12);
    return Words{(id_len << 32) | (payload << 48),
                 (payload >> 16) | (static_cast<std::uint64_t>(kTagInputBytes) << 56)};
  }

  TagCheck() = default;
  explicit TagCheck(const Key& session) {
    const std::uint64_t k0 = detail::load_u64(session.data());
    const std::uint64_t k1 = detail::load_u64(session.data() + 8);
    initial_ = detail::SipState{k0 ^ 0x736f6d6570736575ull, k1 ^ 0x646f72616e646f6dull,
                                k0 ^ 0x6c7967656e657261ull, k1 ^ 0x7465646279746573ull};
  }
  // Step 1: the first message block.
  void start(std::uint32_t counter, const Words& words, std::uint64_t expected) {
    expected_ = expected;
    last_block_ = words.second;
    state_ = initial_;
    state_.compress(words.first | counter);
  }
  // Step 2: the last block and the first finalisation round.
  void advance() {
    state_.compress(last_block_);
    state_.v2 ^= 0xFF;
    state_.round();
  }
  // Step 3: the last three rounds; true when the tag is the expected one.
  bool finish() {
    state_.round();
    state_.round();
    state_.round();
    return ((state_.v0 ^ state_.v1 ^ state_.v2 ^ state_.v3) & kTagMask) == expected_;
  }

 private:
  detail::SipState initial_{};
  detail::SipState state_{};
  std::uint64_t last_block_ = 0;
  std::uint64_t expected_ = 0;
};

// What an AUTH frame's low 16 bits say about its counter, against the last accepted one.
enum class CounterCheck : std::uint8_t {
  fresh,     // up to 32,768 ahead (frames lost on the radio are skipped): `out` holds it
  replayed,  // at or behind the last accepted one: already seen, or older
  spent,     // it would pass 2^32 - 1; the vehicle must reboot for a new session
};
inline CounterCheck expand_counter(std::uint32_t last, std::uint16_t low, std::uint32_t& out) {
  const auto ahead = static_cast<std::uint16_t>(low - static_cast<std::uint16_t>(last));
  if (ahead == 0 || ahead > 0x8000u) return CounterCheck::replayed;
  if (static_cast<std::uint64_t>(last) + ahead > 0xFFFFFFFFull) return CounterCheck::spent;
  out = last + ahead;
  return CounterCheck::fresh;
}

// The ground's half: signs frames for one vehicle in one of its sessions.
class Signer {
 public:
  explicit Signer(const Key& key, MacFunction mac = siphash24) : key_(key), mac_(mac) {}

  // Starts signing for the vehicle session `nonce`, above the vehicle's last accepted counter.
  void start_session(std::uint32_t nonce, std::uint32_t last_counter) {
    session_ = session_key(key_, nonce, mac_);
    nonce_ = nonce;
    next_ = last_counter + 1u;
    active_ = last_counter != 0xFFFFFFFFu;
  }
  bool active() const { return active_; }
  std::uint32_t nonce() const { return nonce_; }
  std::uint32_t next_counter() const { return next_; }

  // The AUTH frame to send right after `frame` (to the same node). False before a session
  // starts or once its counters are spent.
  bool sign(const proto::Frame& frame, proto::Frame& auth) {
    if (!active_) return false;
    const proto::Auth a{static_cast<std::uint16_t>(next_), tag(session_, next_, frame, mac_)};
    if (!proto::encode(a, proto::id_node(frame.id), auth)) return false;
    if (next_ == 0xFFFFFFFFu) active_ = false;
    else ++next_;
    return true;
  }

 private:
  Key key_;
  MacFunction mac_;
  Key session_{};
  std::uint32_t nonce_ = 0;
  std::uint32_t next_ = 1;
  bool active_ = false;
};

}  // namespace pa::auth
