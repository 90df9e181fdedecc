// What the mps2-an386 start-up code tells the rest of the image.
#pragma once

#include <cstdint>

namespace mps2 {

// The main stack reserved by the linker script (counted in the image's RAM figure).
std::uint32_t stack_size_bytes();

// The stack's high-water mark so far: start-up paints the unused stack with a pattern and
// this finds the deepest word overwritten.
std::uint32_t stack_used_bytes();

}  // namespace mps2
