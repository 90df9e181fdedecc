#include "hil/run/plant_exchange.hpp"

#include <stdexcept>
#include <string>
#include <utility>

#include "hil/run/hil_frames.hpp"
#include "hil/run/radio_routing.hpp"
#include "pa/constants.hpp"

namespace hil::run {

using pa::proto::Frame;

namespace {

// Times built from whole nanoseconds and sums of latencies land a rounding error off the
// millisecond grid; well below any period, this keeps a frame due on the grid on its step.
constexpr double kGridTolerance_s = 1e-9;

}  // namespace

PlantExchange::PlantExchange(const PlantConfig& plant, const RadioConfig& radio, std::uint64_t seed,
                             std::size_t vehicles)
    : plant_(plant, seed), period_s_(1.0 / static_cast<double>(plant.imu.rate_Hz)) {
  if (plant.imu.rate_Hz != static_cast<int>(pa::kImuRate_Hz))
    throw std::invalid_argument("the firmware runs on a " + std::to_string(pa::kImuRate_Hz) +
                                " Hz IMU; the plant's imu_rate_Hz is " + std::to_string(plant.imu.rate_Hz));
  if (vehicles < 1 || vehicles > pa::kActVehicles.size())
    throw std::invalid_argument("the arena flies 1 or 2 vehicles, not " + std::to_string(vehicles));
  links_.reserve(vehicles);
  for (std::size_t i = 0; i < vehicles; ++i)
    links_.emplace_back(arena_radio_config(radio, seed, pa::kActVehicles[i]));
}

PlantExchange::Link* PlantExchange::link(pa::VehicleId vehicle) {
  if (!pa::is_act_vehicle(vehicle) || pa::act_slot(vehicle) >= links_.size()) return nullptr;
  return &links_[pa::act_slot(vehicle)];
}

VehicleExchangeCounters PlantExchange::counters(pa::VehicleId vehicle) const {
  if (!pa::is_act_vehicle(vehicle) || pa::act_slot(vehicle) >= links_.size())
    throw std::out_of_range("no vehicle with node " + std::to_string(vehicle.node()) + " runs here");
  const Link& l = links_[pa::act_slot(vehicle)];
  VehicleExchangeCounters c = l.counters;
  c.uplink_lost = l.bridge.lost(Side::ground);
  c.downlink_lost = l.bridge.lost(Side::vehicle);
  return c;
}

void PlantExchange::on_ground_frame(const Frame& frame) {
  pa::proto::Message m;
  if (pa::proto::id_type(frame.id) == static_cast<std::uint8_t>(pa::proto::Type::hil_clock_done)) {
    if (pa::proto::decode(frame, m) == pa::proto::DecodeStatus::ok) {
      ground_released_ = false;  // it answers: it is awaited again
      if (ground_awaited_ && m.hil_clock_done.step == *ground_awaited_) {
        ground_awaited_.reset();
        ++ground_counters_.answered;
      } else {
        ++ground_counters_.other_answers;
      }
      return;
    }
  }
  const std::array<bool, 2> carrying = radios_carrying(frame);
  bool carried = false;
  for (std::size_t v = 0; v < links_.size(); ++v) {
    if (!carrying[v] || !radio_carries(frame)) continue;
    links_[v].bridge.offer(Side::ground, frame, t_s());
    ++links_[v].counters.uplink_offered;
    carried = true;
  }
  if (!carried) ++ground_not_carried_;
}

void PlantExchange::on_vehicle_frame(pa::VehicleId vehicle, const Frame& frame) {
  Link* l = link(vehicle);
  if (l == nullptr) return;
  if (radio_carries(frame)) {
    l->bridge.offer(Side::vehicle, frame, t_s());
    ++l->counters.downlink_offered;
    return;
  }
  // The answer only counts for the sample awaited; one for an earlier sample is late.
  const std::uint16_t tick = l->awaited_tick.value_or(0);
  switch (read_hil_motors(frame, vehicle.node(), tick, motors_[pa::act_slot(vehicle)])) {
    case MotorsAnswer::answer:
      l->released = false;  // back (restarted): waited for again
      if (l->awaited_tick) {
        ++l->counters.answered;
        l->awaited_tick.reset();
      } else {
        ++l->counters.late_answers;  // a repeat (after a resend): the commands are the same
      }
      break;
    case MotorsAnswer::other_tick: ++l->counters.late_answers; break;
    case MotorsAnswer::not_motors: ++l->counters.not_carried; break;
  }
}

bool PlantExchange::answered() const {
  for (const Link& l : links_)
    if (l.awaited_tick && !l.released) return false;
  return !awaiting_ground();
}

void PlantExchange::resend_unanswered() {
  for (Link& l : links_) {
    if (!l.awaited_tick) continue;
    l.outbox.insert(l.outbox.end(), l.sample.begin(), l.sample.end());
    ++l.counters.samples_resent;
  }
  if (awaiting_ground()) send_ground_clock();
}

void PlantExchange::hand_pole_to(pa::VehicleId thrower, const Vec3& origin_m) {
  if (!pa::is_act_vehicle(thrower)) return;
  pole_for_ = PoleWanted{thrower, origin_m};
}

void PlantExchange::show_waiting_for_pole(pa::VehicleId vehicle, bool waiting) {
  if (pa::is_act_vehicle(vehicle)) waiting_for_pole_[pa::act_slot(vehicle)] = waiting;
}

void PlantExchange::hand_pole_when_ready() {
  if (!pole_for_ || !waiting_for_pole_[pa::act_slot(pole_for_->thrower)]) return;
  const pa::VehicleId thrower = pole_for_->thrower;
  const bool at_origin = (plant_.plate_centre_m(thrower) - pole_for_->origin_m).norm() < kAtOrigin_m;
  if (!at_origin || plant_.vehicle(thrower).body.velocity_mps.norm() >= kStillSpeed_mps) return;
  plant_.place_pole_on(thrower);
  ++poles_handed_;
  pole_for_.reset();
}

void PlantExchange::release_vehicle(pa::VehicleId vehicle) {
  Link* l = link(vehicle);
  if (l == nullptr || l->released) return;
  l->released = true;
  ++l->counters.released;
}

bool PlantExchange::vehicle_released(pa::VehicleId vehicle) const {
  return pa::is_act_vehicle(vehicle) && pa::act_slot(vehicle) < links_.size() &&
         links_[pa::act_slot(vehicle)].released;
}

bool PlantExchange::awaiting_vehicle(pa::VehicleId vehicle) const {
  if (!pa::is_act_vehicle(vehicle) || pa::act_slot(vehicle) >= links_.size()) return false;
  const Link& l = links_[pa::act_slot(vehicle)];
  return l.awaited_tick.has_value() && !l.released;
}

bool PlantExchange::vehicle_answered_once(pa::VehicleId vehicle) const {
  return pa::is_act_vehicle(vehicle) && pa::act_slot(vehicle) < links_.size() &&
         links_[pa::act_slot(vehicle)].counters.answered > 0;
}

void PlantExchange::release_ground() {
  if (!ground_released_) ++ground_counters_.released;
  ground_released_ = true;
}

void PlantExchange::send_ground_clock() {
  Frame f;
  pa::proto::encode(
      pa::proto::HilClock{static_cast<std::uint32_t>(steps_), static_cast<std::uint32_t>(mocap_delivered_)},
      pa::proto::kGroundNode, f);
  ground_.push_back(f);
  ++ground_counters_.clocks_sent;
}

void PlantExchange::step() {
  Frame f;
  const double start = t_s() + kGridTolerance_s;
  for (Link& l : links_) {
    while (l.bridge.deliver(Side::vehicle, start, f)) {
      if (uplink_silent_) continue;
      l.outbox.push_back(f);
      ++l.counters.uplink_delivered;
    }
    if (l.released) {
      l.awaited_tick.reset();
    } else if (l.awaited_tick) {
      ++l.counters.missed;
      l.awaited_tick.reset();
    }
  }
  for (std::size_t v = 0; v < links_.size(); ++v)
    if (links_[v].released) motors_[v] = MotorCommands{};

  hand_pole_when_ready();
  plant_.step(period_s_, motors_[0], motors_[1]);
  const double t_end = t_s();
  const bool losses = plant_.losses_active();
  for (Link& l : links_) l.bridge.set_losses_active(losses);

  for (const pa::VehicleId v : pa::kActVehicles) {
    Link* l = link(v);
    ImuSample sample;
    while (plant_.pop_imu(v, sample)) {
      if (l == nullptr) continue;  // no firmware: the queue must not grow
      if (const auto battery = hil_battery_frame(plant_, v, sample)) l->outbox.push_back(*battery);
      l->sample = hil_imu_frames(sample, v.node());
      l->outbox.insert(l->outbox.end(), l->sample.begin(), l->sample.end());
      l->awaited_tick = hil_tick(sample);
      ++l->counters.samples_sent;
    }
    VehicleTruthSummary& truth = truth_[pa::act_slot(v)];
    const double z = plant_.vehicle(v).body.position_m.z();
    if (z > truth.highest_m) truth.highest_m = z;
    if (z > VehicleTruthSummary::kAirborneHeight_m) truth.airborne_s += period_s_;
  }

  for (Link& l : links_) {
    while (l.bridge.deliver(Side::ground, t_end + kGridTolerance_s, f)) {
      ground_.push_back(f);
      ++l.counters.downlink_delivered;
    }
  }
  CapturedFrame m;
  while (plant_.pop_mocap(m)) {
    mocap_.push_back(m);
    ++mocap_delivered_;
  }
  ++steps_;
  if (ground_clock_) {
    ground_awaited_ = static_cast<std::uint32_t>(steps_);
    send_ground_clock();
  }
}

std::vector<Frame> PlantExchange::take_vehicle_frames(pa::VehicleId vehicle) {
  Link* l = link(vehicle);
  return l != nullptr ? std::exchange(l->outbox, {}) : std::vector<Frame>{};
}

std::vector<Frame> PlantExchange::take_ground_frames() { return std::exchange(ground_, {}); }

std::vector<CapturedFrame> PlantExchange::take_mocap() { return std::exchange(mocap_, {}); }

}  // namespace hil::run
