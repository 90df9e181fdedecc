// The optimal catching instant, Section III-B: the pole flies freely (eq. 20, with drag) from
// the launch until the first instant at which the catching condition (42) holds, i.e. at which a
// vehicle at rest catching the pole's lower end would leave it with exactly the energy to swing
// up to the upright by itself (41). The lower end's height then is the nominal catching height.
// Sign convention and the derivation of (42): groundstation/model/impact.hpp.
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include <Eigen/Dense>

#include "groundstation/model/planar_pole_vehicle.hpp"
#include "groundstation/model/pole_free_flight.hpp"

namespace gs::planning {

// The throwing vehicle's planar state at the launch (the end state of the throw, Fig. 5), in
// the xz-plane at y = 0: vehicle position and velocity, pole tilt alpha from the vertical
// (positive towards +x) and its rate. The pole pivots at the vehicle's centre (eq. 23).
struct PlanarLaunchState {
  double x_m = 0.0;
  double z_m = 0.0;
  double vx_mps = 0.0;
  double vz_mps = 0.0;
  double alpha_rad = 0.0;
  double alpha_dot_radps = 0.0;
};

// The launch components of a planar state (theta aside): the vehicle and pole at a throw's end.
PlanarLaunchState launch_state_of(const model::PlanarState<double>& s);

// The end state printed with Fig. 5: (x, z) = (1.5, 2.0) m, (x', z') = (0.3, 5.5) m/s,
// alpha = 0.48 rad, alpha' = 2.5 rad/s.
PlanarLaunchState fig5_launch_state();

// The pole's free-flight state right after leaving the vehicle: centre p_q + L n (23) with
// n = (sin alpha, 0, cos alpha), centre velocity p_q' + L n' (26), Omega = (0, alpha', 0) (27).
model::PoleState pole_state_at_launch(const PlanarLaunchState& launch, const model::PoleParams& params);

// The launch state from the throw planner's CSV (`groundstation plan-throw`, DIR/throw.csv): a
// header row naming the columns t,x,z,vx,vz,theta,alpha,alpha_dot,a_q,omega_y,F_N (any order,
// extra columns allowed), then rows of finite numbers with as many fields as the header. The
// last row is the end of the throw, i.e. the launch. Never throws; errors name source:line.
struct LaunchStateLoad {
  bool ok = false;
  PlanarLaunchState launch;
  int line = 0;       // the row the launch state came from (1-based)
  std::string error;  // when !ok
};
LaunchStateLoad parse_throw_csv_launch_state(std::string_view text, std::string_view source_name);
LaunchStateLoad load_throw_csv_launch_state(const std::string& path);

struct CatchingInstantOptions {
  double step_s = 0.005;            // RK4 step of the free-flight simulation
  double horizon_s = 3.0;           // give up after this much flight
  double time_tolerance_s = 1e-10;  // bisection stops below this bracket width
  // The vertical plane (42) is judged in (model::flight_plane_yaw_rad); unset: the plane of the
  // state the search starts from. A search that continues an observed flight passes the plane of
  // the flight's start, so that both judge alike.
  std::optional<double> plane_yaw_rad;
};

struct CatchingInstant {
  bool found = false;
  double t_s = 0.0;             // time after launch
  double catch_height_m = 0.0;  // z of the lower pole end: the nominal catching height
  Eigen::Vector2d catch_point_m = Eigen::Vector2d::Zero();  // (x, y) of the lower end
  model::PoleState pole;                                    // the pole just before the impact
  double residual_radps = 0.0;                              // eq. (42) at t_s (impact.hpp's form)
};

// Simulates the free flight from `launch` and returns the first instant satisfying (42).
// A sign change of (42) across the instant the pole passes the horizontal (where the other end
// becomes the lower one and alpha jumps by pi) is not a root and is skipped.
CatchingInstant find_catching_instant(const model::PoleState& launch, const model::PoleParams& params,
                                      const CatchingInstantOptions& options = {});

}  // namespace gs::planning
