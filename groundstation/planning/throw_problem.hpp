// The optimal throw, problem (34) of the paper (Section III-A): the planar quadrocopter-pole
// model driven from hover with the pole upright to a launch state at which the pole leaves the
// plate (F_N = 0), over a fixed duration T, minimising
//   J = int_0^T w_alpha alpha^2 + w_thrust (a_q - g)^2 + w_rate Omega_y^2 dt,
// with the inputs in the box of eq. (1), (2) and the pole pressed onto the plate (F_N >= 0)
// throughout.
#pragma once

#include <string>

#include "groundstation/model/planar_pole_vehicle.hpp"
#include "groundstation/model/vehicle_limits.hpp"

namespace gs::planning {

// The weights of eq. (34): 1.5 alpha^2 + (a_q - g)^2 + 8 Omega_y^2.
struct ThrowCostWeights {
  double alpha = 1.5;
  double thrust = 1.0;
  double pitch_rate = 8.0;
};

struct ThrowProblem {
  double duration_s = 2.5;  // T of Fig. 5
  // The launch state s_qp,T of Fig. 5 and the pitch rate of u_q,T; the launch thrust is not a
  // free design value: launch_thrust_mps2() solves F_N(s_T, u_T) = 0 for it.
  model::PlanarState<double> launch_state = figure5_launch_state();
  double launch_pitch_rate_radps = 2.5;
  ThrowCostWeights weights;
  // Input slew limits, not in (34): without them the optimum jumps to the fixed launch input at
  // T (from about (11.2 m/s^2, -2.8 rad/s) to (4.8 m/s^2, +2.5 rad/s) in the last millisecond),
  // which no vehicle flies: the motors' thrust lags (30 ms) and spins down no faster than it
  // lags, and the pitch rate changes only as fast as differential thrust allows. Flown on the
  // truth plant, such a plan leaves the pole sliding on the plate for 0.1 s after T. The bounds
  // hold between consecutive collocation points; 0 turns one off (the paper's problem).
  double thrust_rate_max_mps3 = 100.0;
  double pitch_acceleration_max_radps2 = 60.0;
  model::VehicleLimits limits = default_limits();
  model::PlanarPoleVehicleParams params;

  // (x, z) = (1.5, 2.0) m, (vx, vz) = (0.3, 5.5) m/s, theta = -0.48 rad, alpha = 0.48 rad,
  // alpha' = 2.5 rad/s (Fig. 5 caption).
  static model::PlanarState<double> figure5_launch_state();
  // The values of groundstation/config/vehicle_limits.yaml (a_q in [1, 20] m/s^2,
  // |Omega| <= 10 rad/s), for callers that do not load the file.
  static model::VehicleLimits default_limits();

  // a_q,T with F_N(s_T, (a_q,T, Omega_T)) = 0 exactly (the printed figure says 4.48 m/s^2,
  // which leaves F_N = -0.16 m/s^2 in the derived model; see planar_pole_vehicle.hpp).
  double launch_thrust_mps2() const;
  model::PlanarInput<double> launch_input() const;
  // Hover at the origin with the pole upright: s(0) = 0, u(0) = (g, 0).
  model::PlanarInput<double> hover_input() const;

  // Empty when the problem is well posed, else what is wrong with it (non-positive duration,
  // limits violated by the fixed end inputs, a launch thrust outside the limits, ...).
  std::string validate() const;
};

}  // namespace gs::planning
