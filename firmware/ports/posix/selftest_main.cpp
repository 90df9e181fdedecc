// fw_selftest: the scripted self-test flight of the firmware core on the host, printed for a
// person (the same scenario the Cortex-M4 image flies in QEMU).
#include <cstdio>

#include "fw/selftest.hpp"

int main() {
  const fw::selftest::Result r = fw::selftest::run(nullptr);
  std::printf("firmware core, scripted flight on the host (%u ticks at 1 kHz)\n", r.ticks);
  std::printf("  hover: worst body-rate error            %.3f rad/s\n",
              static_cast<double>(r.hover_rate_error_max_radps));
  std::printf("  rate sines: tracking error (rms)        %.3f rad/s\n",
              static_cast<double>(r.manoeuvre_rate_error_rms_radps));
  std::printf("  pole impact: detected after             %.0f ms (timestamp off by %.0f ms)\n",
              static_cast<double>(r.impact_detection_latency_ms),
              static_cast<double>(r.impact_timestamp_error_ms));
  std::printf("  link loss: levelled hover after         %.0f ms\n",
              static_cast<double>(r.failsafe_hover_after_ms));
  std::printf("  link loss: descent after hovering       %.0f ms\n", static_cast<double>(r.descent_after_ms));
  std::printf("  link loss: motors off after touchdown   %.0f ms\n",
              static_cast<double>(r.motors_off_after_landing_ms));
  if (r.pass) {
    std::printf("selftest: pass\n");
    return 0;
  }
  std::printf("selftest: fail %s\n", r.failure);
  return 1;
}
