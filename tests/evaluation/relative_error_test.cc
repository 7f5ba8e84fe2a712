// Relative error over sub-trajectory lengths as rpg_trajectory_evaluation computes it: segment
// sampling (compute_comparison_indices_length), the default lengths (compute_boxplot_distances)
// and the segment error in %, deg/m, yaw and tilt, on cases worked out by hand.
#include "evaluation/relative_error.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/rotation.h"
#include "evaluation/trajectory_evaluation.h"

namespace mavloc {
namespace {

TEST(RelativeError, SegmentEndsAsRpg) {
  // dist = 0, 0.75, 2.25, 2.5, 4.0 (exact binary fractions), d = 2, tolerance 0.5 (strict):
  // 0 -> target 2: 2.25 off .25 -> 2; 1 -> 2.75: 2.5 off .25 -> 3; 2 -> 4.25: 4.0 off .25 -> 4;
  // 3 -> 4.5: 4.0 off exactly .5, not < .5 -> none; 4 -> none.
  EXPECT_EQ(SegmentEndIndices({0, 0.75, 2.25, 2.5, 4.0}, 2.0, 0.5),
            (std::vector<long>{2, 3, 4, -1, -1}));
  // Tie: target 2 between 1.5 and 2.5 (both .5 off, tolerance 1): rpg's strict '<' keeps 1.
  EXPECT_EQ(SegmentEndIndices({0, 1.5, 2.5}, 2.0, 1.0)[0], 1);
  // Standing still at 1 m: dist 0, 1, 1, 1; d = 1 -> the first of the run, index 1.
  EXPECT_EQ(SegmentEndIndices({0, 1, 1, 1}, 1.0, 0.2)[0], 1);
}

TEST(RelativeError, DefaultLengthsTruncateToCentimetres) {
  // rpg: truncate(pct * L, 2). L = 12.345: 1.2345 -> 1.23, 2.469 -> 2.46, 3.7035 -> 3.70,
  // 4.938 -> 4.93, 6.1725 -> 6.17.
  const auto lengths = DefaultRelativeLengths(12.345, {0.1, 0.2, 0.3, 0.4, 0.5});
  ASSERT_EQ(lengths.size(), 5u);
  EXPECT_NEAR(lengths[0], 1.23, 1e-12);
  EXPECT_NEAR(lengths[1], 2.46, 1e-12);
  EXPECT_NEAR(lengths[2], 3.70, 1e-12);
  EXPECT_NEAR(lengths[3], 4.93, 1e-12);
  EXPECT_NEAR(lengths[4], 6.17, 1e-12);
  // L = 0.05 m: 0.1 L = 0.005 truncates to 0 and is dropped.
  EXPECT_EQ(DefaultRelativeLengths(0.05, {0.1, 0.2, 0.3, 0.4, 0.5}).size(), 4u);
}

std::vector<PosePair> Line(int n) {
  std::vector<PosePair> pairs;
  for (int i = 0; i < n; ++i) {
    PosePair pair;
    pair.t_ns = i * kNsPerSecond;
    pair.T_W_B_gt = Pose(Eigen::Matrix3d::Identity(), Eigen::Vector3d(i, 0, 0));
    pair.T_W_B_est = pair.T_W_B_gt;
    pairs.push_back(pair);
  }
  return pairs;
}

TEST(RelativeError, ScaleErrorInPercent) {
  // Truth x = 0..4, estimate x' = 1.1 x. d = 2 (tolerance 0.4): segments (0,2) (1,3) (2,4);
  // each estimates 2.2 m for 2 m: 0.2 m = 10 %, no rotation. With the scale 1/1.1 (a Sim3
  // alignment's) the error vanishes.
  auto pairs = Line(5);
  for (auto& pair : pairs) pair.T_W_B_est.p *= 1.1;
  const auto dist = AccumulatedDistances(pairs);
  const auto r = ComputeRelativeError(pairs, dist, 2.0);
  ASSERT_EQ(r.count(), 3u);
  for (size_t k = 0; k < 3; ++k) {
    EXPECT_NEAR(r.translation_m[k], 0.2, 1e-12);
    EXPECT_NEAR(r.translation_percent[k], 10.0, 1e-10);
    EXPECT_NEAR(r.rotation_deg[k], 0.0, 1e-9);
  }
  EXPECT_NEAR(r.translation_percent_stats.rmse, 10.0, 1e-10);
  EXPECT_NEAR(ComputeRelativeError(pairs, dist, 2.0, 0.2, 1.0 / 1.1).translation_m_stats.max, 0.0,
              1e-12);
  // d = 4 fits one segment only: rpg computes nothing below 2 segments.
  EXPECT_EQ(ComputeRelativeError(pairs, dist, 4.0).count(), 0u);
}

TEST(RelativeError, RotationYawAndTilt) {
  // Estimate turns by yaw 2 deg from frame 2 on (positions exact), d = 2:
  //  (0,2): dT_est = (Rz2, (2,0,0)), dT_gt = (I, (2,0,0)): E = (Rz2, 0) -> 2 deg, 1 deg/m,
  //         yaw 2, tilt 0, 0 m;
  //  (1,3): the same;
  //  (2,4): no relative rotation, but the body-frame displacement is Rz(-2)(2,0,0): error
  //         |Rz(-2)(2,0,0) - (2,0,0)| = 4 sin(1 deg) m, 0 deg.
  auto pairs = Line(5);
  for (int i = 2; i < 5; ++i) pairs[i].T_W_B_est.q = Eigen::Quaterniond(Rz(2 * kDeg));
  const auto dist = AccumulatedDistances(pairs);
  auto r = ComputeRelativeError(pairs, dist, 2.0);
  ASSERT_EQ(r.count(), 3u);
  EXPECT_NEAR(r.rotation_deg[0], 2.0, 1e-9);
  EXPECT_NEAR(r.rotation_deg_per_m[0], 1.0, 1e-9);
  EXPECT_NEAR(r.yaw_deg[0], 2.0, 1e-9);
  EXPECT_NEAR(r.tilt_deg[0], 0.0, 1e-9);
  EXPECT_NEAR(r.translation_m[0], 0.0, 1e-12);
  EXPECT_NEAR(r.rotation_deg[1], 2.0, 1e-9);
  EXPECT_NEAR(r.translation_m[2], 4.0 * std::sin(1.0 * kDeg), 1e-12);
  EXPECT_NEAR(r.rotation_deg[2], 0.0, 1e-9);
  // A pitch error of 3 deg instead: tilt 3, yaw 0.
  for (int i = 2; i < 5; ++i) pairs[i].T_W_B_est.q = Eigen::Quaterniond(Ry(3 * kDeg));
  r = ComputeRelativeError(pairs, dist, 2.0);
  EXPECT_NEAR(r.tilt_deg[0], 3.0, 1e-9);
  EXPECT_NEAR(r.yaw_deg[0], 0.0, 1e-9);
}

TEST(RelativeError, EntryPointUsesDefaultLengthsOfTheTruthPath) {
  // Truth x = 0..20 (1 m steps, L = 20 m): default lengths 2, 4, 6, 8, 10 m, echoed in the
  // protocol; the estimate is exact, so every relative error is 0.
  std::vector<StampedPose> gt;
  for (int i = 0; i <= 20; ++i)
    gt.push_back(
        {i * kNsPerSecond / 10, Pose(Eigen::Matrix3d::Identity(), Eigen::Vector3d(i, 0, 0))});
  EvaluationProtocol protocol;
  protocol.alignment = AlignmentMode::kNone;  // a straight line cannot be Umeyama-aligned (evo)
  const auto r = EvaluateTrajectory(gt, gt, protocol);
  ASSERT_TRUE(r.has_value());
  EXPECT_EQ(r->protocol.relative_lengths_m, (std::vector<double>{2, 4, 6, 8, 10}));
  ASSERT_EQ(r->relative.size(), 5u);
  EXPECT_EQ(r->relative[0].count(), 19u);  // starts 0..18 (start 19 is 1 m short of 2 m, > 0.4)
  // d = 10: starts 0..10 reach 10 m further; start 11 ends at 20 m, 1 m short, inside rpg's
  // 0.2 d = 2 m tolerance; start 12 is 2 m short: not < 2, rejected.
  EXPECT_EQ(r->relative[4].count(), 12u);
  EXPECT_NEAR(r->relative[4].translation_percent_stats.max, 0.0, 1e-9);
}

// A long trajectory (60,000 pairs: relative errors on a second thread) evaluated keeping every
// segment and per-pair error and keeping only their statistics: the same counts and statistics
// (relative errors, APE, RPE), bit for bit.
TEST(RelativeError, StatisticsAloneMatchTheKeptSegments) {
  std::vector<StampedPose> gt, est;
  for (int i = 0; i < 60'000; ++i) {
    const double t = 0.01 * i;
    const Eigen::Vector3d p(20 * std::cos(0.05 * t), 15 * std::sin(0.07 * t), std::sin(0.3 * t));
    const Eigen::Quaterniond q(Rz(0.1 * t) * Ry(0.01 * std::sin(t)));
    gt.push_back({i * kNsPerSecond / 100, Pose(q, p)});
    const Eigen::Vector3d wobble(0.01 * std::sin(3 * t), 0.01 * std::cos(2 * t), 0.0);
    est.push_back({i * kNsPerSecond / 100,
                   Pose(q * Eigen::Quaterniond(Rx(0.002 * std::cos(t))), p + wobble)});
  }
  EvaluationProtocol kept;
  EvaluationProtocol statistics = kept;
  statistics.keep_series = false;
  const auto a = EvaluateTrajectory(est, gt, kept);
  const auto b = EvaluateTrajectory(est, gt, statistics);
  ASSERT_TRUE(a.has_value() && b.has_value());
  ASSERT_EQ(a->relative.size(), 5u);
  ASSERT_EQ(b->relative.size(), 5u);
  for (size_t k = 0; k < 5; ++k) {
    const RelativeErrorAtLength& full = a->relative[k];
    const RelativeErrorAtLength& alone = b->relative[k];
    EXPECT_GT(full.count(), 1000u);
    EXPECT_EQ(full.count(), full.translation_percent.size());
    EXPECT_EQ(alone.count(), full.count());
    EXPECT_TRUE(alone.translation_percent.empty());
    EXPECT_EQ(alone.translation_percent_stats.mean, full.translation_percent_stats.mean);
    EXPECT_EQ(alone.translation_percent_stats.median, full.translation_percent_stats.median);
    EXPECT_EQ(alone.rotation_deg_per_m_stats.rmse, full.rotation_deg_per_m_stats.rmse);
    EXPECT_EQ(alone.tilt_deg_stats.max, full.tilt_deg_stats.max);
    EXPECT_EQ(ComputeStatistics(full.yaw_deg).median, full.yaw_deg_stats.median);
  }
  EXPECT_EQ(a->ape.translation_m.size(), a->pair_count);
  EXPECT_TRUE(b->ape.translation_m.empty() && b->pair_t_ns.empty());
  for (const auto& [x, y] :
       {std::pair(a->ape_translation_m, b->ape_translation_m),
        std::pair(a->ape_rotation_deg, b->ape_rotation_deg), std::pair(a->ape_full, b->ape_full)}) {
    EXPECT_EQ(x.rmse, y.rmse);
    EXPECT_EQ(x.median, y.median);
    EXPECT_EQ(x.std, y.std);
  }
  ASSERT_EQ(a->rpe.size(), 1u);
  ASSERT_EQ(b->rpe.size(), 1u);
  EXPECT_EQ(a->rpe[0].errors.size(), a->pair_count - 1);
  EXPECT_TRUE(b->rpe[0].errors.empty() && b->rpe[0].t_ns.empty());
  EXPECT_EQ(a->rpe[0].translation_m.median, b->rpe[0].translation_m.median);
  EXPECT_EQ(a->rpe[0].rotation_deg.rmse, b->rpe[0].rotation_deg.rmse);
}

}  // namespace
}  // namespace mavloc
