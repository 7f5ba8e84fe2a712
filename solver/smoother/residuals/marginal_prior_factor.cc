#include "solver/smoother/residuals/marginal_prior_factor.h"

#include <ceres/manifold.h>

namespace mavloc {

MarginalPriorFactor::MarginalPriorFactor(const KeyframeMarginalPrior& prior) : prior_(prior) {
  const Eigen::Quaterniond q = prior.linearization.q_W_B.normalized();
  q_lin_[0] = q.x();
  q_lin_[1] = q.y();
  q_lin_[2] = q.z();
  q_lin_[3] = q.w();
}

Vector15d MarginalPriorFactor::Delta(double const* const* parameters) const {
  Vector15d delta;
  ceres::EigenQuaternionManifold manifold;
  manifold.Minus(parameters[0], q_lin_, delta.data());
  const ImuKeyframeState& x = prior_.linearization;
  delta.segment<3>(3) = Eigen::Map<const Eigen::Vector3d>(parameters[1]) - x.p_W;
  delta.segment<3>(6) = Eigen::Map<const Eigen::Vector3d>(parameters[2]) - x.v_W;
  delta.segment<3>(9) = Eigen::Map<const Eigen::Vector3d>(parameters[3]) - x.biases.b_g;
  delta.segment<3>(12) = Eigen::Map<const Eigen::Vector3d>(parameters[4]) - x.biases.b_a;
  return delta;
}

bool MarginalPriorFactor::Evaluate(double const* const* parameters, double* residuals,
                                   double** jacobians) const {
  const Matrix15d& R = prior_.sqrt_information;
  Eigen::Map<Vector15d> r(residuals);
  r = R * Delta(parameters) + prior_.offset;
  if (!jacobians) return true;
  if (jacobians[0]) {
    ceres::EigenQuaternionManifold manifold;
    Eigen::Matrix<double, 3, 4, Eigen::RowMajor> minus_jacobian;
    manifold.MinusJacobian(parameters[0], minus_jacobian.data());
    Eigen::Map<Eigen::Matrix<double, 15, 4, Eigen::RowMajor>> J_q(jacobians[0]);
    J_q = R.leftCols<3>() * minus_jacobian;
  }
  for (int block = 1; block < 5; ++block) {
    if (!jacobians[block]) continue;
    Eigen::Map<Eigen::Matrix<double, 15, 3, Eigen::RowMajor>> J_block(jacobians[block]);
    J_block = R.middleCols<3>(3 * block);
  }
  return true;
}

}  // namespace mavloc
