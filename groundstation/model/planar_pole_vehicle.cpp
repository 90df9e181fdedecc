#include "groundstation/model/planar_pole_vehicle.hpp"

#include <unsupported/Eigen/AutoDiff>

namespace gs::model {

PlanarLinearisation linearise_planar_pole_vehicle(const PlanarState<double>& s, const PlanarInput<double>& u,
                                                  const PlanarPoleVehicleParams& params) {
  constexpr int kN = planar::kStateSize + planar::kInputSize;
  using Ad = Eigen::AutoDiffScalar<Eigen::Matrix<double, kN, 1>>;
  PlanarState<Ad> s_ad;
  PlanarInput<Ad> u_ad;
  for (int i = 0; i < planar::kStateSize; ++i) s_ad(i) = Ad(s(i), kN, i);
  for (int j = 0; j < planar::kInputSize; ++j) {
    u_ad(j) = Ad(u(j), kN, planar::kStateSize + j);
  }
  const PlanarState<Ad> f = planar_pole_vehicle_dynamics<Ad>(s_ad, u_ad, params);
  PlanarLinearisation lin;
  for (int r = 0; r < planar::kStateSize; ++r) {
    if (f(r).derivatives().size() != kN) {  // an output with no dependence at all
      lin.A.row(r).setZero();
      lin.B.row(r).setZero();
      continue;
    }
    lin.A.row(r) = f(r).derivatives().head<planar::kStateSize>().transpose();
    lin.B.row(r) = f(r).derivatives().tail<planar::kInputSize>().transpose();
  }
  return lin;
}

}  // namespace gs::model
