// The smoother's Cramér–Rao bound (evaluation/crlb/smoother_bound.h) on maps with a board:
// - marker-board-flight (tags in W): the bound against the smoother's own ceres::Covariance at the
//   true states (as crlb_smoother_bound_test.cc does on tag-arena), over a flight that includes the
//   first second on the ground with no marker in view;
// - aprilgrid-calibration (MapFrame::kBoard, the tilt to gravity is estimated): the bound on the
//   tilt equals the smoother's tilt covariance at the truth (the nuisance marginalised exactly,
//   evaluation/crlb/markov_information.h), and the pose bound with the tilt unknown is never below
//   the bound of the same data with the board put into W (tilt known); the filtering bound is
//   the one with the tilt known; an estimated time offset and a board
//   without its true tilt give no bound, with the reason.
#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "core/board_frame.h"
#include "core/quantities.h"
#include "datasets/scenarios/scenario.h"
#include "evaluation/crlb/smoother_bound.h"
#include "solver/estimators/smoother_estimator.h"
#include "solver/smoother/smoother_initialization.h"
#include "solver/smoother/smoother_problem.h"

#include "tests/scenario_support.h"

namespace mavloc {
namespace {

using testing::Simulate;

// The truth at t (linear / slerp between ground-truth rows).
SmootherKeyframe TruthKeyframe(const Dataset& dataset, TimeNs t_ns) {
  const auto& gt = dataset.ground_truth;
  auto it = std::lower_bound(gt.begin(), gt.end(), t_ns,
                             [](const GroundTruthState& s, TimeNs t) { return s.t_ns < t; });
  if (it == gt.end()) it = std::prev(gt.end());
  const GroundTruthState& b = *it;
  const GroundTruthState& a = it == gt.begin() ? b : *std::prev(it);
  const double u = b.t_ns == a.t_ns
                       ? 0.0
                       : static_cast<double>(t_ns - a.t_ns) / static_cast<double>(b.t_ns - a.t_ns);
  SmootherKeyframe kf;
  kf.t_ns = t_ns;
  kf.state.q_W_B = a.T_W_B.q.slerp(u, b.T_W_B.q).normalized();
  kf.state.p_W = (1 - u) * a.T_W_B.p + u * b.T_W_B.p;
  kf.state.v_W = (1 - u) * a.v_W + u * b.v_W;
  kf.state.biases.b_g = (1 - u) * a.b_g + u * b.b_g;
  kf.state.biases.b_a = (1 - u) * a.b_a + u * b.b_a;
  return kf;
}

SmootherResult SmootherAtTruth(const Dataset& dataset, SmootherProblemOptions options) {
  options.loss = SmootherLoss::kNone;
  options.max_iterations = 0;  // evaluate at the truth
  options.relinearize_rounds = 0;
  options.compute_covariance = true;
  std::vector<SmootherKeyframe> truth;
  for (const TimeNs t : SmootherKeyframeTimes(dataset)) truth.push_back(TruthKeyframe(dataset, t));
  return SolveSmoother(dataset, truth, {}, std::nullopt, options);
}

TEST(CrlbBoardBound, MarkerBoardFlightAgreesWithTheSmoothersCovarianceAtTheTruth) {
  const Dataset dataset = Simulate("marker-board-flight", 3, 8.0);
  ASSERT_FALSE(dataset.ground_truth.empty());
  const SmootherCrlb bound = ComputeSmootherCrlb(dataset);
  ASSERT_TRUE(bound.ok) << bound.reason;
  const SmootherResult result =
      SmootherAtTruth(dataset, SmootherEstimator(EstimatorOptions()).ProblemOptionsFor(dataset));
  ASSERT_EQ(result.pose_covariances.size(), bound.keyframes.size());
  double worst_position = 0.0, worst_attitude = 0.0;
  for (size_t k = 0; k < bound.keyframes.size(); ++k) {
    ASSERT_TRUE(result.pose_covariances[k].has_value());
    const auto& C = *result.pose_covariances[k];
    const CrlbSigmas s = SigmasOf(bound.keyframes[k].smoothing, bound.keyframes[k].T_W_B.q);
    worst_position = std::max(
        worst_position, std::abs(s.position_m / std::sqrt(C.topLeftCorner<3, 3>().trace()) - 1.0));
    worst_attitude =
        std::max(worst_attitude,
                 std::abs(s.attitude_rad / std::sqrt(C.bottomRightCorner<3, 3>().trace()) - 1.0));
  }
  std::printf("marker-board-flight: worst relative difference position %.4f attitude %.4f\n",
              worst_position, worst_attitude);
  EXPECT_LT(worst_position, 0.03);
  EXPECT_LT(worst_attitude, 0.03);
}

// The true R_W_M of an aprilgrid-calibration dataset (its truth quantities, core/board_frame.h).
Eigen::Matrix3d TrueBoardToWorld(const Dataset& dataset) {
  const QuantityTable& q = dataset.truth_quantities;
  const double roll = q.rows.at(0).at(q.Index("board_roll"));
  const double pitch = q.rows.at(0).at(q.Index("board_pitch"));
  return BoardToWorldRotation(
      UpInBoard(Eigen::Matrix3d(Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
                                Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))));
}

TEST(CrlbBoardBound, AprilgridTiltIsANuisanceParameter) {
  // The smoother does not estimate the camera-IMU time offset by default: simulate none.
  const Dataset dataset =
      Simulate("aprilgrid-calibration", 2, 6.0, {{"time_offset_ms", "0"}, {"stereo", "0"}});
  ASSERT_EQ(dataset.map.frame, MapFrame::kBoard);
  const SmootherCrlb bound = ComputeSmootherCrlb(dataset);
  ASSERT_TRUE(bound.ok) << bound.reason;
  ASSERT_TRUE(bound.tilt_covariance.has_value());

  // The smoother's tilt covariance at the truth (ceres::Covariance of its own factors).
  SmootherProblemOptions options = SmootherEstimator(EstimatorOptions()).ProblemOptionsFor(dataset);
  const Eigen::Matrix3d R_W_M = TrueBoardToWorld(dataset);
  options.initial_q_W_M = Eigen::Quaterniond(R_W_M);
  const SmootherResult result = SmootherAtTruth(dataset, options);
  ASSERT_TRUE(result.calibration.tilt_covariance.has_value());
  const Eigen::Matrix2d& C = *result.calibration.tilt_covariance;
  const Eigen::Matrix2d& B = *bound.tilt_covariance;
  std::printf("tilt sigma: bound %.4g %.4g rad, smoother at the truth %.4g %.4g rad\n",
              std::sqrt(B(0, 0)), std::sqrt(B(1, 1)), std::sqrt(C(0, 0)), std::sqrt(C(1, 1)));
  EXPECT_LT((B - C).norm() / C.norm(), 0.03);

  // The same data with the board put into W (tilt known): a bound that is nowhere larger, and
  // strictly smaller somewhere (the tilt is not free information).
  Dataset known = dataset;
  known.map.frame = MapFrame::kWorld;
  const Pose T_W_M(R_W_M, Eigen::Vector3d::Zero());
  for (auto& [id, tag] : known.map.tags) tag.T_W_T = T_W_M * tag.T_W_T;
  known.truth_quantities = QuantityTable();
  const SmootherCrlb known_bound = ComputeSmootherCrlb(known);
  ASSERT_TRUE(known_bound.ok) << known_bound.reason;
  ASSERT_EQ(known_bound.keyframes.size(), bound.keyframes.size());
  double largest_increase = 0.0;
  for (size_t k = 0; k < bound.keyframes.size(); ++k) {
    const double tilt_unknown = bound.keyframes[k].smoothing.topLeftCorner<6, 6>().trace();
    const double tilt_known = known_bound.keyframes[k].smoothing.topLeftCorner<6, 6>().trace();
    EXPECT_GE(tilt_unknown, tilt_known * (1.0 - 1e-9)) << k;
    largest_increase = std::max(largest_increase, tilt_unknown / tilt_known - 1.0);
  }
  EXPECT_GT(largest_increase, 1e-3);

  // The filtering bound has the tilt known: at the last keyframe it equals the smoothing bound of
  // the data with the board in W.
  ASSERT_TRUE(bound.keyframes.back().filtering.has_value());
  EXPECT_NEAR(bound.keyframes.back().filtering->trace(),
              known_bound.keyframes.back().smoothing.trace(),
              1e-6 * known_bound.keyframes.back().smoothing.trace());
}

TEST(CrlbBoardBound, EstimatedTimeOffsetIsNotInTheModel) {
  const Dataset dataset = Simulate("aprilgrid-calibration", 1, 3.0, {{"stereo", "0"}});
  EstimatorOptions options;
  options.Set("estimate_time_offset", "1");
  const SmootherCrlb bound = ComputeSmootherCrlb(dataset, options);
  EXPECT_FALSE(bound.ok);
  EXPECT_NE(bound.reason.find("time offset"), std::string::npos) << bound.reason;
  // A board map without the true tilt (e.g. an imported log): no bound, and it says why.
  Dataset no_truth = dataset;
  no_truth.truth_quantities = QuantityTable();
  const SmootherCrlb without = ComputeSmootherCrlb(no_truth);
  EXPECT_FALSE(without.ok);
  EXPECT_NE(without.reason.find("board_roll"), std::string::npos) << without.reason;
}

}  // namespace
}  // namespace mavloc
