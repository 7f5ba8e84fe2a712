// Fisher information of a Markov chain of states x_0 .. x_{n-1} (a block-tridiagonal information
// matrix) and its two Cramér–Rao bounds:
// - filtering (causal): the posterior CRLB recursion of Tichavsky, Muravchik and Nehorai,
// "Posterior
//   Cramér–Rao bounds for discrete-time nonlinear filtering", IEEE TSP 46(5), 1998, eq. (21):
//     J_{k+1} = D22_k + M_{k+1} - D21_k (J_k + D11_k)^-1 D12_k,   J_0 = M_0,
//   where for a transition x_{k+1} = f(x_k) + w_k, w_k ~ N(0, Q_k), linearised as Phi_k:
//     D11 = Phi^T Q^-1 Phi, D12 = D21^T = -Phi^T Q^-1, D22 = Q^-1 (their eq. 34-36),
//   and M_k the information of the measurements (and priors) at step k;
// - smoothing (the whole batch): the diagonal blocks of the inverse of the full information matrix
//   H (diagonal blocks M_k + D22_{k-1} + D11_k, off-diagonal D12_k), by the forward Schur
//   complements S_k = J_k + D11_k and the backward selected-inversion pass
//     Sigma_{n-1} = S_{n-1}^-1,  Sigma_k = S_k^-1 + G_k Sigma_{k+1} G_k^T,  G_k = -S_k^-1 D12_k
//   (the information-form Rauch–Tung–Striebel recursion), linear in n; no dense inverse.
// Numerics: with the transition's Phi and Q (AddTransition keeps them), the forward pass runs in a
// square-root form that needs neither Q^-1 nor a subtraction. With Q = R R^T, T = Phi^-1 R and
// C = T^T J_k T (Woodbury identity):
//     S_k^-1 = T (I + C)^-1 T^T,   G_k = T (I + C)^-1 R^-1,
//     J_{k+1} = M_{k+1} + R^-T (I + C)^-1 C R^-1   (= M_{k+1} + (Q + Phi J_k^-1 Phi^T)^-1),
// where I + C has its eigenvalues >= 1. The information form D22 - D21 S^-1 D12 subtracts two
// numbers of the size of Q^-1 (1e15 for the IMU's bias-walk floors over one keyframe interval)
// to get one of the size of J_k, and loses the digits of the result; it remains the fallback
// for edges without Phi and Q. H is then singular exactly when the last Schur complement
// J_{n-1} is.
// Optional static nuisance parameters d (m of them, e.g. a board's 2-DoF tilt to gravity) coupled
// to every state: H = [[A, B], [B^T, C]] with A the block-tridiagonal part above. The smoothing
// bound marginalises d out exactly (the CRLB with nuisance parameters, e.g. Kay, "Fundamentals of
// Statistical Signal Processing: Estimation Theory", 1993, sec. 3.7): by the block inverse,
//   Sigma_dd = (C - B^T A^-1 B)^-1,  Sigma_xd = -A^-1 B Sigma_dd,
//   Sigma_xx,k = (A^-1)_kk + (A^-1 B)_k Sigma_dd (A^-1 B)_k^T,
// where A^-1 B is two block-tridiagonal solves with the same forward factors S_k (still linear in
// n). The filtering bound with d: when the nuisance information is also given per state
// (nuisance_node, C = prior + sum C_k), the recursion runs on the augmented (x_k, d), a static
// parameter with no process noise, by marginalising x_k out of the joint information of
// (x_k, x_{k+1}, d) at each step:
//   Ja_{k+1} = [[D22_k + M_{k+1}, B_{k+1}], [B_{k+1}^T, Ja_dd + C_{k+1}]]
//              - R^T (Ja_xx + D11_k)^-1 R,   R = [D12_k, Ja_xd],
// and filtering[k] is the (x, x) block of Ja_k^-1. Without nuisance_node the filtering bound
// ignores the coupling: the bound with d known, smaller, still a lower bound but not a tight one.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <vector>

namespace mavloc {

struct MarkovInformation {
  // M_k: information of everything attached to state k alone (measurements, priors); size n.
  std::vector<Eigen::MatrixXd> node;
  // Transition information of the edge k -> k+1 when given directly (size n - 1); empty for edges
  // that came from AddTransition (TransitionBlocks computes them from phi and q when needed: a
  // 15-state chain of an hour at 20 Hz would otherwise hold three more 15 x 15 blocks per state).
  std::vector<Eigen::MatrixXd> d11, d12, d22;
  // The transitions themselves (size n - 1 when every edge came from AddTransition; else empty and
  // the forward pass uses the information form).
  std::vector<Eigen::MatrixXd> phi, q;
  // Static nuisance parameters: B_k (dim of state k x m) per state (size n or empty) and C (m x m).
  std::vector<Eigen::MatrixXd> coupling;
  Eigen::MatrixXd nuisance;
  // Optional: the part C_k of `nuisance` from the measurements of state k (size n; for the
  // filtering bound with d; the rest of `nuisance` is a prior).
  std::vector<Eigen::MatrixXd> nuisance_node;

  int size() const { return static_cast<int>(node.size()); }
  // Adds the edge k -> k+1 of a linear(ised) transition x_{k+1} = Phi x_k + w, w ~ N(0, Q).
  void AddTransition(const Eigen::MatrixXd& Phi, const Eigen::MatrixXd& Q);
  // D11, D12, D22 of edge k: the given ones, else from phi[k] and q[k] (their eq. 34-36).
  void TransitionBlocks(int k, Eigen::MatrixXd* D11, Eigen::MatrixXd* D12,
                        Eigen::MatrixXd* D22) const;
};

struct MarkovBounds {
  // Smoothing covariance bound per state (the diagonal blocks of H^-1); empty when H is singular.
  std::vector<Eigen::MatrixXd> smoothing;
  // Filtering covariance bound J_k^-1 per state; nullopt where J_k is singular (nothing seen yet).
  std::vector<std::optional<Eigen::MatrixXd>> filtering;
  bool smoothing_ok = false;
  // With nuisance parameters: Sigma_xd per state (dim x m) and Sigma_dd (m x m); else empty.
  std::vector<Eigen::MatrixXd> smoothing_cross;
  Eigen::MatrixXd nuisance_covariance;
  // With nuisance_node: the filtering Sigma_xd (dim x m) and Sigma_dd (m x m) per state, set where
  // filtering[k] is.
  std::vector<Eigen::MatrixXd> filtering_cross, filtering_nuisance;
};

// Both bounds (filtering by the forward recursion, smoothing by forward + backward passes).
MarkovBounds ComputeMarkovBounds(const MarkovInformation& information);
// The same, consuming the information: each state's blocks are released once the forward pass has
// used them, and each Schur complement once the backward pass has (without nuisance parameters),
// so that the pass holds about four 15 x 15 blocks per state instead of eleven. Same numbers.
MarkovBounds ComputeMarkovBounds(MarkovInformation&& information);

// The full information matrix H as a dense matrix (tests and small problems only).
Eigen::MatrixXd DenseInformation(const MarkovInformation& information);

}  // namespace mavloc
