// Which vehicle: the one identity of a vehicle from the plant to the wire.
//
// A vehicle is its CAN node id (protocol.hpp: 1..14; node 0 is the ground station, 15 is
// broadcast), so the plant's body, the firmware's configured node, the ground station's vehicle,
// the estimator's vehicle and a frame's node field are the same number and need no mapping. The
// act flies two vehicles, kVehicle1 (node 1, the first thrower) and kVehicle2 (node 2); state kept
// for each of them lives in two-element arrays indexed by act_slot().
//
// Freestanding (the firmware uses it): no heap, no exceptions.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "pa/protocol.hpp"

namespace pa {

class VehicleId {
 public:
  // Explicit: a bare number (a plant index, an array slot) never becomes a vehicle by accident.
  constexpr explicit VehicleId(std::uint8_t node) : node_(node) {}

  constexpr std::uint8_t node() const { return node_; }
  // A node a vehicle may have (not the ground station, not broadcast).
  constexpr bool valid() const {
    return node_ >= proto::kFirstVehicleNode && node_ <= proto::kLastVehicleNode;
  }

  friend constexpr bool operator==(VehicleId a, VehicleId b) { return a.node_ == b.node_; }
  friend constexpr bool operator!=(VehicleId a, VehicleId b) { return a.node_ != b.node_; }

 private:
  std::uint8_t node_;
};

inline constexpr VehicleId kVehicle1{1};
inline constexpr VehicleId kVehicle2{2};
inline constexpr std::array<VehicleId, 2> kActVehicles{kVehicle1, kVehicle2};

constexpr bool is_act_vehicle(VehicleId v) { return v == kVehicle1 || v == kVehicle2; }
// The vehicle's slot in a two-element array: kVehicle1 -> 0, kVehicle2 -> 1. Callers check
// is_act_vehicle() first where the id comes from outside (a frame, a file, an argument).
constexpr std::size_t act_slot(VehicleId v) { return v == kVehicle2 ? 1u : 0u; }
// The act's other vehicle (the catcher of a thrower's pole).
constexpr VehicleId other_vehicle(VehicleId v) { return v == kVehicle2 ? kVehicle1 : kVehicle2; }

}  // namespace pa
