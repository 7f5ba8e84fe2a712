#include "solver/smoother/residuals/map_point_reprojection_factor.h"

#include "core/rotation.h"
#include "solver/smoother/residuals/quaternion_ambient.h"
#include "solver/smoother/residuals/whitened_projection.h"

namespace mavloc {

bool MapPointReprojectionFactor::Evaluate(double const* const* parameters, double* residuals,
                                          double** jacobians) const {
  const Eigen::Quaterniond q_W_B = Eigen::Map<const Eigen::Quaterniond>(parameters[0]).normalized();
  const Eigen::Map<const Eigen::Vector3d> p_W_B(parameters[1]);
  const Eigen::Matrix3d R_W_B = q_W_B.toRotationMatrix();
  const Eigen::Vector3d lever_W = p_W_ - p_W_B;
  const Eigen::Vector3d p_C = R_B_C_.transpose() * (R_W_B.transpose() * lever_W - p_B_C_);
  if (!(p_C.z() > 1e-9)) return false;

  RowMajor2x3 J_uv;
  WhitenedProjection(camera_, p_C, uv_px_, inv_sigma_, residuals, jacobians ? &J_uv : nullptr);
  if (!jacobians) return true;
  const RowMajor2x3 J_pW = J_uv * R_B_C_.transpose() * R_W_B.transpose();  // d r / d p_W
  if (jacobians[0]) {
    const RowMajor2x3 J_tangent = 2.0 * J_pW * Skew(lever_W);
    QuaternionAmbient(parameters[0], J_tangent, jacobians[0]);
  }
  if (jacobians[1]) Eigen::Map<RowMajor2x3>{jacobians[1]} = -J_pW;
  return true;
}

}  // namespace mavloc
