// Reprojection of a known map point in pixels with the calibration as parameters: the board's
// tilt to gravity (q_W_M), the camera-IMU extrinsic (q_B_C, p_B_C) and the camera-IMU time offset
// t_d (an image stamped t_k was exposed at t_k + t_d). Used by the smoother only when one of
// these is estimated; MapPointReprojectionFactor is the fixed-calibration special case.
//   R_t = R_W_B Exp(phi(t_d)),   p_t = p_W_B + v_W t_d + 1/2 g_W t_d^2 + R_W_B dp(t_d)
//     (the pose at t_k + t_d from the keyframe at t_k and the IMU,
//     solver/smoother/imu_time_shift.h)
//   p_W = R_W_M p_M                                     (W origin = M origin, core/board_frame.h)
//   p_C = R_B_C^T (R_t^T (p_W - p_t) - p_B_C),   r = (pi(p_C) - uv) / sigma_px
// with pi the pinhole + distortion projection of core/camera_model.h. On a world map (no board)
// q_W_M is the identity, held constant.
// Parameter blocks: q_W_B (4, Eigen order x y z w), p_W_B (3), v_W (3), q_W_M (4, TiltManifold),
// q_B_C (4), p_B_C (3), t_d (1, seconds). Evaluation fails (the step is rejected) when the point
// is not in front of the camera.
//
// Jacobians are analytic (automatic differentiation over the 22 parameters made this residual
// the smoother's bottleneck): d pi / d p_C by forward-mode differentiation of the projection (3
// dual numbers), then the chain rule in the tangent spaces of the manifolds the smoother uses,
//   q_W_B, q_B_C (ceres::EigenQuaternionManifold: R' = Exp(2 delta) R):
//     d p_C / d delta_WB = 2 R_B_C^T R_t^T [p_W - p_W_B - v t_d - g t_d^2 / 2]x,
//     d p_C / d delta_BC = 2 R_B_C^T [p_B - p_B_C]x;
//   q_W_M (TiltManifold: R' = Exp((d1, d2, 0)) R): d p_C / d d = -R_B_C^T R_t^T [p_W]x (x, y
//     columns);
//   t_d: d p_B / d t_d = -[J_r(phi) phi']x p_B - R_t^T (v + g t_d + R_W_B dp');
// and mapped to the ambient quaternion coordinates with the pseudo-inverse of each manifold's
// PlusJacobian (P^T for Ceres' unit-norm columns, TiltManifold::MinusJacobian for the tilt), so
// that Ceres' ambient-times-PlusJacobian product returns the tangent Jacobian. Checked against
// central differences in tests/solver/smoother_residuals_test.cc.
#pragma once

#include <ceres/sized_cost_function.h>

#include <Eigen/Core>
#include <memory>

#include "core/camera_model.h"
#include "solver/smoother/imu_time_shift.h"

namespace mavloc {

class CalibratedReprojectionFactor : public ceres::SizedCostFunction<2, 4, 3, 3, 4, 4, 3, 1> {
 public:
  CalibratedReprojectionFactor(const CameraModel& camera, std::shared_ptr<const ImuTimeShift> shift,
                               const Eigen::Vector3d& p_M, const Eigen::Vector2d& uv_px,
                               double sigma_px)
      : camera_(camera),
        shift_(std::move(shift)),
        p_M_(p_M),
        uv_px_(uv_px),
        inv_sigma_(1.0 / sigma_px) {}

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

  static ceres::CostFunction* Create(const CameraModel& camera,
                                     std::shared_ptr<const ImuTimeShift> shift,
                                     const Eigen::Vector3d& p_M, const Eigen::Vector2d& uv_px,
                                     double sigma_px) {
    return new CalibratedReprojectionFactor(camera, std::move(shift), p_M, uv_px, sigma_px);
  }

 private:
  CameraModel camera_;
  std::shared_ptr<const ImuTimeShift> shift_;
  Eigen::Vector3d p_M_;
  Eigen::Vector2d uv_px_;
  double inv_sigma_;
};

}  // namespace mavloc
