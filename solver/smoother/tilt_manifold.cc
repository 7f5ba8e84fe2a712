#include "solver/smoother/tilt_manifold.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "core/rotation.h"

namespace mavloc {

namespace {

// d(Exp(phi) * q) / d(phi) at phi = 0 for the quaternion q in Eigen order (x, y, z, w): the pure
// quaternion (0, phi / 2) multiplied on the left, 4 x 3.
Eigen::Matrix<double, 4, 3> LeftPerturbationJacobian(const double* x) {
  const Eigen::Vector3d v(x[0], x[1], x[2]);
  const double w = x[3];
  Eigen::Matrix<double, 4, 3> J;
  J.topRows<3>() = 0.5 * (w * Eigen::Matrix3d::Identity() - Skew(v));
  J.row(3) = -0.5 * v.transpose();
  return J;
}

}  // namespace

bool TiltManifold::Plus(const double* x, const double* delta, double* x_plus_delta) const {
  const Eigen::Quaterniond q(x[3], x[0], x[1], x[2]);
  const Eigen::Quaterniond result =
      (ExpQuaternion(Eigen::Vector3d(delta[0], delta[1], 0.0)) * q).normalized();
  x_plus_delta[0] = result.x();
  x_plus_delta[1] = result.y();
  x_plus_delta[2] = result.z();
  x_plus_delta[3] = result.w();
  return true;
}

bool TiltManifold::PlusJacobian(const double* x, double* jacobian) const {
  Eigen::Map<Eigen::Matrix<double, 4, 2, Eigen::RowMajor>> J(jacobian);
  J = LeftPerturbationJacobian(x).leftCols<2>();
  return true;
}

bool TiltManifold::Minus(const double* y, const double* x, double* y_minus_x) const {
  const Eigen::Quaterniond q_y(y[3], y[0], y[1], y[2]);
  const Eigen::Quaterniond q_x(x[3], x[0], x[1], x[2]);
  const Eigen::Vector3d phi = LogQuaternion((q_y * q_x.conjugate()).normalized());
  y_minus_x[0] = phi.x();
  y_minus_x[1] = phi.y();
  return true;
}

bool TiltManifold::MinusJacobian(const double* x, double* jacobian) const {
  // The columns of the left-perturbation Jacobian are orthogonal with norm 1/2, so its
  // pseudo-inverse is 4 J^T; along the yaw and the quaternion's norm Minus does not change.
  Eigen::Map<Eigen::Matrix<double, 2, 4, Eigen::RowMajor>> J(jacobian);
  J = 4.0 * LeftPerturbationJacobian(x).leftCols<2>().transpose();
  return true;
}

}  // namespace mavloc
