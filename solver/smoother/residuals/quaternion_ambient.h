// Analytic Jacobians of residuals over ceres::EigenQuaternionManifold blocks: the tangent
// Jacobian (d r / d delta with R' = Exp(2 delta) R) mapped to the 4 ambient coordinates
// (x, y, z, w) that Ceres asks a cost function for.
#pragma once

#include <ceres/manifold.h>

#include <Eigen/Core>

namespace mavloc {

// J_tangent (rows x 3) at q into the ambient rows x 4 Jacobian (row-major, at `out`): the
// PlusJacobian P has orthonormal columns, so J_ambient = J_tangent P^T satisfies
// J_ambient P = J_tangent, the product Ceres forms.
template <int kRows>
void QuaternionAmbient(const double* q,
                       const Eigen::Matrix<double, kRows, 3, Eigen::RowMajor>& J_tangent,
                       double* out) {
  static const ceres::EigenQuaternionManifold manifold;
  Eigen::Matrix<double, 4, 3, Eigen::RowMajor> P;
  manifold.PlusJacobian(q, P.data());
  Eigen::Map<Eigen::Matrix<double, kRows, 4, Eigen::RowMajor>> J(out);
  J = J_tangent * P.transpose();
}

}  // namespace mavloc
