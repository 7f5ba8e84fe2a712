// The block-tridiagonal bounds (evaluation/crlb/markov_information.h) on a linear-Gaussian chain,
// where the Cramér–Rao bounds are exact: the filtering bound equals the Kalman filter's covariance
// P_{k|k} and the smoothing bound the Rauch–Tung–Striebel smoother's P_{k|N}, both computed here
// in covariance form (an independent path), and the smoothing bound equals the diagonal blocks of
// the dense inverse of the full information matrix.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>

#include "core/random.h"
#include "evaluation/crlb/markov_information.h"

namespace mavloc {
namespace {

Eigen::MatrixXd RandomMatrix(int rows, int cols, Rng& rng) {
  Eigen::MatrixXd M(rows, cols);
  for (int i = 0; i < rows; ++i)
    for (int j = 0; j < cols; ++j) M(i, j) = rng.Gaussian(0.0, 1.0);
  return M;
}

Eigen::MatrixXd RandomSpd(int n, double scale, Rng& rng) {
  const Eigen::MatrixXd A = RandomMatrix(n, n, rng);
  return scale * (A * A.transpose() + 0.5 * Eigen::MatrixXd::Identity(n, n));
}

double RelativeDifference(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return (a - b).norm() / b.norm();
}

struct Chain {
  std::vector<Eigen::MatrixXd> F, Q, H, R;
  Eigen::MatrixXd P0;
  int n = 0;
};

// x_{k+1} = F_k x_k + w_k, z_k = H_k x_k + v_k, x_0 ~ N(m, P0); some steps without measurement.
Chain MakeChain(int n, int dim, uint64_t seed) {
  Rng rng(seed);
  Chain c;
  c.n = n;
  c.P0 = RandomSpd(dim, 4.0, rng);
  for (int k = 0; k < n; ++k) {
    const int m = k % 4 == 3 ? 0 : 2;  // every fourth step without measurement
    c.H.push_back(RandomMatrix(m, dim, rng));
    c.R.push_back(RandomSpd(m, 0.3, rng));
    if (k + 1 < n) {
      c.F.push_back(Eigen::MatrixXd::Identity(dim, dim) + 0.3 * RandomMatrix(dim, dim, rng));
      c.Q.push_back(RandomSpd(dim, 0.05, rng));
    }
  }
  return c;
}

MarkovInformation InformationOf(const Chain& c) {
  MarkovInformation info;
  for (int k = 0; k < c.n; ++k) {
    Eigen::MatrixXd M = c.H[k].rows() > 0
                            ? Eigen::MatrixXd(c.H[k].transpose() * c.R[k].inverse() * c.H[k])
                            : Eigen::MatrixXd::Zero(c.P0.rows(), c.P0.cols());
    if (k == 0) M += c.P0.inverse();
    info.node.push_back(M);
    if (k + 1 < c.n) info.AddTransition(c.F[k], c.Q[k]);
  }
  return info;
}

// Kalman filter and RTS smoother in covariance form: P_{k|k} and P_{k|N}.
struct KalmanCovariances {
  std::vector<Eigen::MatrixXd> filtering, smoothing;
};

KalmanCovariances KalmanAndRts(const Chain& c) {
  std::vector<Eigen::MatrixXd> P_filt(c.n), P_pred(c.n), P_smooth(c.n);
  for (int k = 0; k < c.n; ++k) {
    P_pred[k] =
        k == 0 ? c.P0
               : Eigen::MatrixXd(c.F[k - 1] * P_filt[k - 1] * c.F[k - 1].transpose() + c.Q[k - 1]);
    if (c.H[k].rows() > 0) {
      const Eigen::MatrixXd S = c.H[k] * P_pred[k] * c.H[k].transpose() + c.R[k];
      const Eigen::MatrixXd K = P_pred[k] * c.H[k].transpose() * S.inverse();
      const Eigen::MatrixXd I = Eigen::MatrixXd::Identity(c.P0.rows(), c.P0.cols());
      // Joseph form.
      P_filt[k] =
          (I - K * c.H[k]) * P_pred[k] * (I - K * c.H[k]).transpose() + K * c.R[k] * K.transpose();
    } else {
      P_filt[k] = P_pred[k];
    }
  }
  P_smooth[c.n - 1] = P_filt[c.n - 1];
  for (int k = c.n - 2; k >= 0; --k) {
    const Eigen::MatrixXd G = P_filt[k] * c.F[k].transpose() * P_pred[k + 1].inverse();
    P_smooth[k] = P_filt[k] + G * (P_smooth[k + 1] - P_pred[k + 1]) * G.transpose();
  }
  return {P_filt, P_smooth};
}

TEST(CrlbMarkov, FilteringAndSmoothingBoundsEqualKalmanAndRtsCovariances) {
  const Chain c = MakeChain(40, 4, 11);
  const KalmanCovariances kalman = KalmanAndRts(c);
  const std::vector<Eigen::MatrixXd>& P_filt = kalman.filtering;
  const std::vector<Eigen::MatrixXd>& P_smooth = kalman.smoothing;

  const MarkovBounds bounds = ComputeMarkovBounds(InformationOf(c));
  ASSERT_TRUE(bounds.smoothing_ok);
  for (int k = 0; k < c.n; ++k) {
    ASSERT_TRUE(bounds.filtering[k].has_value()) << k;
    EXPECT_LT(RelativeDifference(*bounds.filtering[k], P_filt[k]), 1e-9) << "filtering " << k;
    EXPECT_LT(RelativeDifference(bounds.smoothing[k], P_smooth[k]), 1e-9) << "smoothing " << k;
  }
  // Smoothing never above filtering (more data).
  for (int k = 0; k < c.n; ++k)
    EXPECT_LE(bounds.smoothing[k].trace(), bounds.filtering[k]->trace() * (1 + 1e-12));
}

// A nearly constant state (process noise 1e-15 beside unit measurement noise, as the IMU bias
// walks beside weak laser information): the information form's D22 - D21 S^-1 D12 subtracts
// numbers near 1e15 and loses every digit of the result; the square-root form keeps the Kalman
// filter's and RTS smoother's covariances.
TEST(CrlbMarkov, StiffProcessNoiseKeepsItsPrecision) {
  Chain c;
  c.n = 300;
  c.P0 = Eigen::MatrixXd::Identity(2, 2) * 100.0;
  Eigen::MatrixXd F(2, 2), H(1, 2);
  F << 1.0, 0.1, 0.0, 1.0;  // position and a drift rate
  H << 1.0, 0.0;
  for (int k = 0; k < c.n; ++k) {
    c.H.push_back(H);
    c.R.push_back(Eigen::MatrixXd::Identity(1, 1));
    if (k + 1 < c.n) {
      c.F.push_back(F);
      Eigen::MatrixXd Q(2, 2);
      Q << 1e-15, 0.0, 0.0, 1e-17;
      c.Q.push_back(Q);
    }
  }
  const KalmanCovariances kalman = KalmanAndRts(c);
  const MarkovBounds bounds = ComputeMarkovBounds(InformationOf(c));
  ASSERT_TRUE(bounds.smoothing_ok);
  for (int k = 0; k < c.n; k += 10) {
    ASSERT_TRUE(bounds.filtering[k].has_value()) << k;
    EXPECT_LT(RelativeDifference(*bounds.filtering[k], kalman.filtering[k]), 1e-6) << k;
    EXPECT_LT(RelativeDifference(bounds.smoothing[k], kalman.smoothing[k]), 1e-6) << k;
  }
  // After 300 unit-noise measurements of an almost constant position, its bound is about
  // 1 / sqrt(300) (the drift rate takes some of the information).
  EXPECT_NEAR(std::sqrt(bounds.smoothing[150](0, 0)), 1.0 / std::sqrt(300.0), 0.01);
}

TEST(CrlbMarkov, SmoothingBoundEqualsDenseInverse) {
  const Chain c = MakeChain(25, 3, 5);
  const MarkovInformation info = InformationOf(c);
  const Eigen::MatrixXd H_inv = DenseInformation(info).inverse();
  const MarkovBounds bounds = ComputeMarkovBounds(info);
  ASSERT_TRUE(bounds.smoothing_ok);
  for (int k = 0; k < c.n; ++k)
    EXPECT_LT(RelativeDifference(bounds.smoothing[k], H_inv.block(3 * k, 3 * k, 3, 3)), 1e-9);
}

// Static nuisance parameters coupled to every state (a board tilt): the smoothing bound, the
// cross covariances and the nuisance covariance equal the blocks of the dense inverse of the full
// information [[A, B], [B^T, C]]; and the nuisance can only raise the bound.
TEST(CrlbMarkov, NuisanceParametersAreMarginalisedExactly) {
  const Chain c = MakeChain(25, 3, 7);
  MarkovInformation info = InformationOf(c);
  const MarkovBounds known = ComputeMarkovBounds(info);
  Rng rng(11);
  const int m = 2;
  // Measurements z_k = H_k x_k + E_k d + v_k on most states (whitened, unit noise).
  const Eigen::MatrixXd prior = 0.1 * Eigen::MatrixXd::Identity(m, m);  // a weak prior on d
  info.nuisance = prior;
  for (int k = 0; k < c.n; ++k) {
    const Eigen::MatrixXd Hx = RandomMatrix(2, 3, rng), Hd = RandomMatrix(2, m, rng);
    const bool seen = k % 5 != 2;
    if (seen) info.node[k] += Hx.transpose() * Hx;
    info.coupling.push_back(seen ? Eigen::MatrixXd(Hx.transpose() * Hd)
                                 : Eigen::MatrixXd::Zero(3, m));
    info.nuisance_node.push_back(seen ? Eigen::MatrixXd(Hd.transpose() * Hd)
                                      : Eigen::MatrixXd::Zero(m, m));
    info.nuisance += info.nuisance_node.back();
  }
  const int N = 3 * c.n;
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(N + m, N + m);
  H.topLeftCorner(N, N) = DenseInformation(info);
  for (int k = 0; k < c.n; ++k) {
    H.block(3 * k, N, 3, m) = info.coupling[k];
    H.block(N, 3 * k, m, 3) = info.coupling[k].transpose();
  }
  H.bottomRightCorner(m, m) = info.nuisance;
  const Eigen::MatrixXd H_inv = H.inverse();
  const MarkovBounds bounds = ComputeMarkovBounds(info);
  ASSERT_TRUE(bounds.smoothing_ok);
  ASSERT_EQ(bounds.smoothing_cross.size(), static_cast<size_t>(c.n));
  EXPECT_LT(RelativeDifference(bounds.nuisance_covariance, H_inv.bottomRightCorner(m, m)), 1e-9);
  for (int k = 0; k < c.n; ++k) {
    EXPECT_LT(RelativeDifference(bounds.smoothing[k], H_inv.block(3 * k, 3 * k, 3, 3)), 1e-9);
    EXPECT_LT(RelativeDifference(bounds.smoothing_cross[k], H_inv.block(3 * k, N, 3, m)), 1e-9);
  }
  // Filtering with d: the block of x_k in the inverse of the information of the data up to k
  // (states 0..k, d with its prior and the measurements up to k).
  for (int k = 0; k < c.n; ++k) {
    MarkovInformation head;
    head.node.assign(info.node.begin(), info.node.begin() + k + 1);
    head.phi.assign(info.phi.begin(), info.phi.begin() + k);
    head.q.assign(info.q.begin(), info.q.begin() + k);
    const int Nk = 3 * (k + 1);
    Eigen::MatrixXd Hk = Eigen::MatrixXd::Zero(Nk + m, Nk + m);
    Hk.topLeftCorner(Nk, Nk) = DenseInformation(head);
    Eigen::MatrixXd dd = prior;
    for (int j = 0; j <= k; ++j) {
      Hk.block(3 * j, Nk, 3, m) = info.coupling[j];
      Hk.block(Nk, 3 * j, m, 3) = info.coupling[j].transpose();
      dd += info.nuisance_node[j];
    }
    Hk.bottomRightCorner(m, m) = dd;
    const Eigen::MatrixXd Hk_inv = Hk.inverse();
    ASSERT_TRUE(bounds.filtering[k].has_value()) << k;
    EXPECT_LT(RelativeDifference(*bounds.filtering[k], Hk_inv.block(3 * k, 3 * k, 3, 3)), 1e-8)
        << k;
    EXPECT_LT(RelativeDifference(bounds.filtering_cross[k], Hk_inv.block(3 * k, Nk, 3, m)), 1e-8)
        << k;
    EXPECT_LT(RelativeDifference(bounds.filtering_nuisance[k], Hk_inv.bottomRightCorner(m, m)),
              1e-8)
        << k;
  }
  // The last state: nothing in its future, filtering = smoothing.
  EXPECT_LT(RelativeDifference(*bounds.filtering[c.n - 1], bounds.smoothing[c.n - 1]), 1e-8);

  // Without the coupling (d known) the same measurements give a bound that is not larger.
  MarkovInformation without = info;
  without.coupling.clear();
  without.nuisance_node.clear();
  without.nuisance.resize(0, 0);
  const MarkovBounds d_known = ComputeMarkovBounds(without);
  for (int k = 0; k < c.n; ++k)
    EXPECT_LE(d_known.smoothing[k].trace(), bounds.smoothing[k].trace() * (1 + 1e-12));
  EXPECT_EQ(known.smoothing.size(), static_cast<size_t>(c.n));
}

TEST(CrlbMarkov, FilteringBoundUnsetUntilObservable) {
  // No prior and a 1-D measurement of a 2-D state: J_0 is singular, J_1 is not (the transition
  // mixes the components).
  MarkovInformation info;
  Eigen::MatrixXd H(1, 2);
  H << 1.0, 0.0;
  for (int k = 0; k < 3; ++k) info.node.push_back(H.transpose() * H);
  Eigen::MatrixXd F(2, 2);
  F << 1.0, 1.0, 0.0, 1.0;
  for (int k = 0; k < 2; ++k) info.AddTransition(F, 1e-2 * Eigen::MatrixXd::Identity(2, 2));
  const MarkovBounds bounds = ComputeMarkovBounds(info);
  EXPECT_FALSE(bounds.filtering[0].has_value());
  EXPECT_TRUE(bounds.filtering[1].has_value());
  EXPECT_TRUE(bounds.smoothing_ok);
}

TEST(CrlbMarkov, SingularInformationIsReported) {
  MarkovInformation info;
  for (int k = 0; k < 3; ++k) info.node.push_back(Eigen::MatrixXd::Zero(2, 2));
  for (int k = 0; k < 2; ++k)
    info.AddTransition(Eigen::MatrixXd::Identity(2, 2), Eigen::MatrixXd::Identity(2, 2));
  EXPECT_FALSE(ComputeMarkovBounds(info).smoothing_ok);
}

}  // namespace
}  // namespace mavloc
