#include "solver/smoother/smoother_marginalization.h"

#include <ceres/crs_matrix.h>

#include <Eigen/Eigenvalues>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <algorithm>
#include <unordered_map>

namespace mavloc {

namespace {

constexpr int kStateSize = 15;  // tangent of (q, p, v, b_g, b_a)

// The residual blocks that touch keyframes 0..m-1, in the problem's order. Empty with *why when one
// of them also touches a free block outside keyframes 0..m. One pass over every residual block
// (asking Ceres for the residuals of each parameter block would need its per-block residual sets,
// which cost more to keep up while the problem is built than this pass).
std::vector<ceres::ResidualBlockId> EliminatedResiduals(
    ceres::Problem* problem, const std::vector<KeyframeBlockPointers>& keyframes, int m,
    std::string* why) {
  std::unordered_map<const double*, int> keyframe_of;
  for (int k = 0; k <= m; ++k)
    for (double* block : keyframes[k]) keyframe_of[block] = k;
  std::vector<ceres::ResidualBlockId> all, ids;
  problem->GetResidualBlocks(&all);
  std::vector<double*> blocks;
  for (const ceres::ResidualBlockId id : all) {
    problem->GetParameterBlocksForResidualBlock(id, &blocks);
    int first = m;
    bool foreign = false;
    for (double* block : blocks) {
      auto it = keyframe_of.find(block);
      if (it != keyframe_of.end())
        first = std::min(first, it->second);
      else if (!problem->IsParameterBlockConstant(block))
        foreign = true;
    }
    if (first == m) continue;  // touches no eliminated keyframe
    if (foreign) {
      *why = "a residual of keyframe " + std::to_string(first) +
             " also touches an estimated block that is not a keyframe state (landmark, plane or "
             "calibration), which a keyframe prior cannot carry to the next window";
      return {};
    }
    ids.push_back(id);
  }
  return ids;
}

}  // namespace

std::optional<KeyframeMarginalPrior> MarginalizeKeyframes(
    ceres::Problem* problem, const std::vector<KeyframeBlockPointers>& keyframes, int m,
    int num_threads, std::string* why) {
  if (m < 1 || m >= static_cast<int>(keyframes.size())) {
    *why = "no keyframe to marginalize onto";
    return std::nullopt;
  }
  const std::vector<ceres::ResidualBlockId> ids = EliminatedResiduals(problem, keyframes, m, why);
  if (ids.empty()) {
    if (why->empty()) *why = "no residual touches the keyframes to eliminate";
    return std::nullopt;
  }
  ceres::Problem::EvaluateOptions evaluate;
  for (int k = 0; k <= m; ++k) {
    for (double* block : keyframes[k]) {
      if (problem->IsParameterBlockConstant(block)) {
        *why = "keyframe " + std::to_string(k) + " has a constant block";
        return std::nullopt;
      }
      evaluate.parameter_blocks.push_back(block);
    }
  }
  evaluate.residual_blocks = ids;
  evaluate.num_threads = std::max(1, num_threads);
  double cost = 0.0;
  std::vector<double> residuals;
  ceres::CRSMatrix crs;
  if (!problem->Evaluate(evaluate, &cost, &residuals, nullptr, &crs)) {
    *why = "the eliminated residuals could not be evaluated";
    return std::nullopt;
  }
  const int cols = kStateSize * (m + 1);
  if (crs.num_cols != cols) {
    *why = "unexpected tangent size of a keyframe state";
    return std::nullopt;
  }
  const Eigen::Map<const Eigen::SparseMatrix<double, Eigen::RowMajor>> J(
      crs.num_rows, crs.num_cols, static_cast<int>(crs.values.size()), crs.rows.data(),
      crs.cols.data(), crs.values.data());
  const Eigen::Map<const Eigen::VectorXd> r(residuals.data(), static_cast<int>(residuals.size()));
  const Eigen::SparseMatrix<double> H = (J.transpose() * J).pruned();
  const Eigen::VectorXd g = J.transpose() * r;
  const int o = kStateSize * m;  // the eliminated columns come first (time order)
  const Eigen::SparseMatrix<double> H_oo = H.topLeftCorner(o, o);
  const Eigen::MatrixXd H_om = Eigen::MatrixXd(H.block(0, o, o, kStateSize));
  // Time order, no permutation: the factor of a keyframe chain has no fill outside its band.
  Eigen::SimplicialLLT<Eigen::SparseMatrix<double>, Eigen::Lower, Eigen::NaturalOrdering<int>> llt(
      H_oo);
  if (llt.info() != Eigen::Success) {
    *why = "the eliminated keyframes are not determined by their residuals";
    return std::nullopt;
  }
  const Eigen::MatrixXd X = llt.solve(H_om);  // H_oo^-1 H_om
  const Matrix15d H_m =
      Matrix15d(Eigen::MatrixXd(H.block(o, o, kStateSize, kStateSize))) - H_om.transpose() * X;
  const Vector15d g_m = g.tail<kStateSize>() - X.transpose() * g.head(o);
  // R^T R = H_m and R^T e = g_m from the eigen-decomposition H_m = V diag(l) V^T: R = diag(sqrt l)
  // V^T, e = diag(1 / sqrt l) V^T g_m, over the eigenvalues above rounding (a direction of x_m no
  // eliminated residual touches carries no information and gets a zero row).
  const Eigen::SelfAdjointEigenSolver<Matrix15d> eigen(0.5 * (H_m + H_m.transpose()));
  const double floor = 1e-12 * std::max(eigen.eigenvalues().maxCoeff(), 0.0);
  KeyframeMarginalPrior prior;
  for (int i = 0; i < kStateSize; ++i) {
    const double l = eigen.eigenvalues()[i];
    if (!(l > floor)) continue;
    const Vector15d v = eigen.eigenvectors().col(i);
    prior.sqrt_information.row(i) = std::sqrt(l) * v.transpose();
    prior.offset[i] = v.dot(g_m) / std::sqrt(l);
  }
  if (!prior.sqrt_information.allFinite() || !prior.offset.allFinite() ||
      prior.sqrt_information.isZero(0.0)) {
    *why = "the marginal prior is empty or not finite";
    return std::nullopt;
  }
  const KeyframeBlockPointers& b = keyframes[m];
  ImuKeyframeState& x = prior.linearization;
  x.q_W_B = Eigen::Quaterniond(b[0][3], b[0][0], b[0][1], b[0][2]).normalized();
  x.p_W = Eigen::Map<const Eigen::Vector3d>(b[1]);
  x.v_W = Eigen::Map<const Eigen::Vector3d>(b[2]);
  x.biases.b_g = Eigen::Map<const Eigen::Vector3d>(b[3]);
  x.biases.b_a = Eigen::Map<const Eigen::Vector3d>(b[4]);
  return prior;
}

}  // namespace mavloc
