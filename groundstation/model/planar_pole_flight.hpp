// The pole's free flight (Section II-B-1, eq. (9)-(22)) in the vertical plane of a throw, templated
// on the scalar so that the target-throw planner differentiates the catching instant through it
// (throw_collocation_nlp.hpp). The 3D model (pole_free_flight.hpp) evaluates the drag integrals
// with branches between closed forms and a Gauss rule, which automatic differentiation cannot
// pass; here the pole stays in the plane, so the integrals are simpler:
//   n = (sin alpha, cos alpha), e = (cos alpha, -sin alpha) (the normal the rotation moves n
//   along: n' = alpha' e), and the point at xi along the pole moves with
//   v(xi) = v_ax n + (u + xi alpha') e,  v_ax = v . n,  u = v . e          (12)-(14)
//   axial force   -c_z 2L |v_ax| v_ax n                                     (10), exact
//   normal force  -c_xy int |y| y dxi e, y = u + xi alpha'                  (11), exact: the
//                 integrand is the derivative of y^2 |y| / (3 alpha') in xi
//   torque (y)    -c_rot int xi sqrt(v_ax^2 + y^2) y dxi                    (15), Gauss rule
//   alpha''       = torque / Theta                                          (19), Omega normal to n
// The torque's Gauss rule is the one approximation (a few 1e-4 of the torque where the speed
// along the pole passes zero); the planner checks its plan with the 3D model.
#pragma once

#include <Eigen/Core>
#include <cmath>

#include "groundstation/model/planar_pole_vehicle.hpp"
#include "groundstation/model/pole_free_flight.hpp"
#include "groundstation/model/rk4.hpp"

namespace gs::model {

// (x, z, vx, vz) of the pole's centre, alpha (tilt of n from the vertical, positive towards +x)
// and alpha' (= Omega_y), SI units.
namespace planar_flight {
inline constexpr int kStateSize = 6;
enum StateIndex : int { kX = 0, kZ = 1, kVx = 2, kVz = 3, kAlpha = 4, kAlphaDot = 5 };
}  // namespace planar_flight

template <typename Scalar>
using PlanarFlightState = Eigen::Matrix<Scalar, planar_flight::kStateSize, 1>;

// The pole right after leaving the vehicle at the throw's end state s: centre p_q + L n (23),
// centre velocity p_q' + L alpha' e (26), rate alpha' (27); theta plays no part.
template <typename Scalar>
PlanarFlightState<Scalar> planar_pole_at_launch(const PlanarState<Scalar>& s, const PoleParams& params) {
  using std::cos;
  using std::sin;
  const Scalar sa = sin(s(planar::kAlpha)), ca = cos(s(planar::kAlpha));
  const Scalar& rate = s(planar::kAlphaDot);
  const double length = params.half_length_m;
  PlanarFlightState<Scalar> p;
  p(planar_flight::kX) = s(planar::kX) + length * sa;
  p(planar_flight::kZ) = s(planar::kZ) + length * ca;
  p(planar_flight::kVx) = s(planar::kVx) + length * rate * ca;
  p(planar_flight::kVz) = s(planar::kVz) - length * rate * sa;
  p(planar_flight::kAlpha) = s(planar::kAlpha);
  p(planar_flight::kAlphaDot) = rate;
  return p;
}

// |x| for double and (nested) automatic-differentiation scalars alike; Eigen's abs multiplies a
// nested derivative by an int, which it does not define.
template <typename Scalar>
Scalar planar_flight_abs(const Scalar& x) {
  return x < 0.0 ? Scalar(-x) : x;
}

// s' = f(s), eq. (20) in the plane; see the header comment for the drag terms.
template <typename Scalar>
PlanarFlightState<Scalar> planar_pole_flight_derivative(const PlanarFlightState<Scalar>& s,
                                                        const PoleParams& params) {
  using std::cos;
  using std::sin;
  using std::sqrt;
  const auto abs = [](const Scalar& x) { return planar_flight_abs<Scalar>(x); };
  // 6-point Gauss-Legendre rule on [-1, 1].
  static constexpr double kNodes[6] = {-0.9324695142031521, -0.6612093864662645, -0.2386191860831969,
                                       0.2386191860831969,  0.6612093864662645,  0.9324695142031521};
  static constexpr double kWeights[6] = {0.1713244923791704, 0.3607615730481386, 0.4679139345726910,
                                         0.4679139345726910, 0.3607615730481386, 0.1713244923791704};
  const double length = params.half_length_m;
  const Scalar sa = sin(s(planar_flight::kAlpha)), ca = cos(s(planar_flight::kAlpha));
  const Scalar& vx = s(planar_flight::kVx);
  const Scalar& vz = s(planar_flight::kVz);
  const Scalar& rate = s(planar_flight::kAlphaDot);
  const Scalar v_axial = vx * sa + vz * ca;
  const Scalar u = vx * ca - vz * sa;
  const Scalar axial = -params.drag_axial * 2.0 * length * abs(v_axial) * v_axial;
  // int_{-L}^{L} |y| y dxi with y = u + xi alpha'; for a pole that hardly turns, the limit.
  Scalar normal_integral;
  if (abs(rate) > 1e-9) {
    const Scalar y1 = u + length * rate, y0 = u - length * rate;
    normal_integral = (y1 * y1 * abs(y1) - y0 * y0 * abs(y0)) / (3.0 * rate);
  } else {
    normal_integral = 2.0 * length * abs(u) * u;
  }
  const Scalar normal = -params.drag_normal * normal_integral;
  Scalar torque_integral = 0.0 * u;
  for (int k = 0; k < 6; ++k) {
    const double xi = length * kNodes[k];
    const Scalar y = u + xi * rate;
    torque_integral += (length * kWeights[k] * xi) * sqrt(v_axial * v_axial + y * y) * y;
  }
  const double inv_mass = 1.0 / params.mass_kg;
  PlanarFlightState<Scalar> d;
  d(planar_flight::kX) = vx;
  d(planar_flight::kZ) = vz;
  d(planar_flight::kVx) = (axial * sa + normal * ca) * inv_mass;
  d(planar_flight::kVz) = (axial * ca - normal * sa) * inv_mass - params.gravity_mps2;
  d(planar_flight::kAlpha) = rate;
  d(planar_flight::kAlphaDot) = -params.drag_rotational * torque_integral / pole_inertia_kgm2(params);
  return d;
}

// The flight over duration_s in `steps` RK4 steps (duration_s may be a variable of the caller).
template <typename Scalar>
PlanarFlightState<Scalar> planar_pole_flight(const PlanarFlightState<Scalar>& launch,
                                             const Scalar& duration_s, int steps, const PoleParams& params) {
  const Scalar h = duration_s / static_cast<double>(steps);
  PlanarFlightState<Scalar> s = launch;
  const auto f = [&params](const PlanarFlightState<Scalar>& x) {
    return planar_pole_flight_derivative<Scalar>(x, params);
  };
  for (int k = 0; k < steps; ++k) s = rk4_step(f, s, h);
  return s;
}

}  // namespace gs::model
