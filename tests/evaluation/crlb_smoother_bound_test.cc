// The smoother's Cramér–Rao bound (evaluation/crlb/smoother_bound.h) on simulated scenarios:
// - against the smoother's own problem: ceres::Covariance of SolveSmoother's factors (IMU
//   preintegration, reprojection residuals; no robust loss) evaluated at the true states, a path
//   that shares no Jacobian code with the bound; the per-keyframe position and attitude sigmas
//   agree within a few percent (the two IMU models differ in second-order terms: the bound's
//   zero-order-hold error propagation with the bias walk inside each interval, the smoother's
//   interpolated-signal preintegration with a separate bias-walk factor);
// - efficiency at high signal-to-noise: over fixed Monte-Carlo seeds the smoother's RMSE is within
//   the Monte-Carlo uncertainty of the bound (it must not be below the bound beyond that noise:
//   a bound above an efficient estimator's error would be a bug);
// - the filtering bound is never below the smoothing bound;
// - unsupported models say why (laser-only data: crlb_laser_bound_test.cc).
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <map>
#include <numeric>

#include "datasets/scenarios/scenario.h"
#include "evaluation/crlb/efficiency.h"
#include "evaluation/crlb/smoother_bound.h"
#include "solver/estimators/smoother_estimator.h"
#include "solver/smoother/smoother_initialization.h"
#include "solver/smoother/smoother_problem.h"

#include "tests/scenario_support.h"

namespace mavloc {
namespace {

using testing::Simulate;

const GroundTruthState& NearestTruth(const Dataset& dataset, TimeNs t_ns) {
  auto it = std::lower_bound(dataset.ground_truth.begin(), dataset.ground_truth.end(), t_ns,
                             [](const GroundTruthState& s, TimeNs t) { return s.t_ns < t; });
  if (it == dataset.ground_truth.end()) return dataset.ground_truth.back();
  if (it != dataset.ground_truth.begin() &&
      std::abs(std::prev(it)->t_ns - t_ns) < std::abs(it->t_ns - t_ns))
    return *std::prev(it);
  return *it;
}

TEST(CrlbSmootherBound, AgreesWithTheSmoothersCovarianceAtTheTruth) {
  const Dataset dataset = Simulate("tag-arena-dynamic", 3, 8.0);
  ASSERT_FALSE(dataset.ground_truth.empty());
  const SmootherCrlb bound = ComputeSmootherCrlb(dataset);
  ASSERT_TRUE(bound.ok) << bound.reason;

  const SmootherEstimator smoother{EstimatorOptions()};
  SmootherProblemOptions options = smoother.ProblemOptionsFor(dataset);
  options.loss = SmootherLoss::kNone;
  options.max_iterations = 0;  // evaluate at the truth
  options.relinearize_rounds = 0;
  options.compute_covariance = true;
  std::vector<SmootherKeyframe> truth;
  for (const TimeNs t : SmootherKeyframeTimes(dataset)) {
    const GroundTruthState& gt = NearestTruth(dataset, t);
    ASSERT_LE(std::abs(gt.t_ns - t), 1000);
    SmootherKeyframe kf;
    kf.t_ns = t;
    kf.state.q_W_B = gt.T_W_B.q;
    kf.state.p_W = gt.T_W_B.p;
    kf.state.v_W = gt.v_W;
    kf.state.biases.b_g = gt.b_g;
    kf.state.biases.b_a = gt.b_a;
    truth.push_back(kf);
  }
  const SmootherResult result = SolveSmoother(dataset, truth, {}, std::nullopt, options);
  ASSERT_EQ(result.pose_covariances.size(), bound.keyframes.size());
  double worst_position = 0.0, worst_attitude = 0.0;
  for (size_t k = 0; k < bound.keyframes.size(); ++k) {
    ASSERT_TRUE(result.pose_covariances[k].has_value());
    const auto& C = *result.pose_covariances[k];
    const double p_smoother = std::sqrt(C.topLeftCorner<3, 3>().trace());
    const double a_smoother = std::sqrt(C.bottomRightCorner<3, 3>().trace());
    const CrlbSigmas s = SigmasOf(bound.keyframes[k].smoothing, bound.keyframes[k].T_W_B.q);
    worst_position = std::max(worst_position, std::abs(s.position_m / p_smoother - 1.0));
    worst_attitude = std::max(worst_attitude, std::abs(s.attitude_rad / a_smoother - 1.0));
  }
  RecordProperty("worst_position_rel", std::to_string(worst_position));
  RecordProperty("worst_attitude_rel", std::to_string(worst_attitude));
  EXPECT_LT(worst_position, 0.03);
  EXPECT_LT(worst_attitude, 0.03);
}

TEST(CrlbSmootherBound, FilteringBoundIsNeverBelowTheSmoothingBound) {
  const Dataset dataset = Simulate("tag-arena-dynamic", 2, 8.0);
  const SmootherCrlb bound = ComputeSmootherCrlb(dataset);
  ASSERT_TRUE(bound.ok) << bound.reason;
  int with_filtering = 0;
  for (const CrlbKeyframe& kf : bound.keyframes) {
    if (!kf.filtering) continue;
    ++with_filtering;
    const Eigen::Matrix<double, 15, 15> difference = *kf.filtering - kf.smoothing;
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 15, 15>> eig(
        0.5 * (difference + difference.transpose()));
    EXPECT_GE(eig.eigenvalues().minCoeff(), -1e-9 * kf.filtering->norm());
  }
  EXPECT_GT(with_filtering, static_cast<int>(bound.keyframes.size()) / 2);
  // The last keyframe: nothing in its future, both bounds are the same.
  ASSERT_TRUE(bound.keyframes.back().filtering.has_value());
  EXPECT_NEAR(bound.keyframes.back().filtering->trace(), bound.keyframes.back().smoothing.trace(),
              1e-9 * bound.keyframes.back().smoothing.trace());
}

// Mean and standard error of the ratio sqrt(sum e2 / sum b2) over runs (delta method on the
// per-run mean squared errors).
std::pair<double, double> RatioWithError(const std::vector<double>& e2,
                                         const std::vector<double>& b2) {
  const double n = static_cast<double>(e2.size());
  const double me = std::accumulate(e2.begin(), e2.end(), 0.0) / n;
  const double mb = std::accumulate(b2.begin(), b2.end(), 0.0) / n;
  double var = 0.0;
  for (size_t i = 0; i < e2.size(); ++i) {
    const double r = e2[i] - me / mb * b2[i];
    var += r * r;
  }
  var /= (n - 1.0);
  const double ratio2 = me / mb;
  const double se_ratio2 = std::sqrt(var / n) / mb;
  return {std::sqrt(ratio2), 0.5 * se_ratio2 / std::sqrt(ratio2)};
}

// Efficiency at high signal-to-noise on 12 fixed seeds x 8 s. Was disabled while the smoother was
// below the bound (0.83 / 0.84): tag-arena did not state its corner noise as a number, so the
// smoother and the bound assumed 1 px against 0.3 px drawn (tests/evaluation/
// crlb_noise_model_test.cc measures every stated noise). Now position 0.93 +- 0.09, attitude
// 0.87 +- 0.05 on these seeds (a low draw: 0.99 / 1.01 over seeds 101..300).
TEST(CrlbSmootherBound, SmootherIsEfficientAtHighSignalToNoise) {
  EfficiencySums total;
  for (uint64_t seed = 1; seed <= 12; ++seed) {
    const Dataset dataset = Simulate("tag-arena-dynamic", seed, 8.0);
    const SmootherCrlb bound = ComputeSmootherCrlb(dataset);
    ASSERT_TRUE(bound.ok) << bound.reason;
    SmootherEstimator smoother{EstimatorOptions()};
    const Estimate estimate = smoother.Run(dataset);
    total.Add(CompareWithBound(bound, estimate.poses, BoundKind::kSmoothing));
  }
  ASSERT_EQ(total.runs, 12);
  const auto [p_ratio, p_se] = RatioWithError(total.run_position_error2, total.run_position_bound2);
  const auto [a_ratio, a_se] = RatioWithError(total.run_attitude_error2, total.run_attitude_bound2);
  RecordProperty("position_ratio", std::to_string(p_ratio));
  RecordProperty("attitude_ratio", std::to_string(a_ratio));
  std::printf("position ratio %.3f +- %.3f, attitude ratio %.3f +- %.3f\n", p_ratio, p_se, a_ratio,
              a_se);
  // Within 3 standard errors of 1 (the Huber loss at 2 sigma costs about 1 % of efficiency).
  EXPECT_GT(p_ratio, 1.0 - 3.0 * p_se);
  EXPECT_GT(a_ratio, 1.0 - 3.0 * a_se);
  EXPECT_LT(p_ratio, 1.0 + 3.0 * p_se + 0.02);
  EXPECT_LT(a_ratio, 1.0 + 3.0 * a_se + 0.02);
}

TEST(CrlbSmootherBound, UnsupportedModelsSayWhy) {
  const SmootherCrlb three_point = ComputeSmootherCrlb(Simulate("three-point-hover", 1, 10.0));
  EXPECT_FALSE(three_point.ok);
  EXPECT_NE(three_point.reason.find("landmarks"), std::string::npos) << three_point.reason;
  // The laser spot on an unknown plane has a bound (tests/evaluation/crlb_laser_bound_test.cc).
}

}  // namespace
}  // namespace mavloc
