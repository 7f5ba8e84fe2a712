// The smoother's structured marginal covariances (solver/smoother/smoother_covariance.h) against
// ceres::Covariance:
// - selected inversion (Takahashi) on a random SPD banded-plus-border matrix equals the dense
//   inverse on the factor's pattern, and the pattern stays band + border (linear fill);
// - a hand-built problem with quaternion and subset manifolds, constant blocks, Huber and Cauchy
//   losses (points in their down-weighted range), a border block and requested blocks far outside
//   the information matrix's pattern: every block equals ceres::Covariance's to 1e-9 relative
//   (Frobenius norm of the difference over the norm); without its anchor (gauge freedom) both
//   fail;
// - the smoother on simulated scenarios (known landmarks, tags, three-point ground features with D
//   estimated, aprilgrid calibration with both cameras' extrinsics, time offset and board tilt):
//   from the same solution, every pose covariance and calibration covariance of
//   SmootherCovarianceMethod::kStructured equals kCeres' to 1e-9 relative (printed: 3e-12 at
//   worst);
// - rank deficiency is reported the same way by both methods (covariance_failed, no pose
//   covariance): a landmark seen once (its depth is free); free landmarks of mav-figure-eight
//   (some triangulated from nearly parallel rays); laser-plane (its spots leave three directions
//   free besides the smoother's gauge).
#include <gtest/gtest.h>

#include <ceres/ceres.h>

#include <Eigen/Dense>
#include <Eigen/SparseCholesky>
#include <cmath>
#include <cstdio>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "core/pose.h"
#include "solver/estimators/smoother_estimator.h"
#include "solver/smoother/smoother_covariance.h"
#include "solver/smoother/smoother_problem.h"
#include "tests/scenario_support.h"

namespace mavloc {
namespace {

constexpr double kTolerance = 1e-9;  // relative, Frobenius norm

double RelativeDifference(const Eigen::MatrixXd& a, const Eigen::MatrixXd& reference) {
  const double scale = reference.norm();
  return scale > 0.0 ? (a - reference).norm() / scale : (a - reference).norm();
}

// ---------------------------------------------------------------------------------------------
// Selected inversion.

// Random SPD matrix: a chain of `chain` columns with half-bandwidth `band`, then `border` columns
// coupled to everything; diagonally dominant with a small margin.
Eigen::SparseMatrix<double> BandedPlusBorder(int chain, int band, int border, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  const int n = chain + border;
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(n, n);
  for (int j = 0; j < n; ++j)
    for (int i = j + 1; i < n; ++i) {
      const bool in_band = i < chain && i - j <= band;
      const bool in_border = i >= chain;
      if (!in_band && !in_border) continue;
      A(i, j) = A(j, i) = uniform(rng) * (in_border ? 0.3 : 1.0);
    }
  for (int i = 0; i < n; ++i)
    A(i, i) = A.row(i).cwiseAbs().sum() + 0.05 + 0.5 * (1.0 + uniform(rng));
  Eigen::SparseMatrix<double> S = A.sparseView();
  S.makeCompressed();
  return S;
}

TEST(SelectedInverse, EqualsTheDenseInverseOnTheFactorsPattern) {
  const int chain = 600, band = 17, border = 9;
  const Eigen::SparseMatrix<double> A = BandedPlusBorder(chain, band, border, 5);
  Eigen::SimplicialLLT<Eigen::SparseMatrix<double>, Eigen::Lower, Eigen::NaturalOrdering<int>> llt(
      A);
  ASSERT_EQ(llt.info(), Eigen::Success);
  const Eigen::SparseMatrix<double>& L = llt.matrixL().nestedExpression();
  // Linear fill: every column holds at most its band and the border rows.
  EXPECT_LE(L.nonZeros(), static_cast<long>(chain) * (band + 1 + border) + border * border);
  Eigen::SparseMatrix<double> Z;
  ASSERT_TRUE(SelectedInverse(L, &Z));
  ASSERT_EQ(Z.nonZeros(), L.nonZeros());

  const Eigen::MatrixXd dense_inverse =
      Eigen::MatrixXd(A).llt().solve(Eigen::MatrixXd::Identity(A.rows(), A.cols()));
  double max_error = 0.0, sum_sq_error = 0.0, sum_sq = 0.0;
  for (int j = 0; j < Z.outerSize(); ++j)
    for (Eigen::SparseMatrix<double>::InnerIterator it(Z, j); it; ++it) {
      const double reference = dense_inverse(it.row(), it.col());
      const double error = std::abs(it.value() - reference);
      max_error = std::max(max_error, error);
      sum_sq_error += error * error;
      sum_sq += reference * reference;
    }
  std::printf("n = %d: nnz(L) = %ld, max |Z - inv(A)| on the pattern %.2e (max |inv(A)| %.2e)\n",
              static_cast<int>(A.rows()), static_cast<long>(L.nonZeros()), max_error,
              dense_inverse.cwiseAbs().maxCoeff());
  EXPECT_LT(std::sqrt(sum_sq_error / sum_sq), 1e-12);
  EXPECT_LT(max_error, 1e-12 * dense_inverse.cwiseAbs().maxCoeff());
}

TEST(SelectedInverse, RefusesAPatternThatIsNotClosed) {
  // L(1,0) and L(2,0) are stored but not L(2,1): Z(2,1) would be needed and is missing.
  std::vector<Eigen::Triplet<double>> t = {
      {0, 0, 2.0}, {1, 0, 0.5}, {2, 0, 0.3}, {1, 1, 1.5}, {2, 2, 1.0}};
  Eigen::SparseMatrix<double> L(3, 3);
  L.setFromTriplets(t.begin(), t.end());
  L.makeCompressed();
  Eigen::SparseMatrix<double> Z;
  EXPECT_FALSE(SelectedInverse(L, &Z));
}

// ---------------------------------------------------------------------------------------------
// A hand-built problem against ceres::Covariance.

// Relative pose of two (q, p) blocks against a measurement, whitened.
struct RelativePoseResidual {
  Eigen::Quaterniond q_ab;
  Eigen::Vector3d p_ab;
  double weight;
  template <typename T>
  bool operator()(const T* qa, const T* pa, const T* qb, const T* pb, T* r) const {
    const Eigen::Map<const Eigen::Quaternion<T>> q_a(qa), q_b(qb);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> p_a(pa), p_b(pb);
    const Eigen::Quaternion<T> dq = q_ab.cast<T>().conjugate() * q_a.conjugate() * q_b;
    const Eigen::Matrix<T, 3, 1> dp = q_a.conjugate() * (p_b - p_a) - p_ab.cast<T>();
    for (int k = 0; k < 3; ++k) r[k] = T(weight) * dp[k];
    for (int k = 0; k < 3; ++k) r[3 + k] = T(2.0 * weight) * dq.vec()[k];
    return true;
  }
};

// A landmark (3) seen from a pose, with a shared scalar "calibration" offset along the body z.
struct LandmarkResidual {
  Eigen::Vector3d measured_B;
  template <typename T>
  bool operator()(const T* q, const T* p, const T* l, const T* offset, T* r) const {
    const Eigen::Map<const Eigen::Quaternion<T>> q_WB(q);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> p_W(p), l_W(l);
    Eigen::Matrix<T, 3, 1> e = q_WB.conjugate() * (l_W - p_W) - measured_B.cast<T>();
    e[2] += offset[0];
    for (int k = 0; k < 3; ++k) r[k] = T(10.0) * e[k];
    return true;
  }
};

struct PointPrior {
  Eigen::Vector3d mean;
  double weight;
  template <typename T>
  bool operator()(const T* x, T* r) const {
    for (int k = 0; k < 3; ++k) r[k] = T(weight) * (x[k] - T(mean[k]));
    return true;
  }
};

struct QuaternionPrior {
  Eigen::Quaterniond mean;
  double weight;
  template <typename T>
  bool operator()(const T* q, T* r) const {
    const Eigen::Map<const Eigen::Quaternion<T>> q_(q);
    const Eigen::Quaternion<T> d = mean.cast<T>().conjugate() * q_;
    for (int k = 0; k < 3; ++k) r[k] = T(weight) * d.vec()[k];
    return true;
  }
};

struct HandBuilt {
  static constexpr int kPoses = 40;
  static constexpr int kLandmarks = 5;
  std::vector<std::array<double, 4>> q;
  std::vector<std::array<double, 3>> p;
  std::vector<std::array<double, 3>> landmarks;
  std::array<double, 1> offset{0.01};
  std::array<double, 3> fixed{1.0, 2.0, 3.0};  // constant block
  ceres::EigenQuaternionManifold quaternion_manifold;
  ceres::SubsetManifold fix_z{3, {2}};
  ceres::HuberLoss huber{0.5};
  ceres::CauchyLoss cauchy{0.5};
  std::unique_ptr<ceres::Problem> problem;

  explicit HandBuilt(bool anchored) {
    std::mt19937 rng(3);
    std::normal_distribution<double> noise(0.0, 1.0);
    q.resize(kPoses);
    p.resize(kPoses);
    landmarks.resize(kLandmarks);
    std::vector<Eigen::Quaterniond> true_q(kPoses);
    std::vector<Eigen::Vector3d> true_p(kPoses);
    for (int k = 0; k < kPoses; ++k) {
      true_q[k] = Eigen::Quaterniond(Eigen::AngleAxisd(0.1 * k, Eigen::Vector3d::UnitZ()) *
                                     Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitX()));
      true_p[k] = Eigen::Vector3d(std::cos(0.1 * k), std::sin(0.1 * k), 0.02 * k);
      // The values the covariance is evaluated at: off the truth, so residuals are not zero.
      Eigen::Vector3d axis;
      for (int i = 0; i < 3; ++i) axis[i] = noise(rng);  // in order (not as call arguments)
      const Eigen::Quaterniond qk =
          (true_q[k] * Eigen::Quaterniond(Eigen::AngleAxisd(0.02, axis.normalized()))).normalized();
      q[k] = {qk.x(), qk.y(), qk.z(), qk.w()};
      for (int i = 0; i < 3; ++i) p[k][i] = true_p[k][i] + 0.05 * noise(rng);
    }
    std::vector<Eigen::Vector3d> true_l(kLandmarks);
    for (int j = 0; j < kLandmarks; ++j) {
      true_l[j] = Eigen::Vector3d(2.0 * std::cos(1.3 * j), 2.0 * std::sin(1.3 * j), 1.0 + 0.2 * j);
      for (int i = 0; i < 3; ++i) landmarks[j][i] = true_l[j][i] + 0.05 * noise(rng);
    }
    ceres::Problem::Options options;
    options.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    problem = std::make_unique<ceres::Problem>(options);
    for (int k = 0; k < kPoses; ++k) {
      problem->AddParameterBlock(q[k].data(), 4, &quaternion_manifold);
      problem->AddParameterBlock(p[k].data(), 3);
    }
    for (int k = 0; k + 1 < kPoses; ++k) {
      RelativePoseResidual rel{true_q[k].conjugate() * true_q[k + 1],
                               true_q[k].conjugate() * (true_p[k + 1] - true_p[k]), 30.0};
      problem->AddResidualBlock(
          new ceres::AutoDiffCostFunction<RelativePoseResidual, 6, 4, 3, 4, 3>(
              new RelativePoseResidual(rel)),
          nullptr, q[k].data(), p[k].data(), q[k + 1].data(), p[k + 1].data());
    }
    // Each landmark seen from a stretch of poses; the last one from every pose (a border block).
    // Huber on even poses, Cauchy on odd ones; residuals of 10 x 0.05 are beyond their scale.
    for (int j = 0; j < kLandmarks; ++j) {
      const int first = j == kLandmarks - 1 ? 0 : 8 * j;
      const int last = j == kLandmarks - 1 ? kPoses - 1 : std::min(kPoses - 1, 8 * j + 10);
      for (int k = first; k <= last; ++k) {
        LandmarkResidual obs{true_q[k].conjugate() * (true_l[j] - true_p[k]) +
                             Eigen::Vector3d(0.0, 0.0, 0.01)};
        problem->AddResidualBlock(new ceres::AutoDiffCostFunction<LandmarkResidual, 3, 4, 3, 3, 1>(
                                      new LandmarkResidual(obs)),
                                  k % 2 ? static_cast<ceres::LossFunction*>(&cauchy) : &huber,
                                  q[k].data(), p[k].data(), landmarks[j].data(), offset.data());
      }
    }
    // Landmark 1 lives on a plane (subset manifold); a constant block in a residual.
    problem->SetManifold(landmarks[1].data(), &fix_z);
    problem->AddResidualBlock(new ceres::AutoDiffCostFunction<RelativePoseResidual, 6, 4, 3, 4, 3>(
                                  new RelativePoseResidual{Eigen::Quaterniond::Identity(),
                                                           Eigen::Vector3d(1, 1, 1), 1.0}),
                              nullptr, q[5].data(), p[5].data(), q[6].data(), fixed.data());
    problem->SetParameterBlockConstant(fixed.data());
    if (anchored) {
      problem->AddResidualBlock(
          new ceres::AutoDiffCostFunction<PointPrior, 3, 3>(new PointPrior{true_p[0], 100.0}),
          nullptr, p[0].data());
      problem->AddResidualBlock(new ceres::AutoDiffCostFunction<QuaternionPrior, 3, 4>(
                                    new QuaternionPrior{true_q[0], 100.0}),
                                nullptr, q[0].data());
    }
  }

  SmootherCovarianceLayout Layout() {
    SmootherCovarianceLayout layout;
    for (int k = 0; k < kPoses; ++k) layout.keyframes.push_back({q[k].data(), p[k].data()});
    for (auto& l : landmarks) layout.others.push_back(l.data());
    layout.others.push_back(offset.data());
    layout.others.push_back(fixed.data());
    return layout;
  }

  std::vector<std::pair<const double*, const double*>> Pairs() {
    std::vector<std::pair<const double*, const double*>> pairs;
    for (int k = 0; k < kPoses; ++k) {
      pairs.emplace_back(p[k].data(), p[k].data());
      pairs.emplace_back(q[k].data(), q[k].data());
      pairs.emplace_back(p[k].data(), q[k].data());
    }
    for (auto& l : landmarks) pairs.emplace_back(l.data(), l.data());
    pairs.emplace_back(offset.data(), offset.data());
    // Far outside the pattern of J^T J: the first and last poses, a landmark and a far pose.
    pairs.emplace_back(p[0].data(), q[kPoses - 1].data());
    pairs.emplace_back(landmarks[0].data(), p[kPoses - 1].data());
    pairs.emplace_back(offset.data(), landmarks[2].data());
    pairs.emplace_back(fixed.data(), p[3].data());  // constant: zeros
    return pairs;
  }
};

TEST(SmootherCovarianceModule, HandBuiltProblemEqualsCeresCovariance) {
  HandBuilt h(true);
  const auto pairs = h.Pairs();
  ceres::Covariance::Options ceres_options;
  ceres::Covariance reference(ceres_options);
  ASSERT_TRUE(reference.Compute(pairs, h.problem.get()));
  SmootherCovariance structured;
  ASSERT_TRUE(structured.Compute(h.Layout(), pairs, h.problem.get())) << structured.message();
  double worst = 0.0;
  for (const auto& [a, b] : pairs) {
    const int sa = h.problem->ParameterBlockTangentSize(a);
    const int sb = h.problem->ParameterBlockTangentSize(b);
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> x(sa, sb), y(sa, sb),
        yt(sb, sa);
    ASSERT_TRUE(reference.GetCovarianceBlockInTangentSpace(a, b, x.data()));
    ASSERT_TRUE(structured.GetCovarianceBlockInTangentSpace(a, b, y.data()));
    ASSERT_TRUE(structured.GetCovarianceBlockInTangentSpace(b, a, yt.data()));
    EXPECT_EQ(Eigen::MatrixXd(yt.transpose()), Eigen::MatrixXd(y));
    if (a == h.fixed.data()) {
      EXPECT_TRUE(y.isZero(0.0));
      continue;
    }
    const double d = RelativeDifference(y, x);
    worst = std::max(worst, d);
    EXPECT_LT(d, kTolerance);
  }
  const SmootherCovarianceStatistics& s = structured.statistics();
  std::printf(
      "hand-built: %d columns, nnz(H) %lld, nnz(L) %lld, min relative pivot %.2e; worst "
      "relative difference to ceres::Covariance %.2e\n",
      s.dimension, s.information_nonzeros, s.factor_nonzeros, s.min_relative_pivot, worst);
  // Not requested: unavailable.
  double unused[9];
  EXPECT_FALSE(structured.GetCovarianceBlockInTangentSpace(h.p[1].data(), h.p[7].data(), unused));
}

TEST(SmootherCovarianceModule, GaugeFreedomIsAFailureLikeCeres) {
  HandBuilt h(false);  // no prior on the first pose: a free rigid motion of everything
  const auto pairs = h.Pairs();
  ceres::Covariance::Options ceres_options;
  ceres::Covariance reference(ceres_options);
  EXPECT_FALSE(reference.Compute(pairs, h.problem.get()));
  SmootherCovariance structured;
  EXPECT_FALSE(structured.Compute(h.Layout(), pairs, h.problem.get()));
  std::printf("gauge-free: %s; min relative pivot %.2e\n", structured.message().c_str(),
              structured.statistics().min_relative_pivot);
  EXPECT_NE(structured.message().find("rank deficient"), std::string::npos);
  double unused[9];
  EXPECT_FALSE(structured.GetCovarianceBlockInTangentSpace(h.p[0].data(), h.p[0].data(), unused));
}

// ---------------------------------------------------------------------------------------------
// A residual group's fit (ResidualGroupFit): chi2 and redundancy n_g - tr(H^-1 J_g^T J_g).

// The hand-built problem's residual blocks: the relative-pose chain (6 rows, four parameter
// blocks, first) and the rest.
std::pair<std::vector<ceres::ResidualBlockId>, std::vector<ceres::ResidualBlockId>> ChainAndRest(
    ceres::Problem* problem) {
  std::vector<ceres::ResidualBlockId> all, chain, rest;
  problem->GetResidualBlocks(&all);
  std::vector<double*> blocks;
  for (const ceres::ResidualBlockId id : all) {
    problem->GetParameterBlocksForResidualBlock(id, &blocks);
    const bool relative =
        blocks.size() == 4 && problem->GetCostFunctionForResidualBlock(id)->num_residuals() == 6;
    (relative ? chain : rest).push_back(id);
  }
  return {chain, rest};
}

// J over every residual (the group's rows first; the columns of constant blocks left out) and the
// group's row count.
Eigen::MatrixXd DenseJacobian(ceres::Problem* problem,
                              const std::vector<ceres::ResidualBlockId>& group,
                              const std::vector<ceres::ResidualBlockId>& rest, int* group_rows) {
  ceres::Problem::EvaluateOptions options;
  options.residual_blocks = group;
  options.residual_blocks.insert(options.residual_blocks.end(), rest.begin(), rest.end());
  ceres::CRSMatrix crs;
  EXPECT_TRUE(problem->Evaluate(options, nullptr, nullptr, nullptr, &crs));
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(crs.num_rows, crs.num_cols);
  for (int r = 0; r < crs.num_rows; ++r)
    for (int q = crs.rows[r]; q < crs.rows[r + 1]; ++q) J(r, crs.cols[q]) = crs.values[q];
  *group_rows = 0;
  for (const ceres::ResidualBlockId id : group)
    *group_rows += problem->GetCostFunctionForResidualBlock(id)->num_residuals();
  std::vector<int> kept;
  for (int c = 0; c < J.cols(); ++c)
    if (!J.col(c).isZero(0.0)) kept.push_back(c);
  Eigen::MatrixXd Jk(J.rows(), static_cast<Eigen::Index>(kept.size()));
  for (size_t c = 0; c < kept.size(); ++c) Jk.col(static_cast<Eigen::Index>(c)) = J.col(kept[c]);
  return Jk;
}

// tr(H^-1 J_g^T J_g) from dense matrices.
double DenseGroupTrace(ceres::Problem* problem, const std::vector<ceres::ResidualBlockId>& group,
                       const std::vector<ceres::ResidualBlockId>& rest, int* group_rows) {
  const Eigen::MatrixXd J = DenseJacobian(problem, group, rest, group_rows);
  const Eigen::MatrixXd H = J.transpose() * J;
  const Eigen::MatrixXd Jg = J.topRows(*group_rows);
  return (H.ldlt().solve(Jg.transpose() * Jg)).trace();
}

TEST(ResidualGroupFit, RedundancyEqualsTheDenseTraceAndTheGroupsAddUp) {
  HandBuilt h(true);
  const auto [chain, rest] = ChainAndRest(h.problem.get());
  ASSERT_EQ(chain.size(), static_cast<size_t>(HandBuilt::kPoses));  // 39 links + one to `fixed`
  SmootherCovariance for_chain, for_rest;
  ASSERT_TRUE(for_chain.Compute(h.Layout(), {}, h.problem.get(), &chain)) << for_chain.message();
  ASSERT_TRUE(for_rest.Compute(h.Layout(), {}, h.problem.get(), &rest)) << for_rest.message();
  int chain_rows = 0;
  const double dense_trace = DenseGroupTrace(h.problem.get(), chain, rest, &chain_rows);
  const ResidualGroupFit& c = for_chain.group_fit();
  const ResidualGroupFit& r = for_rest.group_fit();
  EXPECT_EQ(c.residuals, chain_rows);
  EXPECT_NEAR(c.residuals - c.redundancy, dense_trace, 1e-9 * dense_trace);
  // tr(H^-1 H_chain) + tr(H^-1 H_rest) = tr(I) = the number of columns.
  const int columns = for_chain.statistics().dimension;
  EXPECT_NEAR((c.residuals - c.redundancy) + (r.residuals - r.redundancy), columns, 1e-9 * columns);
  EXPECT_GT(c.redundancy, 0.0);
  EXPECT_LT(c.redundancy, c.residuals);
  // chi2: the sum of the squared (loss-corrected) residuals of the group, as Ceres evaluates them.
  ceres::Problem::EvaluateOptions options;
  options.residual_blocks = chain;
  std::vector<double> residuals;
  ASSERT_TRUE(h.problem->Evaluate(options, nullptr, &residuals, nullptr, nullptr));
  double chi2 = 0.0;
  for (const double v : residuals) chi2 += v * v;
  EXPECT_NEAR(c.chi2, chi2, 1e-12 * chi2);
}

// Without the prior on the first pose some rigid motions are free: the plain computation refuses
// the problem, the regularized one counts the free directions in no group, so the traces add up to
// the rank of J (from its singular values).
TEST(ResidualGroupFit, RegularizedGaugeFreeProblemCountsTheRank) {
  HandBuilt h(false);
  const auto [chain, rest] = ChainAndRest(h.problem.get());
  SmootherCovariance plain;
  EXPECT_FALSE(plain.Compute(h.Layout(), {}, h.problem.get(), &chain));
  SmootherCovarianceOptions options;
  options.regularization = 1e-9;
  SmootherCovariance for_chain(options), for_rest(options);
  ASSERT_TRUE(for_chain.Compute(h.Layout(), {}, h.problem.get(), &chain)) << for_chain.message();
  ASSERT_TRUE(for_rest.Compute(h.Layout(), {}, h.problem.get(), &rest)) << for_rest.message();
  const ResidualGroupFit& c = for_chain.group_fit();
  const ResidualGroupFit& r = for_rest.group_fit();
  int chain_rows = 0;
  const Eigen::MatrixXd J = DenseJacobian(h.problem.get(), chain, rest, &chain_rows);
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(J);
  svd.setThreshold(1e-10);
  const int rank = static_cast<int>(svd.rank());
  EXPECT_LT(rank, for_chain.statistics().dimension);
  // The weakly constrained directions lose a little of their trace to the regularization (0.002
  // of 253 here); a fitted noise scale from a redundancy of tens is off by 1e-4 of itself.
  EXPECT_NEAR((c.residuals - c.redundancy) + (r.residuals - r.redundancy), rank, 0.01);
  // On the anchored problem the regularization moves the redundancy by less than 1e-6.
  HandBuilt anchored(true);
  const auto [anchored_chain, anchored_rest] = ChainAndRest(anchored.problem.get());
  SmootherCovariance exact, regularized(options);
  ASSERT_TRUE(exact.Compute(anchored.Layout(), {}, anchored.problem.get(), &anchored_chain));
  ASSERT_TRUE(regularized.Compute(anchored.Layout(), {}, anchored.problem.get(), &anchored_chain));
  EXPECT_NEAR(regularized.group_fit().redundancy, exact.group_fit().redundancy,
              1e-6 * exact.group_fit().redundancy);
}

// ---------------------------------------------------------------------------------------------
// The smoother: both methods from the same solution.

struct MethodComparison {
  SmootherResult structured, ceres;
};

// Solves with the estimator (options as on the command line), then solves again from its solution
// once per method, with pose covariances and the calibration's.
MethodComparison CompareMethods(const Dataset& dataset,
                                std::map<std::string, std::string> estimator_options) {
  estimator_options["threads"] = "1";
  SmootherEstimator smoother{EstimatorOptions(estimator_options)};
  smoother.Run(dataset);
  const SmootherResult& first = smoother.last_result();
  EXPECT_TRUE(first.usable) << first.message;
  SmootherProblemOptions o = smoother.ProblemOptionsFor(dataset);
  o.num_threads = 1;
  o.compute_covariance = true;
  o.calibration_covariance = true;
  o.initial_T_B_C = first.calibration.T_B_C;
  o.initial_time_offset_s = first.calibration.time_offset_s;
  if (first.calibration.q_W_M) o.initial_q_W_M = first.calibration.q_W_M;
  MethodComparison c;
  o.covariance_method = SmootherCovarianceMethod::kStructured;
  c.structured = SolveSmoother(dataset, first.keyframes, first.landmarks_W, first.plane, o);
  o.covariance_method = SmootherCovarianceMethod::kCeres;
  c.ceres = SolveSmoother(dataset, first.keyframes, first.landmarks_W, first.plane, o);
  return c;
}

void ExpectSameCovariances(const std::string& name, const MethodComparison& c) {
  const SmootherResult& s = c.structured;
  const SmootherResult& r = c.ceres;
  ASSERT_TRUE(s.usable && r.usable) << s.message << " / " << r.message;
  ASSERT_EQ(s.keyframes.size(), r.keyframes.size());
  // The same solution (the covariance does not touch the parameters).
  for (size_t k = 0; k < s.keyframes.size(); ++k) {
    ASSERT_EQ(s.keyframes[k].state.p_W, r.keyframes[k].state.p_W) << name << " keyframe " << k;
    ASSERT_EQ(s.keyframes[k].state.q_W_B.coeffs(), r.keyframes[k].state.q_W_B.coeffs());
  }
  ASSERT_EQ(s.pose_covariances.size(), s.keyframes.size());
  ASSERT_EQ(r.pose_covariances.size(), r.keyframes.size());
  double worst_pose = 0.0;
  for (size_t k = 0; k < s.keyframes.size(); ++k) {
    ASSERT_TRUE(s.pose_covariances[k] && r.pose_covariances[k]) << name << " keyframe " << k;
    const double d = RelativeDifference(*s.pose_covariances[k], *r.pose_covariances[k]);
    worst_pose = std::max(worst_pose, d);
    EXPECT_LT(d, kTolerance) << name << " keyframe " << k;
  }
  double worst_calibration = 0.0;
  const SmootherCalibration& sc = s.calibration;
  const SmootherCalibration& rc = r.calibration;
  EXPECT_FALSE(sc.covariance_failed);
  EXPECT_FALSE(rc.covariance_failed);
  ASSERT_EQ(sc.T_B_C_covariance.size(), rc.T_B_C_covariance.size());
  for (const auto& [cam, C] : rc.T_B_C_covariance) {
    ASSERT_TRUE(sc.T_B_C_covariance.count(cam));
    const double d = RelativeDifference(sc.T_B_C_covariance.at(cam), C);
    worst_calibration = std::max(worst_calibration, d);
    EXPECT_LT(d, kTolerance) << name << " T_B_C of cam" << cam;
  }
  ASSERT_EQ(sc.time_offset_sigma_s.has_value(), rc.time_offset_sigma_s.has_value());
  if (rc.time_offset_sigma_s) {
    const double d =
        std::abs(*sc.time_offset_sigma_s - *rc.time_offset_sigma_s) / *rc.time_offset_sigma_s;
    worst_calibration = std::max(worst_calibration, d);
    EXPECT_LT(d, kTolerance) << name << " time offset sigma";
  }
  ASSERT_EQ(sc.tilt_covariance.has_value(), rc.tilt_covariance.has_value());
  if (rc.tilt_covariance) {
    const double d = RelativeDifference(*sc.tilt_covariance, *rc.tilt_covariance);
    worst_calibration = std::max(worst_calibration, d);
    EXPECT_LT(d, kTolerance) << name << " tilt";
  }
  const int calibration_blocks = static_cast<int>(rc.T_B_C_covariance.size()) +
                                 (rc.time_offset_sigma_s ? 1 : 0) + (rc.tilt_covariance ? 1 : 0);
  std::printf(
      "%-28s %4zu keyframes: worst relative difference poses %.1e, calibration (%d blocks) %.1e; "
      "min relative pivot %.1e; covariance %.3f s (structured) vs %.3f s (ceres)\n",
      name.c_str(), s.keyframes.size(), worst_pose, calibration_blocks, worst_calibration,
      s.statistics.covariance_min_relative_pivot, s.statistics.covariance_s,
      r.statistics.covariance_s);
}

// Where ceres::Covariance finds the problem rank deficient, the structured method must too (and
// leave every pose covariance unset); elsewhere both give the same covariances.
void ExpectSameOutcome(const std::string& name, const MethodComparison& c) {
  const SmootherResult& s = c.structured;
  const SmootherResult& r = c.ceres;
  ASSERT_TRUE(s.usable && r.usable) << s.message << " / " << r.message;
  const bool ceres_computed = !r.pose_covariances.empty() && r.pose_covariances.front().has_value();
  if (ceres_computed) {
    ExpectSameCovariances(name, c);
    return;
  }
  ASSERT_EQ(s.pose_covariances.size(), s.keyframes.size());
  for (size_t k = 0; k < s.keyframes.size(); ++k) {
    EXPECT_FALSE(r.pose_covariances[k].has_value()) << name << " keyframe " << k;
    EXPECT_FALSE(s.pose_covariances[k].has_value()) << name << " keyframe " << k;
  }
  std::printf("%-28s %4zu keyframes: rank deficient for both (min relative pivot %.1e)\n",
              name.c_str(), s.keyframes.size(), s.statistics.covariance_min_relative_pivot);
}

TEST(SmootherCovarianceMethods, KnownLandmarksFigureEight) {
  const Dataset dataset = testing::Simulate("mav-figure-eight", 2, 6.0);
  if (dataset.ground_truth.empty()) GTEST_SKIP() << "mav-figure-eight not available";
  ExpectSameCovariances("mav-figure-eight", CompareMethods(dataset, {}));
}

TEST(SmootherCovarianceMethods, FreeLandmarksFigureEight) {
  // Every landmark a 3-D parameter seen over a stretch of keyframes (placed after its last one),
  // the gauge fixed by the prior on the first pose.
  const Dataset dataset = testing::Simulate("mav-figure-eight", 2, 4.0);
  if (dataset.ground_truth.empty()) GTEST_SKIP() << "mav-figure-eight not available";
  ExpectSameOutcome("mav-figure-eight, free points",
                    CompareMethods(dataset, {{"landmarks", "unknown"}}));
}

TEST(SmootherCovarianceMethods, TagCornersTagArena) {
  const Dataset dataset = testing::Simulate("tag-arena-dynamic", 2, 8.0);
  if (dataset.ground_truth.empty()) GTEST_SKIP() << "tag-arena-dynamic not available";
  ExpectSameCovariances("tag-arena-dynamic", CompareMethods(dataset, {}));
}

TEST(SmootherCovarianceMethods, GroundFeaturesThreePointWithDEstimated) {
  const Dataset dataset = testing::Simulate("three-point-hover", 2, 12.0);
  if (dataset.ground_truth.empty()) GTEST_SKIP() << "three-point-hover not available";
  ExpectSameCovariances("three-point-hover, D estimated",
                        CompareMethods(dataset, {{"estimate_D", "1"}}));
}

TEST(SmootherCovarianceMethods, LaserSpotOnAnUnknownPlane) {
  const Dataset dataset = testing::Simulate("laser-plane", 2, 10.0);
  if (dataset.ground_truth.empty()) GTEST_SKIP() << "laser-plane not available";
  // The spots leave three directions free besides the gauge the smoother fixes (ceres::Covariance:
  // rank 3 short): both methods report it.
  ExpectSameOutcome("laser-plane", CompareMethods(dataset, {}));
}

TEST(SmootherCovarianceMethods, AprilgridCalibrationBothCameras) {
  // Board map (tilt), T_B_C of cam0 and cam1, time offset: every calibration block.
  const Dataset dataset = testing::Simulate("aprilgrid-calibration", 2, 4.0);
  if (dataset.ground_truth.empty()) GTEST_SKIP() << "aprilgrid-calibration not available";
  ExpectSameCovariances(
      "aprilgrid-calibration",
      CompareMethods(dataset, {{"estimate_extrinsics", "1"}, {"estimate_time_offset", "1"}}));
}

TEST(SmootherCovarianceMethods, ALandmarkSeenOnceIsRankDeficientForBoth) {
  const Dataset base = testing::Simulate("tag-arena-dynamic", 2, 8.0);
  if (base.ground_truth.empty()) GTEST_SKIP() << "tag-arena-dynamic not available";
  SmootherEstimator smoother{EstimatorOptions({{"threads", "1"}, {"estimate_extrinsics", "1"}})};
  smoother.Run(base);
  const SmootherResult& first = smoother.last_result();
  ASSERT_TRUE(first.usable) << first.message;
  // One bearing of a free point, 2 m in front of the camera at the middle keyframe: nothing fixes
  // its depth along the ray.
  const SmootherKeyframe& kf = first.keyframes[first.keyframes.size() / 2];
  const Pose T_W_C = Pose(kf.state.q_W_B, kf.state.p_W) * first.calibration.T_B_C.at(0);
  const Eigen::Vector3d p_C(0.1, -0.05, 2.0);
  Dataset dataset = base;
  dataset.features.push_back({kf.t_ns, 777, Eigen::Vector2d(p_C.x() / p_C.z(), p_C.y() / p_C.z())});
  SmootherProblemOptions o = smoother.ProblemOptionsFor(dataset);
  o.num_threads = 1;
  o.compute_covariance = true;
  o.calibration_covariance = true;
  o.landmarks = LandmarkMode::kUnknown;
  o.features_as_bearings = true;
  o.initial_T_B_C = first.calibration.T_B_C;
  for (const SmootherCovarianceMethod method :
       {SmootherCovarianceMethod::kStructured, SmootherCovarianceMethod::kCeres}) {
    o.covariance_method = method;
    const SmootherResult r =
        SolveSmoother(dataset, first.keyframes, {{777, T_W_C * p_C}}, std::nullopt, o);
    const char* name = method == SmootherCovarianceMethod::kCeres ? "ceres" : "structured";
    ASSERT_TRUE(r.usable) << name << ": " << r.message;
    EXPECT_EQ(r.statistics.num_visual_residuals, first.statistics.num_visual_residuals + 1);
    EXPECT_TRUE(r.calibration.covariance_failed) << name;
    EXPECT_TRUE(r.calibration.T_B_C_covariance.empty()) << name;
    ASSERT_EQ(r.pose_covariances.size(), r.keyframes.size()) << name;
    for (const auto& C : r.pose_covariances) EXPECT_FALSE(C.has_value()) << name;
    if (method == SmootherCovarianceMethod::kStructured)
      std::printf("landmark seen once: min relative pivot %.1e\n",
                  r.statistics.covariance_min_relative_pivot);
  }
  // Without the extra bearing both succeed (the control).
  o.landmarks = LandmarkMode::kKnown;
  for (const SmootherCovarianceMethod method :
       {SmootherCovarianceMethod::kStructured, SmootherCovarianceMethod::kCeres}) {
    o.covariance_method = method;
    const SmootherResult r = SolveSmoother(base, first.keyframes, {}, std::nullopt, o);
    ASSERT_TRUE(r.usable);
    EXPECT_FALSE(r.calibration.covariance_failed);
    EXPECT_EQ(r.calibration.T_B_C_covariance.size(), 1u);
    for (const auto& C : r.pose_covariances) EXPECT_TRUE(C.has_value());
  }
}

}  // namespace
}  // namespace mavloc
