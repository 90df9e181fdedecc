#include "fw/battery_compensation.hpp"

#include <cmath>

#include "fw/float_ops.hpp"
#include "fw/saturating.hpp"
#include "pa/sequence.hpp"

namespace fw {

BatteryCompensation::BatteryCompensation(const BatteryConfig& config) {
  const float v_ref = config.reference_voltage_V;
  // Not finite, zero or negative, or beyond what a reading can carry: compensation is off.
  configured_ = std::isfinite(v_ref) && v_ref > 0.0f && v_ref * kValidMin <= 65.535f;
  if (!configured_) return;
  reference_V_ = v_ref;
  valid_min_V_ = v_ref * kValidMin;
  valid_max_V_ = v_ref * kValidMax;
}

void BatteryCompensation::drop() {
  active_ = false;
  factor_ = 1.0f;
  filtered_mv_ = 0;
}

bool BatteryCompensation::on_voltage_mv(std::uint16_t voltage_mv, std::uint32_t now_us) {
  if (!configured_) return false;
  // A division, not a multiply by 0.001f: a reading of V_ref in mV gives V_ref exactly (the
  // nearest float to both), and with it a factor of exactly 1.
  const float v = static_cast<float>(voltage_mv) / 1000.0f;
  if (v < valid_min_V_ || v > valid_max_V_) {
    saturating_increment(rejected_);
    return false;
  }
  const float before = factor_;
  const std::int32_t step_us = pa::elapsed_us(now_us, last_us_);
  if (!active_ || step_us < 0 || static_cast<float>(step_us) * 1e-6f > kDtMax_s) {
    filtered_V_ = v;  // the first reading, or the first after a gap: the filter starts there
  } else {
    const float dt_s = clampf(static_cast<float>(step_us) * 1e-6f, kDtMin_s, kDtMax_s);
    filtered_V_ += (v - filtered_V_) * (dt_s / (kFilterTime_s + dt_s));
  }
  active_ = true;
  last_us_ = now_us;
  const float ratio = reference_V_ / filtered_V_;
  factor_ = ratio * ratio < kFactorMax ? ratio * ratio : kFactorMax;
  filtered_mv_ = static_cast<std::uint16_t>(filtered_V_ * 1000.0f + 0.5f);  // within 0..65535 mV
  return factor_ != before;
}

bool BatteryCompensation::check_stale(std::uint32_t now_us) {
  if (!active_ || pa::elapsed_us(now_us, last_us_) <= static_cast<std::int32_t>(kStale_us)) return false;
  const bool changed = factor_ != 1.0f;
  drop();
  return changed;
}

}  // namespace fw
