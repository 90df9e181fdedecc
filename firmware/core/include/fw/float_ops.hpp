// Small float helpers of the 1 kHz loop. They are forced inline: at -Os GCC would otherwise
// call them, and a call costs more instructions than their bodies.
#pragma once

#include <cmath>

#include "fw/types.hpp"

namespace fw {

[[gnu::always_inline]] inline float clampf(float v, float lo, float hi) {
  return v < lo ? lo : (v > hi ? hi : v);
}

// clampf(v, -limit, limit), with the usual case (already inside) decided by one comparison.
[[gnu::always_inline]] inline float clamp_symmetric(float v, float limit) {
  return std::fabs(v) <= limit ? v : clampf(v, -limit, limit);
}

// Zero when the values are finite, NaN otherwise: x * 0 is 0 for a finite x and NaN for a NaN or
// an infinity, and a NaN survives a sum. Summing markers checks many values with one comparison
// (`!(sum == 0.0f)` is true for a NaN), cheaper than classifying each value (a multiply-add per
// value on the Cortex-M4). This needs IEEE semantics: never build the firmware with
// -ffinite-math-only (or -ffast-math), which would fold x * 0 to 0.
[[gnu::always_inline]] inline float nonfinite_marker(float v) { return v * 0.0f; }
[[gnu::always_inline]] inline float nonfinite_marker(const Vec3f& v) {
  return v[0] * 0.0f + v[1] * 0.0f + v[2] * 0.0f;
}

// |v[i]| <= limit for every component; false for NaN and the infinities, so it is also the
// finiteness check. A sum inside the limit decides the usual case with one comparison (each
// magnitude is at most the rounded sum of the non-negative magnitudes).
[[gnu::always_inline]] inline bool all_within(const Vec3f& v, float limit) {
  if (std::fabs(v[0]) + std::fabs(v[1]) + std::fabs(v[2]) <= limit) return true;
  return std::fabs(v[0]) <= limit && std::fabs(v[1]) <= limit && std::fabs(v[2]) <= limit;
}

}  // namespace fw
