// Forwarding header, for tests/bench/runtime/closed_loop_bench.cpp only: the series moved to the
// trials (hil/trials/series.hpp, namespace hil::trials). Remove once the benchmark names them there.
#pragma once

#include "hil/trials/series.hpp"

namespace hil::sil {

using trials::catch_series;
using trials::SeriesConfig;
using trials::SeriesRunner;

}  // namespace hil::sil
