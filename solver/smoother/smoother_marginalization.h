// Marginalization of the first keyframes of a smoother window onto a later keyframe: the linear
// Gaussian factor (residuals/marginal_prior_factor.h) that replaces the eliminated states and every
// residual that touches them, at the current estimate.
//
// With J and r the Jacobian (tangent space, robust-loss corrections applied, as Ceres evaluates
// them) and residuals of those residual blocks over the states x_0 .. x_m of keyframes 0..m in
// time order, H = J^T J and g = J^T r, the quadratic model 0.5 |r + J dx|^2 minimized over
// x_0 .. x_{m-1} leaves on x_m
//   H_m = H_mm - H_mo H_oo^-1 H_om,   g_m = g_m - H_mo H_oo^-1 g_o       (Schur complement).
// IMU factors chain consecutive keyframes and every other eliminated residual touches one
// keyframe, so H is block-tridiagonal: it is accumulated as 15 x 15 blocks and H_oo eliminated by
// a block Cholesky along the chain in time order (no fill; linear in m). The factor
// r_prior = R dx_m + e has the same
// Hessian and gradient: R^T R = H_m, R^T e = g_m (R from the eigen-decomposition of H_m, so that a
// direction no eliminated residual informs gets no information rather than a failure).
#pragma once

#include <ceres/problem.h>

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "solver/smoother/residuals/marginal_prior_factor.h"

namespace mavloc {

// A keyframe's parameter blocks in the smoother: q (4, Ceres' EigenQuaternionManifold), p, v, b_g,
// b_a (3 each).
using KeyframeBlockPointers = std::array<double*, 5>;

// Eliminates keyframes 0..m-1 of `keyframes` (time order) onto keyframe m. Nullopt, with the reason
// in *why, when a residual that touches them also touches a parameter block that is neither one of
// keyframes 0..m nor constant (a landmark, a plane, a calibration block: a window cannot hand those
// on in a keyframe prior), when a residual couples keyframes that are not consecutive, or when the
// eliminated states are not determined by their residuals.
std::optional<KeyframeMarginalPrior> MarginalizeKeyframes(
    ceres::Problem* problem, const std::vector<KeyframeBlockPointers>& keyframes, int m,
    int num_threads, std::string* why);

}  // namespace mavloc
