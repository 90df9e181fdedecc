// What a filter's prediction propagates. The estimator's own updates need the covariances (the
// next correction weighs by them); latency compensation only needs the state at the time a
// command will act, and the covariance propagation is most of a prediction's cost (the
// free-flight EKF's 13 x 13 congruence per 5 ms step), so it skips it.
#pragma once

#include <cstdint>

namespace gs::estimation {

enum class Propagation : std::uint8_t {
  mean_and_covariance,
  mean_only,  // the covariance is left as it was
};

}  // namespace gs::estimation
