#include "groundstation/runtime/frame_interval.hpp"

#include <algorithm>

namespace gs::runtime {

double frame_interval_s(std::optional<double> last_s, double now_s, const FrameIntervalSettings& settings) {
  return last_s ? std::clamp(now_s - *last_s, 0.0, settings.max_s) : settings.first_s;
}

}  // namespace gs::runtime
