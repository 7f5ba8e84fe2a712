// Reprojection of a known map point (tag or marker corner, surveyed landmark) in pixels:
//   p_C = R_B_C^T (R_W_B^T (p_W - p_W_B) - p_B_C),   r = (pi(p_C) - uv) / sigma_px
// with pi the pinhole + distortion projection of core/camera_model.h (CameraModel::ProjectT).
// Parameter blocks: q_W_B (4, Eigen order x y z w; ceres::EigenQuaternionManifold), p_W_B (3).
// The point, T_B_C and the camera are constants. Evaluation fails (the step is rejected) when the
// point is not in front of the camera.
//
// Jacobians are analytic (this residual is the smoother's most numerous one): d pi / d p_C by
// forward-mode differentiation of the projection over the 3 coordinates of p_C, then, with
// R_W_B' = Exp(2 delta) R_W_B,
//   d p_C / d delta = 2 R_B_C^T R_W_B^T [p_W - p_W_B]x,   d p_C / d p_W_B = -R_B_C^T R_W_B^T,
// the quaternion's mapped to its ambient coordinates (quaternion_ambient.h). Checked against
// central differences in tests/solver/smoother_residuals_test.cc.
// MapPointReprojectionFactorAutoDiff is the same residual differentiated automatically: the
// reference the analytic Jacobians are checked against and timed against
// (SmootherProblemOptions::autodiff_jacobians).
#pragma once

#include <ceres/autodiff_cost_function.h>
#include <ceres/sized_cost_function.h>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "core/camera_model.h"
#include "core/pose.h"

namespace mavloc {

class MapPointReprojectionFactor : public ceres::SizedCostFunction<2, 4, 3> {
 public:
  MapPointReprojectionFactor(const CameraModel& camera, const Pose& T_B_C,
                             const Eigen::Vector3d& p_W, const Eigen::Vector2d& uv_px,
                             double sigma_px)
      : camera_(camera),
        R_B_C_(T_B_C.q.normalized().toRotationMatrix()),
        p_B_C_(T_B_C.p),
        p_W_(p_W),
        uv_px_(uv_px),
        inv_sigma_(1.0 / sigma_px) {}

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

  static ceres::CostFunction* Create(const CameraModel& camera, const Pose& T_B_C,
                                     const Eigen::Vector3d& p_W, const Eigen::Vector2d& uv_px,
                                     double sigma_px) {
    return new MapPointReprojectionFactor(camera, T_B_C, p_W, uv_px, sigma_px);
  }

 private:
  CameraModel camera_;
  Eigen::Matrix3d R_B_C_;
  Eigen::Vector3d p_B_C_;
  Eigen::Vector3d p_W_;
  Eigen::Vector2d uv_px_;
  double inv_sigma_;
};

class MapPointReprojectionFactorAutoDiff {
 public:
  MapPointReprojectionFactorAutoDiff(const CameraModel& camera, const Pose& T_B_C,
                                     const Eigen::Vector3d& p_W, const Eigen::Vector2d& uv_px,
                                     double sigma_px)
      : camera_(camera),
        q_B_C_(T_B_C.q.normalized()),
        p_B_C_(T_B_C.p),
        p_W_(p_W),
        uv_px_(uv_px),
        inv_sigma_(1.0 / sigma_px) {}

  template <typename T>
  bool operator()(const T* q_ptr, const T* p_ptr, T* residuals) const {
    using Vec3 = Eigen::Matrix<T, 3, 1>;
    const Eigen::Quaternion<T> q_W_B = Eigen::Map<const Eigen::Quaternion<T>>(q_ptr).normalized();
    const Eigen::Map<const Vec3> p_W_B(p_ptr);
    const Vec3 p_B = q_W_B.conjugate() * (p_W_.cast<T>() - p_W_B);
    const Vec3 p_C = q_B_C_.cast<T>().conjugate() * (p_B - p_B_C_.cast<T>());
    if (!(p_C[2] > T(1e-9))) return false;
    T uv[2];
    camera_.ProjectT(p_C.data(), uv);
    residuals[0] = (uv[0] - T(uv_px_[0])) * T(inv_sigma_);
    residuals[1] = (uv[1] - T(uv_px_[1])) * T(inv_sigma_);
    return true;
  }

  static ceres::CostFunction* Create(const CameraModel& camera, const Pose& T_B_C,
                                     const Eigen::Vector3d& p_W, const Eigen::Vector2d& uv_px,
                                     double sigma_px) {
    return new ceres::AutoDiffCostFunction<MapPointReprojectionFactorAutoDiff, 2, 4, 3>(
        new MapPointReprojectionFactorAutoDiff(camera, T_B_C, p_W, uv_px, sigma_px));
  }

 private:
  CameraModel camera_;
  Eigen::Quaterniond q_B_C_;
  Eigen::Vector3d p_B_C_;
  Eigen::Vector3d p_W_;
  Eigen::Vector2d uv_px_;
  double inv_sigma_;
};

}  // namespace mavloc
