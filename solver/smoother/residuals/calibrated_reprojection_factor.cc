#include "solver/smoother/residuals/calibrated_reprojection_factor.h"

#include <ceres/jet.h>
#include <ceres/manifold.h>

#include <Eigen/Geometry>

#include "core/imu.h"
#include "core/rotation.h"
#include "solver/smoother/residuals/quaternion_ambient.h"
#include "solver/smoother/residuals/whitened_projection.h"
#include "solver/smoother/tilt_manifold.h"

namespace mavloc {

bool CalibratedReprojectionFactor::Evaluate(double const* const* parameters, double* residuals,
                                            double** jacobians) const {
  const Eigen::Quaterniond q_W_B = Eigen::Map<const Eigen::Quaterniond>(parameters[0]).normalized();
  const Eigen::Map<const Eigen::Vector3d> p_W_B(parameters[1]), v_W(parameters[2]);
  const Eigen::Quaterniond q_W_M = Eigen::Map<const Eigen::Quaterniond>(parameters[3]).normalized();
  const Eigen::Quaterniond q_B_C = Eigen::Map<const Eigen::Quaterniond>(parameters[4]).normalized();
  const Eigen::Map<const Eigen::Vector3d> p_B_C(parameters[5]);
  const double t_d = parameters[6][0];

  // The body pose at the exposure time.
  Eigen::Vector3d phi, dphi, dp, ddp;
  shift_->EvaluateWithDerivative(t_d, &phi, &dphi, &dp, &ddp);
  const Eigen::Matrix3d R_W_B = q_W_B.toRotationMatrix();
  const Eigen::Matrix3d R_t = R_W_B * ExpSO3(phi);
  const Eigen::Vector3d g = GravityW();
  const Eigen::Vector3d p_t = p_W_B + v_W * t_d + 0.5 * g * t_d * t_d + R_W_B * dp;

  const Eigen::Vector3d p_W = q_W_M * p_M_;
  const Eigen::Vector3d p_B = R_t.transpose() * (p_W - p_t);
  const Eigen::Matrix3d R_B_C = q_B_C.toRotationMatrix();
  const Eigen::Vector3d c = p_B - p_B_C;
  const Eigen::Vector3d p_C = R_B_C.transpose() * c;
  if (!(p_C.z() > 1e-9)) return false;

  RowMajor2x3 J_uv;
  WhitenedProjection(camera_, p_C, uv_px_, inv_sigma_, residuals, jacobians ? &J_uv : nullptr);
  if (!jacobians) return true;
  const RowMajor2x3 J_pB = J_uv * R_B_C.transpose();  // d r / d p_B
  const RowMajor2x3 J_pW = J_pB * R_t.transpose();    // d r / d p_W (and -d r / d p_t)

  if (jacobians[0]) {
    const Eigen::Vector3d lever = p_W - p_W_B - v_W * t_d - 0.5 * g * t_d * t_d;
    const RowMajor2x3 J_tangent = 2.0 * J_pW * Skew(lever);
    QuaternionAmbient(parameters[0], J_tangent, jacobians[0]);
  }
  if (jacobians[1]) Eigen::Map<RowMajor2x3>{jacobians[1]} = -J_pW;
  if (jacobians[2]) Eigen::Map<RowMajor2x3>{jacobians[2]} = -t_d * J_pW;
  if (jacobians[3]) {
    const Eigen::Matrix<double, 2, 2> J_tilt = (-J_pW * Skew(p_W)).leftCols<2>();
    static const TiltManifold tilt;
    Eigen::Matrix<double, 2, 4, Eigen::RowMajor> pseudo_inverse;
    tilt.MinusJacobian(parameters[3], pseudo_inverse.data());
    Eigen::Map<Eigen::Matrix<double, 2, 4, Eigen::RowMajor>>{jacobians[3]} =
        J_tilt * pseudo_inverse;
  }
  if (jacobians[4]) {
    const RowMajor2x3 J_tangent = 2.0 * J_uv * R_B_C.transpose() * Skew(c);
    QuaternionAmbient(parameters[4], J_tangent, jacobians[4]);
  }
  if (jacobians[5]) Eigen::Map<RowMajor2x3>{jacobians[5]} = -J_pB;
  if (jacobians[6]) {
    const Eigen::Vector3d omega = RightJacobianSO3(phi) * dphi;  // body rate at t_k + t_d
    const Eigen::Vector3d dp_B =
        -Skew(omega) * p_B - R_t.transpose() * (v_W + g * t_d + R_W_B * ddp);
    Eigen::Map<Eigen::Vector2d>{jacobians[6]} = J_pB * dp_B;
  }
  return true;
}

}  // namespace mavloc
