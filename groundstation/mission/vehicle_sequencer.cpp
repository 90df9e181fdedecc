#include "groundstation/mission/vehicle_sequencer.hpp"

namespace gs::mission {

std::string_view task_name(Task task) {
  switch (task) {
    case Task::parked: return "parked";
    case Task::arming: return "arming";
    case Task::take_off: return "take_off";
    case Task::hover: return "hover";
    case Task::balance: return "balance";
    case Task::throwing: return "throwing";
    case Task::release: return "release";
    case Task::retreat: return "retreat";
    case Task::wait: return "wait";
    case Task::catching: return "catching";
    case Task::rebalance: return "rebalance";
    case Task::clear: return "clear";
    case Task::landing: return "landing";
    case Task::failsafe: return "failsafe";
    case Task::descend: return "descend";
  }
  return "?";
}

std::string_view condition_name(int bit) {
  static constexpr std::array<std::string_view, condition::kCount> kNames = {
      "vehicle_lost",     "estimate_lost", "armed",        "on_ground",        "command_failed",
      "at_height",        "at_target",     "pole_on_self", "pole_free",        "pole_down",
      "pole_upright",     "throw_over",    "release_over", "catch_due",        "catch_unreachable",
      "catch_infeasible", "catch_missed",  "settled",      "request_take_off", "request_throw",
      "request_catch",    "request_abort", "request_land", "pole_fallen"};
  return bit >= 0 && bit < condition::kCount ? kNames[static_cast<std::size_t>(bit)] : "?";
}

std::string condition_names(std::uint32_t word) { return bit_names(word, condition::kCount, condition_name); }

std::string_view reason_name(Reason reason) {
  switch (reason) {
    case Reason::none: return "none";
    case Reason::vehicle_lost: return "vehicle_lost";
    case Reason::estimate_lost: return "estimate_lost";
    case Reason::vehicle_back: return "vehicle_back";
    case Reason::land_requested: return "land_requested";
    case Reason::landed: return "landed";
    case Reason::take_off_requested: return "take_off_requested";
    case Reason::armed: return "armed";
    case Reason::arm_failed: return "arm_failed";
    case Reason::airborne: return "airborne";
    case Reason::pole_placed: return "pole_placed";
    case Reason::pole_lost: return "pole_lost";
    case Reason::throw_requested: return "throw_requested";
    case Reason::throw_ended: return "throw_ended";
    case Reason::pole_left_early: return "pole_left_early";
    case Reason::released: return "released";
    case Reason::clear_of_pole: return "clear_of_pole";
    case Reason::catch_requested: return "catch_requested";
    case Reason::catch_started: return "catch_started";
    case Reason::out_of_reach: return "out_of_reach";
    case Reason::infeasible: return "infeasible";
    case Reason::abort_requested: return "abort_requested";
    case Reason::caught: return "caught";
    case Reason::missed: return "missed";
    case Reason::pole_upright: return "pole_upright";
    case Reason::pole_fallen: return "pole_fallen";
    case Reason::near_floor: return "near_floor";
    case Reason::pole_down: return "pole_down";
  }
  return "?";
}

const Transition* find_transition(Task task, std::uint32_t conditions) {
  return first_matching_row(kTransitions, task_bit(task), conditions);
}

bool VehicleSequencer::step(std::uint32_t conditions, double now_s) {
  conditions_ = conditions;
  const Transition* row = find_transition(task_, conditions);
  if (row == nullptr || row->to == task_) return false;
  task_ = row->to;
  since_s_ = now_s;
  reason_ = row->reason;
  return true;
}

void VehicleSequencer::reset(Task task, double now_s) {
  task_ = task;
  since_s_ = now_s;
  reason_ = Reason::none;
}

}  // namespace gs::mission
