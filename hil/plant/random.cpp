#include "hil/plant/random.hpp"

#include <cmath>
#include <numbers>

namespace hil {

namespace {
// splitmix64: spreads (seed, stream) over the whole state so nearby seeds give unrelated streams.
std::uint64_t mix(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}
}  // namespace

Random::Random(std::uint64_t seed, RandomStream stream)
    : engine_(mix(mix(seed) ^ (static_cast<std::uint64_t>(stream) * 0xD1B54A32D192ED03ull))) {}

double Random::uniform() {
  // The top 53 bits give every double in [0, 1) on a 2^-53 grid.
  return static_cast<double>(engine_() >> 11) * 0x1.0p-53;
}

double Random::uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }

double Random::gaussian() {
  // Box-Muller, keeping the second draw of each pair.
  if (have_spare_) {
    have_spare_ = false;
    return spare_;
  }
  const double u1 = 1.0 - uniform();  // (0, 1]: log is finite
  const double u2 = uniform();
  const double r = std::sqrt(-2.0 * std::log(u1));
  const double phi = 2.0 * std::numbers::pi * u2;
  spare_ = r * std::sin(phi);
  have_spare_ = true;
  return r * std::cos(phi);
}

}  // namespace hil
