// Physical constants and arena-wide figures shared by the firmware, the ground station
// and the HIL plant. Values given by the paper cite it; the rest are documented choices.
// Freestanding: no heap, no exceptions, no OS.
#pragma once

namespace pa {

inline constexpr double kGravity_mps2 = 9.81;
// The same in float, for the firmware's single-precision FPU.
inline constexpr float kGravityFloat_mps2 = 9.81f;
static_assert(kGravityFloat_mps2 == static_cast<float>(kGravity_mps2));

// The pole (paper, Section VII-A).
inline constexpr double kPoleHalfLength_m = 0.665;  // 2L = 1.33 m
inline constexpr double kPoleMass_kg = 0.03;
inline constexpr double kPoleDragAxial = 0.5e-3;       // c_z, kg/m^2 (0.5 g m^-2)
inline constexpr double kPoleDragNormal = 3.5e-3;      // c_xy
inline constexpr double kPoleDragRotational = 2.1e-3;  // c_rot

// The catching plate (paper, Section VII-A).
inline constexpr double kPlateDiameter_m = 0.12;
inline constexpr double kPlateHeightAboveCg_m = 0.03;

// Loop rates (docs/architecture.md, "One tick of the system").
inline constexpr unsigned kImuRate_Hz = 1000;
inline constexpr unsigned kMocapRate_Hz = 200;
inline constexpr unsigned kImuPeriod_us = 1000000u / kImuRate_Hz;

// The vehicle's periodic frames (docs/protocol.md): what its firmware sends by default
// (fw::LinkConfig) and what the ground station's radio link budget counts.
inline constexpr unsigned kLinkSessionPeriod_us = 100000;       // LINK_SESSION, 10 Hz
inline constexpr unsigned kVehicleHeartbeatPeriod_us = 20000;   // VEHICLE_HEARTBEAT, 50 Hz
inline constexpr unsigned kTelemetryRatesPeriod_us = 5000;      // 200 Hz
inline constexpr unsigned kTelemetryAttitudePeriod_us = 10000;  // 100 Hz
inline constexpr unsigned kTelemetryMotorsPeriod_us = 10000;    // 100 Hz
inline constexpr unsigned kTelemetryStatusPeriod_us = 100000;   // 10 Hz

}  // namespace pa
