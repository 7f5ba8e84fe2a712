#include "solver/smoother/residuals/map_point_reprojection_factor.h"

#include <ceres/jet.h>

#include "core/rotation.h"
#include "solver/smoother/residuals/quaternion_ambient.h"

namespace mavloc {

bool MapPointReprojectionFactor::Evaluate(double const* const* parameters, double* residuals,
                                          double** jacobians) const {
  using RowMajor2x3 = Eigen::Matrix<double, 2, 3, Eigen::RowMajor>;
  const Eigen::Quaterniond q_W_B = Eigen::Map<const Eigen::Quaterniond>(parameters[0]).normalized();
  const Eigen::Map<const Eigen::Vector3d> p_W_B(parameters[1]);
  const Eigen::Matrix3d R_W_B = q_W_B.toRotationMatrix();
  const Eigen::Vector3d lever_W = p_W_ - p_W_B;
  const Eigen::Vector3d p_C = R_B_C_.transpose() * (R_W_B.transpose() * lever_W - p_B_C_);
  if (!(p_C.z() > 1e-9)) return false;

  // Projection and its Jacobian by forward-mode differentiation over the 3 coordinates of p_C.
  using Jet3 = ceres::Jet<double, 3>;
  const Jet3 p_C_jet[3] = {Jet3(p_C.x(), 0), Jet3(p_C.y(), 1), Jet3(p_C.z(), 2)};
  Jet3 uv[2];
  camera_.ProjectT(p_C_jet, uv);
  residuals[0] = (uv[0].a - uv_px_.x()) * inv_sigma_;
  residuals[1] = (uv[1].a - uv_px_.y()) * inv_sigma_;
  if (!jacobians) return true;

  RowMajor2x3 J_uv;  // whitened d r / d p_C
  J_uv.row(0) = uv[0].v.transpose() * inv_sigma_;
  J_uv.row(1) = uv[1].v.transpose() * inv_sigma_;
  const RowMajor2x3 J_pW = J_uv * R_B_C_.transpose() * R_W_B.transpose();  // d r / d p_W
  if (jacobians[0]) {
    const RowMajor2x3 J_tangent = 2.0 * J_pW * Skew(lever_W);
    QuaternionAmbient(parameters[0], J_tangent, jacobians[0]);
  }
  if (jacobians[1]) Eigen::Map<RowMajor2x3>{jacobians[1]} = -J_pW;
  return true;
}

}  // namespace mavloc
