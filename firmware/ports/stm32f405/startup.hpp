// What the STM32F405 start-up code tells the rest of the image.
#pragma once

#include <cstdint>

namespace stm32f405 {

// The main stack's high-water mark so far: start-up paints the unused stack with a pattern
// and this finds the deepest word overwritten (it scans only the untouched part).
std::uint32_t stack_used_bytes();

}  // namespace stm32f405
