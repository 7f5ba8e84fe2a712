// evo's metrics on tiny trajectories whose answers are worked out by hand in the comments:
// statistics (evo get_all_statistics), the four pose relations, association (sync.py: shorter
// trajectory walked, first match on ties, max_diff, offset), alignment (n_to_align, first-pose,
// align_origin, degenerate refusal) and RPE pair selection (filters.py) and values.
#include "evaluation/trajectory_metrics.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/rotation.h"
#include "evaluation/trajectory_evaluation.h"

namespace mavloc {
namespace {

constexpr TimeNs kMs = 1'000'000;

StampedPose At(TimeNs t_ns, const Eigen::Vector3d& p,
               const Eigen::Matrix3d& R = Eigen::Matrix3d::Identity()) {
  return {t_ns, Pose(R, p)};
}

using Pairs = std::vector<std::pair<size_t, size_t>>;

TEST(TrajectoryStatistics, EvenAndOddCountsAsNumpy) {
  // e = {1, 2, 3, 4}: sse = 30, rmse = sqrt(30 / 4), mean 2.5, median (2 + 3) / 2,
  // std = sqrt((1.5^2 + 0.5^2 + 0.5^2 + 1.5^2) / 4) = sqrt(1.25).
  const ErrorStatistics s = ComputeStatistics({4.0, 1.0, 3.0, 2.0});
  EXPECT_DOUBLE_EQ(s.sse, 30.0);
  EXPECT_DOUBLE_EQ(s.rmse, std::sqrt(7.5));
  EXPECT_DOUBLE_EQ(s.mean, 2.5);
  EXPECT_DOUBLE_EQ(s.median, 2.5);
  EXPECT_DOUBLE_EQ(s.std, std::sqrt(1.25));
  EXPECT_DOUBLE_EQ(s.min, 1.0);
  EXPECT_DOUBLE_EQ(s.max, 4.0);
  EXPECT_EQ(s.count, 4u);
  EXPECT_DOUBLE_EQ(ComputeStatistics({3.0, 1.0, 2.0}).median, 2.0);
  EXPECT_EQ(ComputeStatistics({}).count, 0u);
}

TEST(TrajectoryMetrics, PoseRelationsOfOneErrorTransform) {
  // E = (Rz(90 deg), (3, 4, 0)): ||t|| = 5; angle 90 deg; Rz(90) - I = [[-1, -1, 0], [1, -1, 0],
  // [0, 0, 0]] so ||R - I||_F = 2; ||E - I_4||_F = sqrt(4 + 25).
  const PoseErrorValues e = PoseErrors(Rz(90 * kDeg), Eigen::Vector3d(3, 4, 0));
  EXPECT_NEAR(e.translation_m, 5.0, 1e-12);
  EXPECT_NEAR(e.rotation_deg, 90.0, 1e-12);
  EXPECT_NEAR(e.rotation_part, 2.0, 1e-12);
  EXPECT_NEAR(e.full, std::sqrt(29.0), 1e-12);
  // Small and half-turn angles keep their precision (atan2 form).
  EXPECT_NEAR(PoseErrors(Rx(1e-7), Eigen::Vector3d::Zero()).rotation_deg, 1e-7 / kDeg, 1e-16);
  EXPECT_NEAR(PoseErrors(Ry(M_PI), Eigen::Vector3d::Zero()).rotation_deg, 180.0, 1e-9);
}

TEST(TrajectoryMetrics, ApeThroughTheEntryPoint) {
  // Truth: identity at x = 0, 1, 2. Estimate: the same except pose 1 at (1, 3, 4) rotated
  // Rz(90): errors (0, 5, 0) m, (0, 90, 0) deg, rot_part (0, 2, 0), full (0, sqrt(2^2 + 5^2), 0).
  // (evo uses E = T_est^-1 T_gt for APE: same norms as T_gt^-1 T_est.)
  std::vector<StampedPose> gt, est;
  for (int i = 0; i < 3; ++i) gt.push_back(At(i * 100 * kMs, Eigen::Vector3d(i, 0, 0)));
  est = gt;
  est[1] = At(100 * kMs, Eigen::Vector3d(1, 3, 4), Rz(90 * kDeg));
  EvaluationProtocol protocol;
  protocol.alignment = AlignmentMode::kNone;
  const auto r = EvaluateTrajectory(est, gt, protocol);
  ASSERT_TRUE(r.has_value());
  EXPECT_EQ(r->pair_count, 3u);
  EXPECT_NEAR(r->ape.translation_m[1], 5.0, 1e-12);
  EXPECT_NEAR(r->ape_translation_m.rmse, std::sqrt(25.0 / 3.0), 1e-12);
  EXPECT_NEAR(r->ape_translation_m.mean, 5.0 / 3.0, 1e-12);
  EXPECT_NEAR(r->ape_translation_m.median, 0.0, 1e-12);
  EXPECT_NEAR(r->ape_rotation_deg.max, 90.0, 1e-9);
  EXPECT_NEAR(r->ape_rotation_part.sse, 4.0, 1e-12);
  EXPECT_NEAR(r->ape_full.max, std::sqrt(29.0), 1e-12);
  protocol.ape_relation = PoseRelation::kFull;
  EXPECT_NEAR(EvaluateTrajectory(est, gt, protocol)->HeadlineApe().max, std::sqrt(29.0), 1e-12);
}

TEST(Association, EvoNearestWalksTheShorterTrajectory) {
  // Truth 0, 10, 20, 30, 40 ms; estimate 5, 16, 55 ms; max_diff 10 ms. The estimate is shorter:
  // 5 -> |5 - 0| = |5 - 10| = 5, first minimum -> truth 0; 16 -> truth 20 (4 ms); 55 -> 40 is
  // 15 ms away: dropped.
  std::vector<StampedPose> gt, est;
  for (int i = 0; i < 5; ++i) gt.push_back(At(i * 10 * kMs, Eigen::Vector3d(i, 0, 0)));
  for (TimeNs t : {5, 16, 55}) est.push_back(At(t * kMs, Eigen::Vector3d::Zero()));
  auto a = AssociateTrajectories(est, gt, {AssociationMode::kNearest, 0.010, 0.0});
  ASSERT_EQ(a.pairs.size(), 2u);
  EXPECT_EQ(a.truth_index, (std::vector<size_t>{0, 2}));
  EXPECT_EQ(a.estimate_index, (std::vector<size_t>{0, 1}));
  EXPECT_EQ(a.pairs[1].T_W_B_gt.p.x(), 2.0);
  // Swapped lengths: the truth (3 stamps) is walked, each picks the nearest estimate stamp.
  a = AssociateTrajectories(gt, est, {AssociationMode::kNearest, 0.010, 0.0});
  EXPECT_EQ(a.estimate_index, (std::vector<size_t>{0, 2}));
  EXPECT_EQ(a.truth_index, (std::vector<size_t>{0, 1}));
  // A stamp of the longer trajectory is used twice: truth 1, 2 ms (walked) both pick estimate 0.
  a = AssociateTrajectories({At(0, {0, 0, 0}), At(10 * kMs, {1, 0, 0}), At(20 * kMs, {2, 0, 0})},
                            {At(1 * kMs, {0, 0, 0}), At(2 * kMs, {0, 0, 0})},
                            {AssociationMode::kNearest, 0.010, 0.0});
  EXPECT_EQ(a.estimate_index, (std::vector<size_t>{0, 0}));
  // Equal lengths: the estimate is walked (evo: snd_longer is false).
  a = AssociateTrajectories({At(0, {0, 0, 0}), At(14 * kMs, {0, 0, 0})},
                            {At(4 * kMs, {0, 0, 0}), At(10 * kMs, {0, 0, 0})},
                            {AssociationMode::kNearest, 0.010, 0.0});
  EXPECT_EQ(a.truth_index, (std::vector<size_t>{0, 1}));
  // Offset: estimate stamps 1000 s later, shifted back by -1000 s (evo --t_offset).
  std::vector<StampedPose> late = est;
  for (auto& pose : late) pose.t_ns += 1000 * kNsPerSecond;
  a = AssociateTrajectories(late, gt, {AssociationMode::kNearest, 0.010, -1000.0});
  EXPECT_EQ(a.truth_index, (std::vector<size_t>{0, 2}));
  EXPECT_EQ(a.pairs[0].t_ns, 5 * kMs);
  // A gap of exactly max_diff matches (integer nanoseconds).
  EXPECT_EQ(AssociateTrajectories({At(10 * kMs, {0, 0, 0})}, {At(0, {0, 0, 0})},
                                  {AssociationMode::kNearest, 0.010, 0.0})
                .pairs.size(),
            1u);
}

TEST(Association, InterpolatesInsideTheTruthSpan) {
  // Truth at 0 ms (origin, identity) and 10 ms ((1, 0, 0), Rz(90)). Estimate at 2.5 ms: a = 0.25,
  // p = (0.25, 0, 0), rotation Rz(22.5 deg). 12 ms lies after the last truth stamp: dropped.
  const std::vector<StampedPose> gt = {At(0, {0, 0, 0}), At(10 * kMs, {1, 0, 0}, Rz(M_PI / 2))};
  const std::vector<StampedPose> est = {At(2'500'000, {0, 0, 0}), At(12 * kMs, {0, 0, 0})};
  const auto a = AssociateTrajectories(est, gt, {AssociationMode::kInterpolate, 0.010, 0.0});
  ASSERT_EQ(a.pairs.size(), 1u);
  EXPECT_NEAR(a.pairs[0].T_W_B_gt.p.x(), 0.25, 1e-12);
  EXPECT_NEAR(RotationAngleBetween(a.pairs[0].T_W_B_gt.q, Eigen::Quaterniond(Rz(M_PI / 8))), 0.0,
              1e-12);
}

TEST(Alignment, FirstNPairsFirstPoseAndOrigin) {
  // n_to_align = 3 (evo --n_to_align): pairs 0..2 are the truth shifted by (1, 0, 0) and fix the
  // se3 alignment to t = (-1, 0, 0); the 4th estimate (9, 0, 0) against truth (5, 5, 5) then
  // has error |(8, 0, 0) - (5, 5, 5)| = sqrt(9 + 25 + 25).
  const std::vector<Eigen::Vector3d> g = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {5, 5, 5}};
  std::vector<StampedPose> gt, est;
  for (int i = 0; i < 4; ++i) {
    gt.push_back(At(i * 100 * kMs, g[i]));
    est.push_back(At(i * 100 * kMs, i < 3 ? Eigen::Vector3d(g[i] + Eigen::Vector3d(1, 0, 0))
                                          : Eigen::Vector3d(9, 0, 0)));
  }
  EvaluationProtocol protocol;
  protocol.alignment = AlignmentMode::kSe3;
  protocol.n_to_align = 3;
  auto r = EvaluateTrajectory(est, gt, protocol);
  ASSERT_TRUE(r.has_value());
  EXPECT_EQ(r->aligned_pairs, 3u);
  EXPECT_NEAR((r->alignment.t - Eigen::Vector3d(-1, 0, 0)).norm(), 0.0, 1e-12);
  EXPECT_NEAR(r->ape.translation_m[3], std::sqrt(59.0), 1e-12);

  // One frame with posyaw (rpg alignPositionYawSingle): truth pose 0 has yaw 70 deg, estimate
  // yaw 30 deg at (1, 0, 0): R = Rz(40 deg), t = p_gt0 - Rz(40) (1, 0, 0).
  gt[0] = At(0, {2, 3, 0}, Rz(70 * kDeg));
  est[0] = At(0, {1, 0, 0}, Rz(30 * kDeg));
  protocol.alignment = AlignmentMode::kPosYaw;
  protocol.n_to_align = 1;
  r = EvaluateTrajectory(est, gt, protocol);
  ASSERT_TRUE(r.has_value());
  EXPECT_NEAR((r->alignment.R - Rz(40 * kDeg)).norm(), 0.0, 1e-12);
  EXPECT_NEAR(
      (r->alignment.t - (Eigen::Vector3d(2, 3, 0) - Rz(40 * kDeg) * Eigen::Vector3d(1, 0, 0)))
          .norm(),
      0.0, 1e-12);
  EXPECT_NEAR(r->ape.translation_m[0], 0.0, 1e-12);
  EXPECT_NEAR(r->ape.rotation_deg[0], 0.0, 1e-9);

  // align_origin (evo): T = T_gt0 T_est0^-1 = (Rz(40), (2, 3, 0) - Rz(40) (1, 0, 0)): the same
  // transform here; combined with another alignment it is refused, as evo does.
  protocol.alignment = AlignmentMode::kNone;
  protocol.n_to_align = -1;
  protocol.align_origin = true;
  r = EvaluateTrajectory(est, gt, protocol);
  ASSERT_TRUE(r.has_value());
  EXPECT_NEAR((r->alignment.R - Rz(40 * kDeg)).norm(), 0.0, 1e-12);
  EXPECT_NEAR(r->ape.translation_m[0], 0.0, 1e-12);
  protocol.alignment = AlignmentMode::kSe3;
  std::string why;
  EXPECT_FALSE(EvaluateTrajectory(est, gt, protocol, &why).has_value());
  EXPECT_NE(why.find("align_origin"), std::string::npos);
}

TEST(Alignment, CollinearPointsAreRefusedAsEvo) {
  // Points on a line: cross-covariance of rank 1, evo raises "Degenerate covariance rank".
  std::vector<Eigen::Vector3d> line;
  for (int i = 0; i < 5; ++i) line.emplace_back(i, 2.0 * i, 0.0);
  EXPECT_FALSE(AlignPoints(line, line, AlignmentMode::kSe3).has_value());
  EXPECT_TRUE(AlignPoints(line, line, AlignmentMode::kPosYaw).has_value());
}

TEST(RpePairs, FramesAsFiltersPy) {
  // n = 7, delta 2: consecutive ids 0, 2, 4, 6 -> (0,2) (2,4) (4,6); all pairs (i, i + 2).
  const std::vector<Eigen::Vector3d> p(7, Eigen::Vector3d::Zero());
  EXPECT_EQ(SelectRpePairs(p, {}, {2, DeltaUnit::kFrames, false}), (Pairs{{0, 2}, {2, 4}, {4, 6}}));
  EXPECT_EQ(SelectRpePairs(p, {}, {2, DeltaUnit::kFrames, true}),
            (Pairs{{0, 2}, {1, 3}, {2, 4}, {3, 5}, {4, 6}}));
  // delta 3: ids 0, 3, 6 -> (0,3) (3,6).
  EXPECT_EQ(SelectRpePairs(p, {}, {3, DeltaUnit::kFrames, false}), (Pairs{{0, 3}, {3, 6}}));
}

TEST(RpePairs, PathAsFiltersPy) {
  // x = 0, 0.5, 1.0, 1.75, 2.5, 3.25 (exact binary fractions).
  std::vector<Eigen::Vector3d> p;
  for (double x : {0.0, 0.5, 1.0, 1.75, 2.5, 3.25}) p.emplace_back(x, 0, 0);
  // Consecutive, delta 0.9: path counts 0, .5, 1.0 -> keep 2 and restart; .75, 1.5 -> keep 4;
  // .75 -> ids (2, 4): one pair.
  EXPECT_EQ(SelectRpePairs(p, {}, {0.9, DeltaUnit::kMetres, false}), (Pairs{{2, 4}}));
  // All pairs, delta 1, tol 0.1: from 0 the distances .5 1 1.75 2.5 3.25 -> j = 2 exact; from 1:
  // .5 1.25 .. -> best off by .25 > .1, rejected; likewise from 2, 3, 4.
  EXPECT_EQ(SelectRpePairs(p, {}, {1.0, DeltaUnit::kMetres, true, 0.1}), (Pairs{{0, 2}}));
  // With tol 0.3: (1, 3) (off .25), (2, 3) (.75 off .25 beats 1.5), (3, 4), (4, 5).
  EXPECT_EQ(SelectRpePairs(p, {}, {1.0, DeltaUnit::kMetres, true, 0.3}),
            (Pairs{{0, 2}, {1, 3}, {2, 3}, {3, 4}, {4, 5}}));
  // Tie: from 0, distances .5 and 1.5 are both .5 off delta 1: numpy.argmin keeps the first.
  std::vector<Eigen::Vector3d> q = {{0, 0, 0}, {0.5, 0, 0}, {1.5, 0, 0}};
  EXPECT_EQ(SelectRpePairs(q, {}, {1.0, DeltaUnit::kMetres, true, 0.5}), (Pairs{{0, 1}, {1, 2}}));
  // Standing still: x = 0, 1, 1, 1, 2: from 0 the distances 1, 1, 1, 2 -> first j = 1.
  std::vector<Eigen::Vector3d> still = {{0, 0, 0}, {1, 0, 0}, {1, 0, 0}, {1, 0, 0}, {2, 0, 0}};
  const Pairs all = SelectRpePairs(still, {}, {1.0, DeltaUnit::kMetres, true, 0.1});
  ASSERT_FALSE(all.empty());
  EXPECT_EQ(all.front(), (std::pair<size_t, size_t>{0, 1}));
  // Seconds: the stamps as the abscissa, same rules.
  EXPECT_EQ(SelectRpePairs({}, {0.0, 0.5, 1.0, 1.75, 2.5, 3.25}, {0.9, DeltaUnit::kSeconds, false}),
            (Pairs{{2, 4}}));
}

TEST(Rpe, HandComputedErrors) {
  // Truth: identity at x = 0, 1, 2. Estimate: pose 1 turned Rz(90) in place.
  // Pair (0,1): Q_rel = (I, (1,0,0)), P_rel = (Rz90, (1,0,0)); E = (Rz90, 0): 0 m, 90 deg.
  // Pair (1,2): P_rel = (Rz(-90), Rz(-90)(1,0,0) = (0,-1,0)), E = (Rz(-90), (-1,-1,0)):
  //   sqrt(2) m, 90 deg, rot_part 2, full sqrt(4 + 2).
  std::vector<PosePair> pairs;
  for (int i = 0; i < 3; ++i) {
    PosePair pair;
    pair.t_ns = i * 100 * kMs;
    pair.T_W_B_gt = Pose(Eigen::Matrix3d::Identity(), Eigen::Vector3d(i, 0, 0));
    pair.T_W_B_est = pair.T_W_B_gt;
    pairs.push_back(pair);
  }
  pairs[1].T_W_B_est.q = Eigen::Quaterniond(Rz(M_PI / 2));
  const auto rpe = ComputeRpeEvo(pairs, {1, DeltaUnit::kFrames, false});
  ASSERT_TRUE(rpe.has_value());
  ASSERT_EQ(rpe->errors.size(), 2u);
  EXPECT_NEAR(rpe->errors[0].translation_m, 0.0, 1e-12);
  EXPECT_NEAR(rpe->errors[0].rotation_deg, 90.0, 1e-9);
  EXPECT_NEAR(rpe->errors[1].translation_m, std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(rpe->errors[1].rotation_part, 2.0, 1e-12);
  EXPECT_NEAR(rpe->errors[1].full, std::sqrt(6.0), 1e-12);
  // Statistics of {0, sqrt 2}: rmse 1, mean = median = std = sqrt(2) / 2, sse 2.
  EXPECT_NEAR(rpe->translation_m.rmse, 1.0, 1e-12);
  EXPECT_NEAR(rpe->translation_m.mean, std::sqrt(0.5), 1e-12);
  EXPECT_NEAR(rpe->translation_m.median, std::sqrt(0.5), 1e-12);
  EXPECT_NEAR(rpe->translation_m.std, std::sqrt(0.5), 1e-12);
  EXPECT_NEAR(rpe->translation_m.sse, 2.0, 1e-12);
  // delta 2 frames: only (0, 2), where both poses agree: zero error.
  const auto rpe2 = ComputeRpeEvo(pairs, {2, DeltaUnit::kFrames, false});
  ASSERT_TRUE(rpe2.has_value());
  EXPECT_EQ(rpe2->errors.size(), 1u);
  EXPECT_NEAR(rpe2->translation_m.max, 0.0, 1e-12);
  EXPECT_FALSE(ComputeRpeEvo(pairs, {3, DeltaUnit::kFrames, false}).has_value());
}

TEST(YawDrift, LinearYawErrorGivesItsSlope) {
  // Truth along x at 1 m/s, 10 poses 1 s apart; the estimate's yaw error is 0.5 deg per pose:
  // slope 0.5 deg/m and 0.5 deg/s, final 4.5 deg.
  std::vector<StampedPose> gt, est;
  for (int i = 0; i < 10; ++i) {
    gt.push_back(At(i * kNsPerSecond, Eigen::Vector3d(i, 0, 0), Rx(0.1 * i)));
    est.push_back(At(i * kNsPerSecond, Eigen::Vector3d(i, 0, 0), Rz(0.5 * i * kDeg) * Rx(0.1 * i)));
  }
  EvaluationProtocol protocol;
  protocol.alignment = AlignmentMode::kNone;
  const auto r = EvaluateTrajectory(est, gt, protocol);
  ASSERT_TRUE(r.has_value());
  ASSERT_TRUE(r->yaw_drift.valid);
  EXPECT_NEAR(r->yaw_drift.rate_deg_per_m, 0.5, 1e-9);
  EXPECT_NEAR(r->yaw_drift.rate_deg_per_s, 0.5, 1e-9);
  EXPECT_NEAR(r->yaw_drift.final_deg, 4.5, 1e-9);
}

}  // namespace
}  // namespace mavloc
