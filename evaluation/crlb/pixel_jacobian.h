// The whitened pixel Jacobian of a map point for the Cramér–Rao bound (smoother_bound.h): the
// derivative of pi(T_C_W p_W) / sigma_px, with T_W_C = T_W_B T_B_C and pi the camera's pinhole +
// distortion projection (core/camera_model.h), with respect to
//   dp     (m):   T_W_B.p + dp,
//   dtheta (rad): T_W_B.q Exp(dtheta) (right perturbation),
//   d1, d2 (rad): the point moved to Exp((d1, d2, 0)) p_W (a board's tilt to gravity,
//   TiltManifold's
//                 left perturbation; only with_tilt, else those columns are zero).
// Analytic: with p_B = R_W_B^T (p_W - p_W_B) and p_C = R_B_C^T (p_B - p_B_C),
//   d p_C / d dp = -R_C_W,  d p_C / d dtheta = R_B_C^T [p_B]x,  d p_C / d d = -R_C_W [p_W]x (cols
//   1-2),
// chained with CameraModel::ProjectWithJacobian.
#pragma once

#include <Eigen/Core>

#include "core/dataset.h"
#include "core/pose.h"

namespace mavloc {

// False when the point is not in front of the camera (depth <= 0.01 m).
bool PixelJacobian(const CameraSensor& camera, const Pose& T_W_B, const Eigen::Vector3d& p_W,
                   double sigma_px, bool with_tilt, Eigen::Matrix<double, 2, 8>* J);

}  // namespace mavloc
