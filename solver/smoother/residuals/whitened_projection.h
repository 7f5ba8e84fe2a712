// The whitened reprojection residual r = (pi(p_C) - uv) / sigma_px of the analytic reprojection
// factors, with its Jacobian d r / d p_C by forward-mode differentiation of the camera's
// projection (core/camera_model.h, CameraModel::ProjectT) over the 3 coordinates of p_C.
#pragma once

#include <ceres/jet.h>

#include <Eigen/Core>

#include "core/camera_model.h"

namespace mavloc {

using RowMajor2x3 = Eigen::Matrix<double, 2, 3, Eigen::RowMajor>;

// Writes r to residuals[0..1] and returns d r / d p_C.
inline RowMajor2x3 WhitenedProjection(const CameraModel& camera, const Eigen::Vector3d& p_C,
                                      const Eigen::Vector2d& uv_px, double inv_sigma_px,
                                      double* residuals) {
  using Jet3 = ceres::Jet<double, 3>;
  const Jet3 p_C_jet[3] = {Jet3(p_C.x(), 0), Jet3(p_C.y(), 1), Jet3(p_C.z(), 2)};
  Jet3 uv[2];
  camera.ProjectT(p_C_jet, uv);
  residuals[0] = (uv[0].a - uv_px.x()) * inv_sigma_px;
  residuals[1] = (uv[1].a - uv_px.y()) * inv_sigma_px;
  RowMajor2x3 J_uv;
  J_uv.row(0) = uv[0].v.transpose() * inv_sigma_px;
  J_uv.row(1) = uv[1].v.transpose() * inv_sigma_px;
  return J_uv;
}

}  // namespace mavloc
