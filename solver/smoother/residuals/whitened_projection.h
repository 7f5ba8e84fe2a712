// The whitened reprojection residual r = (pi(p_C) - uv) / sigma_px of the analytic reprojection
// factors, with its Jacobian d r / d p_C from the camera's analytic projection Jacobian
// (core/camera_model.h, CameraModel::ProjectWithJacobian).
#pragma once

#include <Eigen/Core>

#include "core/camera_model.h"

namespace mavloc {

using RowMajor2x3 = Eigen::Matrix<double, 2, 3, Eigen::RowMajor>;

// Writes r to residuals[0..1]; with J_r_pC, also d r / d p_C.
inline void WhitenedProjection(const CameraModel& camera, const Eigen::Vector3d& p_C,
                               const Eigen::Vector2d& uv_px, double inv_sigma_px, double* residuals,
                               RowMajor2x3* J_r_pC) {
  Eigen::Vector2d uv;
  if (J_r_pC) {
    uv = camera.ProjectWithJacobian(p_C, J_r_pC);
    *J_r_pC *= inv_sigma_px;
  } else {
    camera.ProjectT(p_C.data(), uv.data());
  }
  residuals[0] = (uv.x() - uv_px.x()) * inv_sigma_px;
  residuals[1] = (uv.y() - uv_px.y()) * inv_sigma_px;
}

}  // namespace mavloc
