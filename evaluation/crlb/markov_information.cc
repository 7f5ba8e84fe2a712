#include "evaluation/crlb/markov_information.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>

namespace mavloc {

namespace {

// Inverse of a symmetric positive definite matrix, or nullopt when it is not numerically positive
// definite. Jacobi-scaled first (the blocks mix metres, radians and biases over many decades): the
// scaled matrix must have its smallest eigenvalue above 1e-12 of the largest.
std::optional<Eigen::MatrixXd> SpdInverse(const Eigen::MatrixXd& A) {
  const Eigen::VectorXd diagonal = A.diagonal();
  if (!(diagonal.minCoeff() > 0.0)) return std::nullopt;
  const Eigen::VectorXd d = diagonal.cwiseSqrt().cwiseInverse();
  Eigen::MatrixXd S = d.asDiagonal() * A * d.asDiagonal();
  S = 0.5 * (S + S.transpose()).eval();
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(S);
  if (eig.info() != Eigen::Success) return std::nullopt;
  const Eigen::VectorXd& l = eig.eigenvalues();
  if (!(l.maxCoeff() > 0.0) || l.minCoeff() <= 1e-12 * l.maxCoeff()) return std::nullopt;
  const Eigen::MatrixXd S_inv =
      eig.eigenvectors() * l.cwiseInverse().asDiagonal() * eig.eigenvectors().transpose();
  return d.asDiagonal() * S_inv * d.asDiagonal();
}

// The filtering bound on the augmented state (x_k, d) (see the header).
void AugmentedFiltering(const MarkovInformation& info, MarkovBounds* bounds) {
  const int n = info.size();
  const int m = static_cast<int>(info.nuisance.rows());
  Eigen::MatrixXd prior = info.nuisance;
  for (const Eigen::MatrixXd& C : info.nuisance_node) prior -= C;
  const auto joint = [&](int k, const Eigen::MatrixXd& xx, const Eigen::MatrixXd& dd) {
    const int dim = static_cast<int>(xx.rows());
    Eigen::MatrixXd Ja(dim + m, dim + m);
    Ja.topLeftCorner(dim, dim) = xx;
    Ja.topRightCorner(dim, m) = info.coupling[k];
    Ja.bottomLeftCorner(m, dim) = info.coupling[k].transpose();
    Ja.bottomRightCorner(m, m) = dd + info.nuisance_node[k];
    return Ja;
  };
  Eigen::MatrixXd Ja = joint(0, info.node[0], prior);
  bounds->filtering_cross.assign(n, Eigen::MatrixXd());
  bounds->filtering_nuisance.assign(n, Eigen::MatrixXd());
  for (int k = 0; k < n; ++k) {
    const int dim = static_cast<int>(info.node[k].rows());
    if (const auto P = SpdInverse(0.5 * (Ja + Ja.transpose()))) {
      bounds->filtering[k] = P->topLeftCorner(dim, dim);
      bounds->filtering_cross[k] = P->topRightCorner(dim, m);
      bounds->filtering_nuisance[k] = P->bottomRightCorner(m, m);
    }
    if (k + 1 == n) break;
    Eigen::MatrixXd D11, D12, D22;
    info.TransitionBlocks(k, &D11, &D12, &D22);
    const Eigen::MatrixXd A = Ja.topLeftCorner(dim, dim) + D11;
    const auto A_inv = SpdInverse(0.5 * (A + A.transpose()));
    if (!A_inv) return;  // not expected: D11 = Phi^T Q^-1 Phi is positive definite
    Eigen::MatrixXd R(dim, D12.cols() + m);
    R.leftCols(D12.cols()) = D12;
    R.rightCols(m) = Ja.topRightCorner(dim, m);
    Eigen::MatrixXd next = joint(k + 1, info.node[k + 1] + D22, Ja.bottomRightCorner(m, m));
    next -= R.transpose() * *A_inv * R;
    Ja = 0.5 * (next + next.transpose());
  }
}

}  // namespace

void MarkovInformation::AddTransition(const Eigen::MatrixXd& Phi, const Eigen::MatrixXd& Q) {
  phi.push_back(Phi);
  q.push_back(0.5 * (Q + Q.transpose()));
}

void MarkovInformation::TransitionBlocks(int k, Eigen::MatrixXd* D11, Eigen::MatrixXd* D12,
                                         Eigen::MatrixXd* D22) const {
  if (k < static_cast<int>(d11.size())) {
    *D11 = d11[k];
    *D12 = d12[k];
    *D22 = d22[k];
    return;
  }
  // Q is positive definite for any noisy model; the scaled inverse keeps the precision where its
  // entries span many decades (position noise ~1e-12 m^2 beside bias walks ~1e-7).
  const Eigen::MatrixXd& Phi = phi[k];
  const Eigen::MatrixXd& Q = q[k];
  const std::optional<Eigen::MatrixXd> inverse = SpdInverse(Q);
  const Eigen::MatrixXd Q_inv = inverse ? *inverse
                                        : Eigen::MatrixXd(Eigen::LLT<Eigen::MatrixXd>(Q).solve(
                                              Eigen::MatrixXd::Identity(Q.rows(), Q.cols())));
  const Eigen::MatrixXd Q_inv_s = 0.5 * (Q_inv + Q_inv.transpose());
  *D11 = Phi.transpose() * Q_inv_s * Phi;
  *D12 = -Phi.transpose() * Q_inv_s;
  *D22 = Q_inv_s;
}

namespace {

// One step of the forward pass in the square-root form (see the header): from J_k and the edge's
// Phi, Q = R R^T, with T = Phi^-1 R and C = T^T J_k T,
//   S_k^-1 = T (I + C)^-1 T^T,  G_k = T (I + C)^-1 R^-1,  J_{k+1} - M_{k+1} = R^-T (I + C)^-1 C
//   R^-1.
// False when Q is not positive definite or Phi is singular (the caller uses the information form).
bool SquareRootStep(const Eigen::MatrixXd& J, const Eigen::MatrixXd& Phi, const Eigen::MatrixXd& Q,
                    Eigen::MatrixXd* S_inv, Eigen::MatrixXd* G, Eigen::MatrixXd* J_pred) {
  const Eigen::LLT<Eigen::MatrixXd> chol_Q(Q);
  if (chol_Q.info() != Eigen::Success) return false;
  const Eigen::MatrixXd R = chol_Q.matrixL();
  const Eigen::FullPivLU<Eigen::MatrixXd> lu(Phi);
  if (!lu.isInvertible()) return false;
  const Eigen::MatrixXd T = lu.solve(R);
  const int dim = static_cast<int>(J.rows());
  const Eigen::MatrixXd I = Eigen::MatrixXd::Identity(dim, dim);
  const Eigen::MatrixXd R_inv = R.triangularView<Eigen::Lower>().solve(I);
  Eigen::MatrixXd C = T.transpose() * J * T;
  C = 0.5 * (C + C.transpose()).eval();
  const Eigen::LLT<Eigen::MatrixXd> chol(I + C);  // eigenvalues >= 1 when J is PSD
  if (chol.info() != Eigen::Success) return false;
  const Eigen::MatrixXd S = T * chol.solve(T.transpose());
  *S_inv = 0.5 * (S + S.transpose());
  *G = T * chol.solve(R_inv);
  const Eigen::MatrixXd X = chol.solve(C);  // (I + C)^-1 C, symmetric
  const Eigen::MatrixXd P = R_inv.transpose() * (0.5 * (X + X.transpose())) * R_inv;
  *J_pred = 0.5 * (P + P.transpose());
  return true;
}

}  // namespace

MarkovBounds ComputeMarkovBounds(const MarkovInformation& info) {
  return ComputeMarkovBounds(MarkovInformation(info));
}

MarkovBounds ComputeMarkovBounds(MarkovInformation&& info) {
  MarkovBounds bounds;
  const int n = info.size();
  if (n == 0) return bounds;
  const int m = static_cast<int>(info.nuisance.rows());
  const bool augmented = m > 0 && static_cast<int>(info.coupling.size()) == n &&
                         static_cast<int>(info.nuisance_node.size()) == n;
  const bool nuisance = m > 0 && static_cast<int>(info.coupling.size()) == n;
  // Forward: J_k (filtering information, kept for the current state only), S_k^-1 =
  // (J_k + D11_k)^-1 (smoothing Schur complements) and G_k = -S_k^-1 D12_k. With the edge's Phi and
  // Q, in the square-root form (no Q^-1, no subtraction); else in the information form. The
  // filtering bound J_k^-1 as J_k is known (with nuisance_node: AugmentedFiltering, which needs
  // every block, so nothing is released then).
  std::vector<Eigen::MatrixXd> S_inv(n), G(n);
  bounds.filtering.assign(n, std::nullopt);
  const bool have_phi_q =
      static_cast<int>(info.phi.size()) == n - 1 && static_cast<int>(info.q.size()) == n - 1;
  bool ok = true;
  Eigen::MatrixXd J = info.node[0];
  for (int k = 0; k < n; ++k) {
    if (!augmented) bounds.filtering[k] = SpdInverse(J);
    Eigen::MatrixXd J_pred, J_next;
    if (k + 1 < n && have_phi_q &&
        SquareRootStep(J, info.phi[k], info.q[k], &S_inv[k], &G[k], &J_pred)) {
      J_next = info.node[k + 1] + J_pred;
    } else {
      Eigen::MatrixXd D11, D12, D22;
      if (k + 1 < n) info.TransitionBlocks(k, &D11, &D12, &D22);
      const Eigen::MatrixXd S = k + 1 < n ? Eigen::MatrixXd(J + D11) : J;
      auto inv = SpdInverse(S);
      if (!inv) {
        ok = false;  // the filtering bound stops here too (no J_{k+1})
        break;
      }
      S_inv[k] = *inv;
      if (k + 1 < n) {
        G[k] = -S_inv[k] * D12;
        J_next = info.node[k + 1] + D22 - D12.transpose() * S_inv[k] * D12;
      }
    }
    if (!augmented) {  // this state's blocks are used up
      info.node[k] = Eigen::MatrixXd();
      if (k < static_cast<int>(info.phi.size())) info.phi[k] = info.q[k] = Eigen::MatrixXd();
    }
    J = std::move(J_next);
  }
  if (augmented) AugmentedFiltering(info, &bounds);
  if (!ok) return bounds;
  // Backward selected inversion. Without nuisance parameters (which need S_k^-1 and G_k again)
  // each Sigma_k takes the storage of S_k^-1 and G_k is released as soon as it is used.
  if (nuisance) {
    bounds.smoothing = S_inv;
  } else {
    bounds.smoothing = std::move(S_inv);
    S_inv.clear();
  }
  for (int k = n - 2; k >= 0; --k) {
    const Eigen::MatrixXd C =
        bounds.smoothing[k] + G[k] * bounds.smoothing[k + 1] * G[k].transpose();
    bounds.smoothing[k] = 0.5 * (C + C.transpose());
    if (!nuisance) G[k] = Eigen::MatrixXd();
  }
  if (nuisance) {
    // Y = A^-1 B: forward z_k = B_k - D12_{k-1}^T S_{k-1}^-1 z_{k-1}, backward
    // Y_{n-1} = S_{n-1}^-1 z_{n-1}, Y_k = S_k^-1 z_k + G_k Y_{k+1}.
    std::vector<Eigen::MatrixXd> Y(n);
    Y[0] = info.coupling[0];
    for (int k = 1; k < n; ++k) Y[k] = info.coupling[k] + G[k - 1].transpose() * Y[k - 1];
    Y[n - 1] = S_inv[n - 1] * Y[n - 1];
    for (int k = n - 2; k >= 0; --k) Y[k] = S_inv[k] * Y[k] + G[k] * Y[k + 1];
    Eigen::MatrixXd schur = info.nuisance;
    for (int k = 0; k < n; ++k) schur -= info.coupling[k].transpose() * Y[k];
    const std::optional<Eigen::MatrixXd> sigma_dd = SpdInverse(0.5 * (schur + schur.transpose()));
    if (!sigma_dd) return bounds;  // the nuisance is not identifiable: no bound
    bounds.nuisance_covariance = *sigma_dd;
    bounds.smoothing_cross.resize(n);
    for (int k = 0; k < n; ++k) {
      bounds.smoothing_cross[k] = -Y[k] * *sigma_dd;
      const Eigen::MatrixXd C = bounds.smoothing[k] + Y[k] * *sigma_dd * Y[k].transpose();
      bounds.smoothing[k] = 0.5 * (C + C.transpose());
    }
  }
  bounds.smoothing_ok = true;
  return bounds;
}

Eigen::MatrixXd DenseInformation(const MarkovInformation& info) {
  const int n = info.size();
  std::vector<int> offset(n + 1, 0);
  for (int k = 0; k < n; ++k) offset[k + 1] = offset[k] + static_cast<int>(info.node[k].rows());
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(offset[n], offset[n]);
  for (int k = 0; k < n; ++k) {
    const int a = offset[k], da = static_cast<int>(info.node[k].rows());
    H.block(a, a, da, da) += info.node[k];
    if (k + 1 < n) {
      const int b = offset[k + 1], db = static_cast<int>(info.node[k + 1].rows());
      Eigen::MatrixXd D11, D12, D22;
      info.TransitionBlocks(k, &D11, &D12, &D22);
      H.block(a, a, da, da) += D11;
      H.block(a, b, da, db) += D12;
      H.block(b, a, db, da) += D12.transpose();
      H.block(b, b, db, db) += D22;
    }
  }
  return H;
}

}  // namespace mavloc
