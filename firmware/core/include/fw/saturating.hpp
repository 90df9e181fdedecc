// Saturating counters and narrowing casts for telemetry fields: a count that outgrows its field
// reads as the field's maximum instead of wrapping to a small, plausible number.
#pragma once

#include <cstdint>
#include <limits>
#include <type_traits>

namespace fw {

// `value`, or To's maximum when it does not fit (unsigned types only: counts and durations).
template <class To, class From>
constexpr To saturate_cast(From value) {
  static_assert(std::is_unsigned_v<To> && std::is_unsigned_v<From>, "counts are unsigned");
  constexpr To kMax = std::numeric_limits<To>::max();
  if constexpr (std::numeric_limits<From>::max() <= kMax) return static_cast<To>(value);
  else return value > kMax ? kMax : static_cast<To>(value);
}

// ++count, stopping at the type's maximum.
template <class T>
constexpr void saturating_increment(T& count) {
  static_assert(std::is_unsigned_v<T>, "counts are unsigned");
  if (count != std::numeric_limits<T>::max()) ++count;
}

}  // namespace fw
