#include "console.hpp"

#include <cmath>

#include "semihosting.hpp"

namespace mps2 {

void ConsoleLine::put(char c) {
  if (length_ < kCapacity) buffer_[length_++] = c;
}

ConsoleLine& ConsoleLine::text(const char* s) {
  while (s != nullptr && *s != '\0') put(*s++);
  return *this;
}

ConsoleLine& ConsoleLine::u64(std::uint64_t v) {
  char digits[20];
  int n = 0;
  do {
    digits[n++] = static_cast<char>('0' + v % 10u);
    v /= 10u;
  } while (v != 0u);
  while (n > 0) put(digits[--n]);
  return *this;
}

ConsoleLine& ConsoleLine::u32(std::uint32_t v) { return u64(v); }

ConsoleLine& ConsoleLine::i32(std::int32_t v) {
  if (v < 0) {
    put('-');
    return u64(static_cast<std::uint64_t>(-static_cast<std::int64_t>(v)));
  }
  return u64(static_cast<std::uint64_t>(v));
}

ConsoleLine& ConsoleLine::fixed(float v, int decimals) {
  if (std::isnan(v)) return text("nan");
  if (std::isinf(v)) return text(v < 0.0f ? "-inf" : "inf");
  if (decimals < 0) decimals = 0;
  if (decimals > 6) decimals = 6;
  const bool negative = v < 0.0f;
  const float magnitude = negative ? -v : v;
  if (magnitude >= 1e15f) return text("overflow");
  std::uint64_t scale = 1;
  for (int i = 0; i < decimals; ++i) scale *= 10u;
  const auto scaled = static_cast<std::uint64_t>(magnitude * static_cast<float>(scale) + 0.5f);
  if (negative && scaled != 0u) put('-');
  u64(scaled / scale);
  if (decimals > 0) {
    put('.');
    std::uint64_t frac = scaled % scale;
    for (std::uint64_t div = scale / 10u; div != 0u; div /= 10u) {
      put(static_cast<char>('0' + frac / div));
      frac %= div;
    }
  }
  return *this;
}

void ConsoleLine::emit() {
  buffer_[length_] = '\n';
  buffer_[length_ + 1] = '\0';
  semihosting::write0(buffer_);
  length_ = 0;
}

}  // namespace mps2
