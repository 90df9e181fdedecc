// The vehicle-bus frames (pa::proto::Frame: 11-bit identifier, 0-8 bytes) over a byte stream,
// for a transparent radio modem on a serial line: the one framing both ends use (the flight
// image on its UART, the ground station on the modem's port, groundstation/service/radio_bus.hpp):
//
//   0x7E | id low 8 bits | id high 3 bits + length << 4 | payload (length bytes) | CRC-8
//
// The CRC-8 (polynomial 0x07, initial 0) covers the header and payload after the sync byte. The
// decoder takes one byte at a time, hunts for the sync byte, and drops a frame with a bad
// header or CRC (counted) and hunts again, so line noise or a cut frame costs the frames it
// touches and no more. No heap; constant time per byte.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "pa/protocol.hpp"

namespace pa::serial_frame {

inline constexpr std::uint8_t kSync = 0x7E;
inline constexpr std::size_t kMaxBytes = 1 + 2 + pa::proto::kMaxPayload + 1;

// A table of the 256 byte remainders, built at compile time: one look-up per byte instead of
// eight shift-and-xor steps (the link encodes a frame for every frame the core sends).
constexpr std::array<std::uint8_t, 256> make_crc8_table() {
  std::array<std::uint8_t, 256> table{};
  for (unsigned i = 0; i < 256; ++i) {
    auto crc = static_cast<std::uint8_t>(i);
    for (int bit = 0; bit < 8; ++bit)
      crc = static_cast<std::uint8_t>((crc & 0x80u) != 0u ? (crc << 1) ^ 0x07u : crc << 1);
    table[i] = crc;
  }
  return table;
}
inline constexpr std::array<std::uint8_t, 256> kCrc8Table = make_crc8_table();

constexpr std::uint8_t crc8_update(std::uint8_t crc, std::uint8_t byte) {
  return kCrc8Table[static_cast<std::uint8_t>(crc ^ byte)];
}

// Writes the frame's bytes into `out`; returns how many (0 for an invalid frame).
constexpr std::size_t encode(const pa::proto::Frame& f, std::array<std::uint8_t, kMaxBytes>& out) {
  if (f.id > 0x7FFu || f.len > pa::proto::kMaxPayload) return 0;
  std::size_t n = 0;
  out[n++] = kSync;
  out[n++] = static_cast<std::uint8_t>(f.id & 0xFFu);
  out[n++] = static_cast<std::uint8_t>((f.id >> 8) | (f.len << 4));
  for (std::uint8_t i = 0; i < f.len; ++i) out[n++] = f.data[i];
  std::uint8_t crc = 0;
  for (std::size_t i = 1; i < n; ++i) crc = crc8_update(crc, out[i]);
  out[n++] = crc;
  return n;
}

struct DecoderStats {
  std::uint32_t frames = 0;
  std::uint32_t crc_errors = 0;
  std::uint32_t bad_headers = 0;  // reserved bit set or length above 8
};

class Decoder {
 public:
  // Feeds one byte; true when it completed a valid frame (then in `out`).
  bool push(std::uint8_t byte, pa::proto::Frame& out) {
    switch (state_) {
      case State::hunt:
        if (byte == kSync) {
          state_ = State::id_low;
          crc_ = 0;
        }
        return false;
      case State::id_low:
        frame_.id = byte;
        crc_ = crc8_update(crc_, byte);
        state_ = State::id_high_len;
        return false;
      case State::id_high_len: {
        const auto len = static_cast<std::uint8_t>(byte >> 4);
        if ((byte & 0x08u) != 0u || len > pa::proto::kMaxPayload) {
          ++stats_.bad_headers;
          state_ = byte == kSync ? State::id_low : State::hunt;
          crc_ = 0;
          return false;
        }
        frame_.id = static_cast<std::uint16_t>(frame_.id | ((byte & 0x07u) << 8));
        frame_.len = len;
        frame_.data = {};
        crc_ = crc8_update(crc_, byte);
        got_ = 0;
        state_ = len == 0 ? State::crc : State::payload;
        return false;
      }
      case State::payload:
        frame_.data[got_++] = byte;
        crc_ = crc8_update(crc_, byte);
        if (got_ == frame_.len) state_ = State::crc;
        return false;
      case State::crc:
        state_ = State::hunt;
        if (byte != crc_) {
          ++stats_.crc_errors;
          return false;
        }
        ++stats_.frames;
        out = frame_;
        return true;
    }
    state_ = State::hunt;
    return false;
  }

  const DecoderStats& stats() const { return stats_; }

 private:
  enum class State : std::uint8_t { hunt, id_low, id_high_len, payload, crc };
  State state_ = State::hunt;
  pa::proto::Frame frame_{};
  std::uint8_t crc_ = 0;
  std::uint8_t got_ = 0;
  DecoderStats stats_{};
};

}  // namespace pa::serial_frame
