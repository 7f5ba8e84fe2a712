#include "evaluation/crlb/markov_information.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

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
    const Eigen::MatrixXd A = Ja.topLeftCorner(dim, dim) + info.d11[k];
    const auto A_inv = SpdInverse(0.5 * (A + A.transpose()));
    if (!A_inv) return;  // not expected: D11 = Phi^T Q^-1 Phi is positive definite
    Eigen::MatrixXd R(dim, info.d12[k].cols() + m);
    R.leftCols(info.d12[k].cols()) = info.d12[k];
    R.rightCols(m) = Ja.topRightCorner(dim, m);
    Eigen::MatrixXd next = joint(k + 1, info.node[k + 1] + info.d22[k], Ja.bottomRightCorner(m, m));
    next -= R.transpose() * *A_inv * R;
    Ja = 0.5 * (next + next.transpose());
  }
}

}  // namespace

void MarkovInformation::AddTransition(const Eigen::MatrixXd& Phi, const Eigen::MatrixXd& Q) {
  // Q is positive definite for any noisy model; the scaled inverse keeps the precision where its
  // entries span many decades (position noise ~1e-12 m^2 beside bias walks ~1e-7).
  const std::optional<Eigen::MatrixXd> inverse = SpdInverse(Q);
  const Eigen::MatrixXd Q_inv =
      inverse ? *inverse
              : Eigen::MatrixXd(Eigen::LLT<Eigen::MatrixXd>(0.5 * (Q + Q.transpose()))
                                    .solve(Eigen::MatrixXd::Identity(Q.rows(), Q.cols())));
  const Eigen::MatrixXd Q_inv_s = 0.5 * (Q_inv + Q_inv.transpose());
  d11.push_back(Phi.transpose() * Q_inv_s * Phi);
  d12.push_back(-Phi.transpose() * Q_inv_s);
  d22.push_back(Q_inv_s);
}

MarkovBounds ComputeMarkovBounds(const MarkovInformation& info) {
  MarkovBounds bounds;
  const int n = info.size();
  if (n == 0) return bounds;
  // Forward: J_k (filtering information) and S_k = J_k + D11_k (smoothing Schur complements).
  std::vector<Eigen::MatrixXd> J(n), S(n), S_inv(n);
  bool ok = true;
  J[0] = info.node[0];
  for (int k = 0; k < n; ++k) {
    S[k] = k + 1 < n ? Eigen::MatrixXd(J[k] + info.d11[k]) : J[k];
    auto inv = SpdInverse(S[k]);
    if (!inv) {
      ok = false;
      break;
    }
    S_inv[k] = *inv;
    if (k + 1 < n)
      J[k + 1] = info.node[k + 1] + info.d22[k] - info.d12[k].transpose() * S_inv[k] * info.d12[k];
  }
  bounds.filtering.assign(n, std::nullopt);
  const int m = static_cast<int>(info.nuisance.rows());
  const bool augmented = m > 0 && static_cast<int>(info.coupling.size()) == n &&
                         static_cast<int>(info.nuisance_node.size()) == n;
  if (augmented) {
    AugmentedFiltering(info, &bounds);
  } else {
    for (int k = 0; k < n; ++k) {
      if (J[k].size() == 0) break;
      bounds.filtering[k] = SpdInverse(J[k]);
    }
  }
  if (!ok) return bounds;
  // Backward selected inversion.
  bounds.smoothing.assign(n, Eigen::MatrixXd());
  bounds.smoothing[n - 1] = S_inv[n - 1];
  for (int k = n - 2; k >= 0; --k) {
    const Eigen::MatrixXd G = -S_inv[k] * info.d12[k];
    const Eigen::MatrixXd C = S_inv[k] + G * bounds.smoothing[k + 1] * G.transpose();
    bounds.smoothing[k] = 0.5 * (C + C.transpose());
  }
  if (m > 0 && static_cast<int>(info.coupling.size()) == n) {
    // Y = A^-1 B: forward z_k = B_k - D12_{k-1}^T S_{k-1}^-1 z_{k-1}, backward
    // Y_{n-1} = S_{n-1}^-1 z_{n-1}, Y_k = S_k^-1 z_k + G_k Y_{k+1}.
    std::vector<Eigen::MatrixXd> Y(n);
    Y[0] = info.coupling[0];
    for (int k = 1; k < n; ++k)
      Y[k] = info.coupling[k] - info.d12[k - 1].transpose() * (S_inv[k - 1] * Y[k - 1]);
    Y[n - 1] = S_inv[n - 1] * Y[n - 1];
    for (int k = n - 2; k >= 0; --k) Y[k] = S_inv[k] * Y[k] - S_inv[k] * info.d12[k] * Y[k + 1];
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
      H.block(a, a, da, da) += info.d11[k];
      H.block(a, b, da, db) += info.d12[k];
      H.block(b, a, db, da) += info.d12[k].transpose();
      H.block(b, b, db, db) += info.d22[k];
    }
  }
  return H;
}

}  // namespace mavloc
