#include "groundstation/control/throw_frame.hpp"

#include <catch2/catch.hpp>
#include <cmath>

#include "groundstation/control/controller_states.hpp"

using gs::control::Pivot;
using gs::control::ThrowFrame;
using gs::model::PoleState;
using gs::model::VehicleState;

namespace {

Eigen::Matrix3d attitude(const VehicleState& s) {
  return gs::model::rotation_inertial_from_body(s.phi_rad, s.theta_rad, s.psi_rad);
}

// The planar throw's state of a scene, and the same scene seen from a frame.
gs::model::PlanarState<double> planar(const Pivot& pivot, const VehicleState& v, const PoleState& p) {
  return gs::control::planar_throw_state(pivot, v, p, Eigen::Vector3d::Zero());
}

}  // namespace

TEST_CASE("points and directions go into the throw's frame and back") {
  const ThrowFrame frame{Eigen::Vector3d(3.4, -1.0, 2.0), 2.2};
  const Eigen::Vector3d p(0.3, 1.7, 2.5);
  CHECK((frame.to_arena(frame.to_frame(p)) - p).norm() < 1e-12);
  CHECK((frame.to_arena_xy(frame.to_frame_xy(p.head<2>())) - p.head<2>()).norm() < 1e-12);
  // +x of the frame is the throw's direction in the arena.
  const Eigen::Vector2d ahead = frame.direction_to_arena(Eigen::Vector2d::UnitX());
  CHECK(ahead.x() == Approx(std::cos(2.2)));
  CHECK(ahead.y() == Approx(std::sin(2.2)));
  CHECK((frame.to_frame(frame.origin_m)).norm() < 1e-12);
}

TEST_CASE("a throw towards -x is the planar throw mirrored: the pitch, the pole's tilt and x change sign") {
  const ThrowFrame back{Eigen::Vector3d(3.0, 0.0, 2.0), M_PI};
  VehicleState v;
  v.p_m = Eigen::Vector3d(2.4, 0.0, 1.6);
  v.v_mps = Eigen::Vector3d(-0.5, 0.0, 1.0);
  v.theta_rad = -0.3;  // the thrust axis leans towards -x
  PoleState pole;
  pole.n = Eigen::Vector3d(-std::sin(0.2), 0.0, std::cos(0.2));
  const Pivot pivot{v.p_m + Eigen::Vector3d(0.0, 0.0, 0.1), v.v_mps};
  pole.p_m = pivot.p_m + 0.65 * pole.n;
  pole.v_mps = v.v_mps + Eigen::Vector3d(-0.2, 0.0, 0.05);

  const VehicleState f = back.to_frame(v);
  CHECK(f.theta_rad == Approx(0.3));
  CHECK(f.phi_rad == Approx(0.0).margin(1e-12));
  CHECK(f.psi_rad == Approx(0.0).margin(1e-12));  // the vehicle does not yaw for the throw
  const auto s = planar(back.to_frame(pivot), f, back.to_frame(pole));
  const Pivot forward_pivot{Eigen::Vector3d(0.6, 0.0, -0.3), Eigen::Vector3d(0.5, 0.0, 1.0)};
  CHECK(s(gs::model::planar::kX) == Approx(forward_pivot.p_m.x()));
  CHECK(s(gs::model::planar::kZ) == Approx(forward_pivot.p_m.z()));
  CHECK(s(gs::model::planar::kVx) == Approx(0.5));
  CHECK(s(gs::model::planar::kTheta) == Approx(0.3));
  CHECK(s(gs::model::planar::kAlpha) == Approx(0.2));
  // A pitch rate commanded in the frame is the opposite pitch rate on the vehicle.
  const Eigen::Vector3d w = back.body_rates_to_vehicle(Eigen::Vector3d(0.0, 2.5, 0.1));
  CHECK((w - Eigen::Vector3d(0.0, -2.5, 0.1)).norm() < 1e-12);
}

TEST_CASE("in any direction the frame sees the thrust axis and the pole turned with it, the heading kept") {
  for (const double beta : {0.0, 0.7, M_PI / 2, 2.5, -1.9}) {
    const ThrowFrame frame{Eigen::Vector3d(1.0, 2.0, 2.0), beta};
    VehicleState v;
    v.p_m = Eigen::Vector3d(1.5, 2.2, 1.8);
    v.v_mps = Eigen::Vector3d(0.3, -0.4, 0.9);
    v.phi_rad = 0.15;
    v.theta_rad = -0.25;
    v.psi_rad = 0.4;
    const VehicleState f = frame.to_frame(v);
    const Eigen::Vector3d thrust_axis = attitude(v).col(2);
    CHECK((attitude(f).col(2) - frame.direction_to_frame(thrust_axis)).norm() < 1e-12);
    VehicleState level = v;
    level.phi_rad = level.theta_rad = 0.0;
    CHECK(frame.to_frame(level).psi_rad == Approx(0.4));  // a level vehicle keeps its yaw exactly
    CHECK(std::abs(f.psi_rad - 0.4) < 0.05);              // a tilted one to second order in its tilt
    CHECK((f.v_mps - frame.direction_to_frame(v.v_mps)).norm() < 1e-12);
    // A body rate about the relabelled axes turns the vehicle's thrust axis as the frame sees it:
    // d/dt (R e_z) = R (omega x e_z) in either description.
    const Eigen::Vector3d w_frame(0.4, -1.1, 0.3);
    const Eigen::Vector3d w_vehicle = frame.body_rates_to_vehicle(w_frame);
    const Eigen::Vector3d axis_rate_arena = attitude(v) * w_vehicle.cross(Eigen::Vector3d::UnitZ());
    const Eigen::Vector3d axis_rate_frame = attitude(f) * w_frame.cross(Eigen::Vector3d::UnitZ());
    CHECK((axis_rate_frame - frame.direction_to_frame(axis_rate_arena)).norm() < 1e-12);
    PoleState pole;
    pole.p_m = Eigen::Vector3d(1.6, 2.1, 2.5);
    pole.n = Eigen::Vector3d(0.1, -0.2, 1.0).normalized();
    pole.omega_radps = Eigen::Vector3d(0.5, 0.2, 0.0);
    const PoleState pf = frame.to_frame(pole);
    CHECK((pf.n - frame.direction_to_frame(pole.n)).norm() < 1e-12);
    CHECK((pf.p_m - frame.to_frame(pole.p_m)).norm() < 1e-12);
    CHECK((pf.omega_radps - frame.direction_to_frame(pole.omega_radps)).norm() < 1e-12);
  }
}
