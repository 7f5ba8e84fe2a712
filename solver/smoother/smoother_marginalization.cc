#include "solver/smoother/smoother_marginalization.h"

#include <ceres/crs_matrix.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
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

// H = J^T J and g = J^T r of keyframes 0..m as the blocks of a chain (IMU factors couple
// consecutive keyframes, every other eliminated residual one keyframe): diag[k] = H_kk,
// upper[k] = H_k,k+1, g[k]; accumulated row by row from J's nonzeros (tangent columns, 15 per
// keyframe in time order). False, with *why, when a row couples keyframes that are not consecutive.
bool ChainBlocks(const ceres::CRSMatrix& J, const std::vector<double>& r, int m,
                 std::vector<Matrix15d>* diag, std::vector<Matrix15d>* upper,
                 std::vector<Vector15d>* g, std::string* why) {
  diag->assign(m + 1, Matrix15d::Zero());
  upper->assign(m, Matrix15d::Zero());
  g->assign(m + 1, Vector15d::Zero());
  for (int row = 0; row < J.num_rows; ++row) {
    for (int a = J.rows[row]; a < J.rows[row + 1]; ++a) {
      const int ka = J.cols[a] / kStateSize, ia = J.cols[a] % kStateSize;
      (*g)[ka](ia) += J.values[a] * r[row];
      for (int b = J.rows[row]; b < J.rows[row + 1]; ++b) {
        const int kb = J.cols[b] / kStateSize, ib = J.cols[b] % kStateSize;
        if (kb == ka) {
          (*diag)[ka](ia, ib) += J.values[a] * J.values[b];
        } else if (kb == ka + 1) {
          (*upper)[ka](ia, ib) += J.values[a] * J.values[b];
        } else if (kb != ka - 1) {
          *why = "a residual couples keyframes " + std::to_string(std::min(ka, kb)) + " and " +
                 std::to_string(std::max(ka, kb)) + ", which are not consecutive";
          return false;
        }
      }
    }
  }
  return true;
}

// The Schur complement onto keyframe m by block elimination along the chain, in time order (the
// block Cholesky factorization of H_oo, which has no fill outside the band):
//   S_0 = H_00, y_0 = g_0;  S_k+1 = H_k+1,k+1 - H_k,k+1^T S_k^-1 H_k,k+1,
//   y_k+1 = g_k+1 - H_k,k+1^T S_k^-1 y_k;  H_m = S_m, g_m = y_m.
bool SchurComplementOfChain(const ceres::CRSMatrix& J, const std::vector<double>& r, int m,
                            Matrix15d* H_m, Vector15d* g_m, std::string* why) {
  std::vector<Matrix15d> diag, upper;
  std::vector<Vector15d> g;
  if (!ChainBlocks(J, r, m, &diag, &upper, &g, why)) return false;
  Matrix15d S = diag[0];
  Vector15d y = g[0];
  for (int k = 0; k < m; ++k) {
    const Eigen::LLT<Matrix15d> llt(S);
    if (llt.info() != Eigen::Success) {
      *why = "the eliminated keyframes are not determined by their residuals";
      return false;
    }
    const Matrix15d A = llt.solve(upper[k]);  // S_k^-1 H_k,k+1
    S = diag[k + 1] - upper[k].transpose() * A;
    y = g[k + 1] - A.transpose() * y;
  }
  *H_m = S;
  *g_m = y;
  return true;
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
  Matrix15d H_m;
  Vector15d g_m;
  if (!SchurComplementOfChain(crs, residuals, m, &H_m, &g_m, why)) return std::nullopt;
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
