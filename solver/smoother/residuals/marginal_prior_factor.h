// The prior a window of the smoother hands to the next (solver/smoother/smoother_windows.h): what
// the measurements before the window's first keyframe said about that keyframe's state, as a
// linear Gaussian factor on its tangent space at a fixed linearization point x_lin:
//   r = R delta + e,   delta = [q (-) q_lin; p - p_lin; v - v_lin; b_g - b_g_lin; b_a - b_a_lin],
// with q (-) q_lin Ceres' EigenQuaternionManifold difference (the tangent the smoother's Jacobians
// use). R^T R is the Schur complement of the marginalized states and R^T e its gradient
// (solver/smoother/smoother_marginalization.h): the factor is the quadratic model of everything
// eliminated (Sibley et al., "Sliding window filter", 2010; Basalt's square-root marginalization,
// Demmel et al. 2021, keeps the same linear factor at a fixed linearization point).
// The Jacobian is R in the tangent at the current estimate (the first-order model at x_lin, as the
// factor is linear in delta): R times Ceres' MinusJacobian in ambient coordinates.
#pragma once

#include <ceres/sized_cost_function.h>

#include <Eigen/Core>

#include "solver/smoother/imu_preintegration.h"

namespace mavloc {

using Matrix15d = Eigen::Matrix<double, 15, 15>;
using Vector15d = Eigen::Matrix<double, 15, 1>;

// The marginal prior on one keyframe's state [dtheta (Ceres' quaternion tangent), p, v, b_g, b_a].
struct KeyframeMarginalPrior {
  ImuKeyframeState linearization;
  Matrix15d sqrt_information = Matrix15d::Zero();  // R
  Vector15d offset = Vector15d::Zero();            // e
};

class MarginalPriorFactor : public ceres::SizedCostFunction<15, 4, 3, 3, 3, 3> {
 public:
  explicit MarginalPriorFactor(const KeyframeMarginalPrior& prior);

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

  // delta of the header comment: the state (q, p, v, b_g, b_a blocks, quaternion in Eigen order
  // x, y, z, w) minus the linearization point.
  Vector15d Delta(double const* const* parameters) const;

 private:
  KeyframeMarginalPrior prior_;
  double q_lin_[4];
};

}  // namespace mavloc
