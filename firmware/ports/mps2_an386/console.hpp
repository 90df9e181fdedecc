// A line-at-a-time console over semihosting with its own number formatting, so the image
// needs no printf (newlib-nano's pulls in malloc through its stdio buffers).
#pragma once

#include <cstddef>
#include <cstdint>

namespace mps2 {

// Builds one line in a fixed buffer; emit() appends the newline and writes it. Text that
// does not fit is cut, never written past the buffer.
class ConsoleLine {
 public:
  ConsoleLine& text(const char* s);
  ConsoleLine& u32(std::uint32_t v);
  ConsoleLine& i32(std::int32_t v);
  ConsoleLine& u64(std::uint64_t v);
  // Fixed-point with `decimals` digits (0..6), rounded half away from zero; "nan"/"inf"
  // for non-finite values and "overflow" beyond 1e15.
  ConsoleLine& fixed(float v, int decimals);
  void emit();

 private:
  void put(char c);

  static constexpr std::size_t kCapacity = 120;
  char buffer_[kCapacity + 2]{};  // room for '\n' and NUL
  std::size_t length_ = 0;
};

}  // namespace mps2
