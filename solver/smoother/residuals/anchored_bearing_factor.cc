#include "solver/smoother/residuals/anchored_bearing_factor.h"

#include "core/rotation.h"
#include "solver/smoother/residuals/quaternion_ambient.h"

namespace mavloc {

using RowMajor2x3 = Eigen::Matrix<double, 2, 3, Eigen::RowMajor>;

AnchoredBearingFactor::AnchoredBearingFactor(const Pose& T_B_Ca, const Eigen::Vector3d& b_anchor_Ca,
                                             const Pose& T_B_Co,
                                             const Eigen::Vector2d& xy_normalized, double sigma_rad)
    : R_B_Ca_(T_B_Ca.q.normalized().toRotationMatrix()),
      R_B_Co_(T_B_Co.q.normalized().toRotationMatrix()),
      p_B_Ca_(T_B_Ca.p),
      p_B_Co_(T_B_Co.p),
      b_anchor_B_(R_B_Ca_ * b_anchor_Ca.normalized()),
      bearing_(Eigen::Vector3d(xy_normalized.x(), xy_normalized.y(), 1.0).normalized()),
      basis_(BearingTangentBasis(bearing_)),
      inv_sigma_(1.0 / sigma_rad) {}

bool AnchoredBearingFactor::Evaluate(double const* const* parameters, double* residuals,
                                     double** jacobians) const {
  const Eigen::Matrix3d R_W_Ba =
      Eigen::Map<const Eigen::Quaterniond>(parameters[0]).normalized().toRotationMatrix();
  const Eigen::Map<const Eigen::Vector3d> p_W_Ba(parameters[1]);
  const Eigen::Matrix3d R_W_Bo =
      Eigen::Map<const Eigen::Quaterniond>(parameters[2]).normalized().toRotationMatrix();
  const Eigen::Map<const Eigen::Vector3d> p_W_Bo(parameters[3]);
  const double rho = parameters[4][0];
  const Eigen::Vector3d lever_o_W = R_W_Bo * p_B_Co_;  // p_W_Co - p_W_Bo
  const Eigen::Vector3d baseline_W = R_W_Ba * p_B_Ca_ + p_W_Ba - (lever_o_W + p_W_Bo);
  const Eigen::Vector3d h_W = R_W_Ba * b_anchor_B_ + rho * baseline_W;
  const Eigen::Matrix3d R_Co_W = R_B_Co_.transpose() * R_W_Bo.transpose();
  const Eigen::Vector3d h = R_Co_W * h_W;
  const double norm = h.norm();
  if (!(norm > 1e-12)) return false;
  const Eigen::Vector3d u = h / norm;
  Eigen::Map<Eigen::Vector2d>{residuals} = inv_sigma_ * (basis_ * (u - bearing_));
  if (!jacobians) return true;
  const RowMajor2x3 J_h =
      (inv_sigma_ / norm) * basis_ * (Eigen::Matrix3d::Identity() - u * u.transpose());
  const RowMajor2x3 J_hW = J_h * R_Co_W;
  if (jacobians[0]) {
    const Eigen::Vector3d v_a = R_W_Ba * (b_anchor_B_ + rho * p_B_Ca_);
    const RowMajor2x3 J_tangent = -2.0 * J_hW * Skew(v_a);
    QuaternionAmbient(parameters[0], J_tangent, jacobians[0]);
  }
  if (jacobians[1]) Eigen::Map<RowMajor2x3>{jacobians[1]} = rho * J_hW;
  if (jacobians[2]) {
    const RowMajor2x3 J_tangent = 2.0 * J_hW * (Skew(h_W) + rho * Skew(lever_o_W));
    QuaternionAmbient(parameters[2], J_tangent, jacobians[2]);
  }
  if (jacobians[3]) Eigen::Map<RowMajor2x3>{jacobians[3]} = -rho * J_hW;
  if (jacobians[4]) Eigen::Map<Eigen::Vector2d>{jacobians[4]} = J_hW * baseline_W;
  return true;
}

}  // namespace mavloc
