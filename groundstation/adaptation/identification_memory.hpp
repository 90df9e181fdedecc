// The motors' identification each vehicle flies with, kept from one take-off to the next and,
// with the adaptation store, from one run to the next (issue 25: "a failed fit is refused with a
// clear reason and the previous identification is kept").
//
// What it decides, per vehicle (by pa::VehicleId):
// - kept(): the last accepted identification. It starts as the store's last accepted one for the
//   vehicle (none without a store or before its first); an accepted fit replaces it, a refused
//   one leaves it in place.
// - lag_at_arming(): the motor time constant to set on board as the vehicle arms, before this
//   take-off's own fit: the kept one, when it differs from the firmware's design lag by more than
//   the tolerance (the fit's own accuracy, GroundStationConfig::motor_lag_tolerance_fraction).
//   Sent at every arming, not only when the ground station believes the equaliser differs: a
//   vehicle switched off since (a battery swap) has forgotten it, and the command is idempotent.
// - finished(): a take-off's fit is recorded (the store's `identifications`, accepted or refused,
//   with the vehicle's thrust gain at that moment when it had been measured) and, when accepted
//   and different from what the equaliser is set to by more than the tolerance, its lag is the
//   one to set on board now.
// - inertia_scale_to_set(): the same for the rate loop's inertia, at arming (against the file's)
//   and after each fit (against what is set), with the same tolerance.
// A result that cannot be stored (a non-finite fit) is neither kept nor set. The store is the
// same file as the learner's (a second SQLite connection: each write is its own transaction).
// Time-free: the runtime hands it the results and the time.
#pragma once

#include <array>
#include <optional>
#include <string>

#include "groundstation/adaptation/adaptation_law.hpp"
#include "groundstation/adaptation/adaptation_store.hpp"
#include "groundstation/adaptation/identification_record.hpp"

namespace gs::adaptation {

struct IdentificationMemorySettings {
  double design_time_constant_s = 0.03;  // the airframe's lag, which the firmware starts with
  double tolerance_fraction = 0.1;       // of the lag or inertia scale to set
  // The rate loop's inertia is only ever lowered to a vehicle's own, never raised above the
  // airframe file's. A loop whose J is above the vehicle's has a higher gain (J_used / J_true)
  // and rang with the throw's TV-LQR; one below it is slower and flew the act as well as the
  // design's. Measured (hil campaign --attempts 1000 on the arena envelope, throwers' inertia
  // 0.8-0.88 of the file's / 1.04-1.2): unequalised 159 of 217 / 354 of 395 caught; equalised
  // both ways 189 / 335; lowered only 190 / 354 (891 of 1000 in all, 855 unequalised).
  double max_inertia_scale = 1.0;
};

class IdentificationMemory {
 public:
  // In memory only when `store_path` is empty; else opens (or creates, with `adaptation`) the
  // store and starts from its last accepted identifications. Throws StoreError.
  IdentificationMemory(const IdentificationMemorySettings& settings, const std::string& store_path,
                       const AdaptationSettings& adaptation);

  const std::optional<estimation::MotorIdentification>& kept(pa::VehicleId vehicle) const;
  std::optional<double> lag_at_arming(pa::VehicleId vehicle) const;
  // Records the fit finished at `now_s` and returns the lag to set on board now, if any.
  // `equalised_s`: what the vehicle's equaliser is set to as far as the ground station knows.
  // Throws StoreError when the store cannot be written.
  std::optional<double> finished(pa::VehicleId vehicle, const estimation::IdentificationResult& result,
                                 std::optional<double> thrust_gain, double now_s, double equalised_s);
  // The rate loop's inertia scale to set on board (J_true / J_file, the kept fit's 1 / g) when it
  // differs from `on_board` (1 as the vehicle arms) by more than the tolerance, if any.
  std::optional<double> inertia_scale_to_set(pa::VehicleId vehicle, double on_board) const;

 private:
  // By node (std::out_of_range for a node no vehicle may have).
  std::optional<estimation::MotorIdentification>& slot(pa::VehicleId vehicle);
  bool differs(double lag_s, double from_s) const;

  IdentificationMemorySettings settings_;
  std::optional<AdaptationStore> store_;
  std::array<std::optional<estimation::MotorIdentification>, pa::proto::kLastVehicleNode + 1> kept_;
};

}  // namespace gs::adaptation
