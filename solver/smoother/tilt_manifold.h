// The 2-DoF manifold of the board-to-world rotation q_W_M on a board log (core/board_frame.h):
// only the gravity direction in the board frame M is observable, the rotation about gravity (yaw
// of W) is gauge. Storage is a unit quaternion in Eigen order (x, y, z, w); the tangent is a
// left (world-frame) perturbation about W's x and y axes, in radians (full angle):
//   Plus(q, d) = Exp((d1, d2, 0)) * q,
//   Minus(y, x) = the (x, y) components of Log(y * x^-1),
// so the yaw of W has no direction in the tangent space and the solver cannot move it. Plus
// followed by Minus is the identity for |d| < pi; Minus is the local inverse used by Ceres'
// covariance and gradient checks.
#pragma once

#include <ceres/manifold.h>

namespace mavloc {

class TiltManifold : public ceres::Manifold {
 public:
  int AmbientSize() const override { return 4; }
  int TangentSize() const override { return 2; }
  bool Plus(const double* x, const double* delta, double* x_plus_delta) const override;
  // 4 x 2, row-major, at delta = 0.
  bool PlusJacobian(const double* x, double* jacobian) const override;
  bool Minus(const double* y, const double* x, double* y_minus_x) const override;
  // 2 x 4, row-major, at y = x.
  bool MinusJacobian(const double* x, double* jacobian) const override;
};

}  // namespace mavloc
