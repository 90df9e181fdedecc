// Vehicle-bus frames over a serial line (pa/serial_frame.hpp): the byte layout, the CRC, and
// resynchronisation after noise.
#include <catch2/catch.hpp>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "pa/serial_frame.hpp"

namespace {

namespace sf = pa::serial_frame;
using pa::proto::Frame;

Frame make(std::uint16_t id, std::vector<std::uint8_t> payload) {
  Frame f;
  f.id = id;
  f.len = static_cast<std::uint8_t>(payload.size());
  for (std::size_t i = 0; i < payload.size(); ++i) f.data[i] = payload[i];
  return f;
}

std::vector<std::uint8_t> bytes_of(const Frame& f) {
  std::array<std::uint8_t, sf::kMaxBytes> out{};
  const std::size_t n = sf::encode(f, out);
  return {out.begin(), out.begin() + static_cast<std::ptrdiff_t>(n)};
}

std::vector<Frame> decode_all(sf::Decoder& d, const std::vector<std::uint8_t>& bytes) {
  std::vector<Frame> frames;
  Frame f;
  for (std::uint8_t b : bytes)
    if (d.push(b, f)) frames.push_back(f);
  return frames;
}

bool same(const Frame& a, const Frame& b) { return a.id == b.id && a.len == b.len && a.data == b.data; }

}  // namespace

TEST_CASE("crc-8 (0x07) of the standard check string") {
  std::uint8_t crc = 0;
  for (char c : std::string("123456789")) crc = sf::crc8_update(crc, static_cast<std::uint8_t>(c));
  CHECK(crc == 0xF4);
}

TEST_CASE("a frame's bytes: sync, identifier, length, payload, crc") {
  const Frame f = make(0x2B1, {0xAA, 0x55});
  const std::vector<std::uint8_t> b = bytes_of(f);
  REQUIRE(b.size() == 6);
  CHECK(b[0] == 0x7E);
  CHECK(b[1] == 0xB1);
  CHECK(b[2] == (0x02 | (2 << 4)));
  CHECK(b[3] == 0xAA);
  CHECK(b[4] == 0x55);
  std::uint8_t crc = 0;
  for (int i = 1; i < 5; ++i) crc = sf::crc8_update(crc, b[i]);
  CHECK(b[5] == crc);

  std::array<std::uint8_t, sf::kMaxBytes> out{};
  CHECK(sf::encode(make(0x800, {}), out) == 0);  // identifier beyond 11 bits
  Frame too_long = make(0x10, {});
  too_long.len = 9;
  CHECK(sf::encode(too_long, out) == 0);
}

TEST_CASE("frames survive the round trip, empty and full ones included") {
  const std::vector<Frame> sent = {make(0x0B1, {1, 2, 3, 4, 5, 6, 7, 8}), make(0x7FF, {}),
                                   make(0x0A0, {0x7E, 0x7E, 0x7E})};
  std::vector<std::uint8_t> stream;
  for (const Frame& f : sent) {
    const auto b = bytes_of(f);
    stream.insert(stream.end(), b.begin(), b.end());
  }
  sf::Decoder d;
  const std::vector<Frame> got = decode_all(d, stream);
  REQUIRE(got.size() == sent.size());
  for (std::size_t i = 0; i < sent.size(); ++i) CHECK(same(got[i], sent[i]));
  CHECK(d.stats().frames == 3);
}

TEST_CASE("noise, a corrupted frame and a bad header cost only themselves") {
  const Frame a = make(0x0B1, {1, 2, 3});
  const Frame b = make(0x131, {9, 8, 7, 6, 5, 4, 3, 2});
  std::vector<std::uint8_t> stream = {0x00, 0x13, 0xFF};  // line noise before anything
  auto corrupted = bytes_of(a);
  corrupted[4] ^= 0x01;
  stream.insert(stream.end(), corrupted.begin(), corrupted.end());
  stream.insert(stream.end(), {0x7E, 0x01, 0x98});  // length 9: a bad header
  const auto good_a = bytes_of(a), good_b = bytes_of(b);
  stream.insert(stream.end(), good_a.begin(), good_a.end());
  stream.insert(stream.end(), good_b.begin(), good_b.end());

  sf::Decoder d;
  const std::vector<Frame> got = decode_all(d, stream);
  REQUIRE(got.size() == 2);
  CHECK(same(got[0], a));
  CHECK(same(got[1], b));
  CHECK(d.stats().crc_errors == 1);
  CHECK(d.stats().bad_headers == 1);
}
