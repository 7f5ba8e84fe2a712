// Alignment and trajectory metrics: se3 recovers a known rigid transform to 1e-9, sim3 also the
// scale, posyaw leaves roll and pitch untouched; ATE statistics match an independent computation.
#include "evaluation/alignment.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "core/random.h"
#include "core/rotation.h"
#include "evaluation/association.h"
#include "evaluation/trajectory_evaluation.h"
#include "evaluation/trajectory_metrics.h"

namespace mavloc {
namespace {

std::vector<StampedPose> RandomTrajectory(Rng& rng, int n) {
  std::vector<StampedPose> poses;
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  for (int i = 0; i < n; ++i) {
    p += rng.Gaussian3(0.1);
    poses.push_back({1'000'000'000 + i * 50'000'000LL,
                     Pose{QuaternionFromEuler(
                              {rng.Uniform(-0.3, 0.3), rng.Uniform(-0.3, 0.3), rng.Uniform(-3, 3)}),
                          p}});
  }
  return poses;
}

// est = S^-1 applied to gt: p_est = (R^T (p_gt - t)) / s, q_est = R^T q_gt.
std::vector<StampedPose> Transform(const std::vector<StampedPose>& gt, const Similarity& S) {
  std::vector<StampedPose> est;
  for (const auto& pose : gt) {
    est.push_back({pose.t_ns, Pose(Eigen::Quaterniond(S.R.transpose()) * pose.T_W_B.q,
                                   S.R.transpose() * (pose.T_W_B.p - S.t) / S.scale)});
  }
  return est;
}

// The APE of the one trajectory-error engine, nearest association within 1 ms, no RPE.
std::optional<TrajectoryEvaluation> Ate(const std::vector<StampedPose>& est,
                                        const std::vector<StampedPose>& gt, AlignmentMode mode) {
  EvaluationProtocol protocol;
  protocol.max_dt_s = 1e-3;
  protocol.alignment = mode;
  protocol.rpe_deltas.clear();
  protocol.relative_length_fractions.clear();
  return EvaluateTrajectory(est, gt, protocol);
}

TEST(Alignment, Se3RecoversARigidTransform) {
  Rng rng(1);
  for (int trial = 0; trial < 20; ++trial) {
    const auto gt = RandomTrajectory(rng, 100);
    Similarity S;
    S.R = ExpSO3(rng.Gaussian3(1.0));
    S.t = rng.Gaussian3(5.0);
    const auto ate = Ate(Transform(gt, S), gt, AlignmentMode::kSe3);
    ASSERT_TRUE(ate.has_value());
    ASSERT_EQ(ate->pair_count, gt.size());
    EXPECT_NEAR((ate->alignment.R - S.R).norm(), 0.0, 1e-9);
    EXPECT_NEAR((ate->alignment.t - S.t).norm(), 0.0, 1e-9);
    EXPECT_DOUBLE_EQ(ate->alignment.scale, 1.0);
    EXPECT_LT(ate->ape_translation_m.max, 1e-9);
    EXPECT_LT(ate->ape_rotation_deg.max * kDeg, 1e-9);
  }
}

TEST(Alignment, Sim3RecoversTheScale) {
  Rng rng(2);
  for (int trial = 0; trial < 20; ++trial) {
    const auto gt = RandomTrajectory(rng, 80);
    Similarity S;
    S.R = ExpSO3(rng.Gaussian3(1.0));
    S.t = rng.Gaussian3(5.0);
    S.scale = rng.Uniform(0.2, 5.0);
    const auto ate = Ate(Transform(gt, S), gt, AlignmentMode::kSim3);
    ASSERT_TRUE(ate.has_value());
    EXPECT_NEAR(ate->alignment.scale, S.scale, 1e-9 * S.scale);
    EXPECT_NEAR((ate->alignment.R - S.R).norm(), 0.0, 1e-9);
    EXPECT_LT(ate->ape_translation_m.max, 1e-9);
    // se3 cannot absorb the scale.
    EXPECT_GT(Ate(Transform(gt, S), gt, AlignmentMode::kSe3)->ape_translation_m.rmse,
              std::abs(S.scale - 1.0) > 0.1 ? 1e-3 : 0.0);
  }
}

TEST(Alignment, PosYawRecoversYawAndTranslationAndKeepsRollPitch) {
  Rng rng(3);
  for (int trial = 0; trial < 20; ++trial) {
    const auto gt = RandomTrajectory(rng, 60);
    Similarity S;
    S.R = Rz(rng.Uniform(-M_PI, M_PI));
    S.t = rng.Gaussian3(3.0);
    const auto est = Transform(gt, S);
    const auto ate = Ate(est, gt, AlignmentMode::kPosYaw);
    ASSERT_TRUE(ate.has_value());
    EXPECT_NEAR((ate->alignment.R - S.R).norm(), 0.0, 1e-9);
    EXPECT_LT(ate->ape_translation_m.max, 1e-9);
    // Even against a full 3-D rotation offset, posyaw only rotates about z: roll and pitch of the
    // aligned estimate equal the estimate's own.
    Similarity tilted;
    tilted.R = ExpSO3(rng.Gaussian3(0.5));
    const auto est2 = Transform(gt, tilted);
    const auto ate2 = Ate(est2, gt, AlignmentMode::kPosYaw);
    ASSERT_TRUE(ate2.has_value());
    EXPECT_NEAR(ate2->alignment.R(2, 2), 1.0, 1e-12);
    for (const auto& pose : est2) {
      const EulerRpy before = EulerFromQuaternion(pose.T_W_B.q);
      const EulerRpy after =
          EulerFromQuaternion(Eigen::Quaterniond(ate2->alignment.R) * pose.T_W_B.q);
      EXPECT_NEAR(WrapAngle(after.roll - before.roll), 0.0, 1e-9);
      EXPECT_NEAR(after.pitch - before.pitch, 0.0, 1e-9);
    }
  }
}

TEST(Alignment, DegenerateInputs) {
  std::vector<Eigen::Vector3d> same(5, Eigen::Vector3d(1, 2, 3));
  EXPECT_FALSE(AlignPoints(same, same, AlignmentMode::kSe3).has_value());
  EXPECT_FALSE(
      AlignPoints({Eigen::Vector3d::Zero()}, {Eigen::Vector3d::Zero()}, AlignmentMode::kSim3)
          .has_value());
  EXPECT_TRUE(AlignPoints(same, same, AlignmentMode::kNone).has_value());
  EXPECT_EQ(ParseAlignmentMode("posyaw"), AlignmentMode::kPosYaw);
  EXPECT_FALSE(ParseAlignmentMode("affine").has_value());
}

TEST(Ate, StatisticsMatchAnIndependentComputation) {
  Rng rng(4);
  const auto gt = RandomTrajectory(rng, 51);
  auto est = gt;
  std::vector<double> errors;
  for (auto& pose : est) {
    const Eigen::Vector3d offset = rng.Gaussian3(0.05);
    pose.T_W_B.p += offset;
    errors.push_back(offset.norm());
  }
  const auto ate = Ate(est, gt, AlignmentMode::kNone);
  ASSERT_TRUE(ate.has_value());
  // Independent computation.
  const double n = errors.size();
  double sum = 0, sum_sq = 0;
  for (double e : errors) {
    sum += e;
    sum_sq += e * e;
  }
  std::vector<double> sorted = errors;
  std::sort(sorted.begin(), sorted.end());
  const double mean = sum / n;
  double var = 0;
  for (double e : errors) var += (e - mean) * (e - mean);
  EXPECT_NEAR(ate->ape_translation_m.rmse, std::sqrt(sum_sq / n), 1e-12);
  EXPECT_NEAR(ate->ape_translation_m.mean, mean, 1e-12);
  EXPECT_NEAR(ate->ape_translation_m.median, sorted[25], 1e-12);
  EXPECT_NEAR(ate->ape_translation_m.std, std::sqrt(var / n), 1e-12);
  EXPECT_NEAR(ate->ape_translation_m.min, sorted.front(), 1e-12);
  EXPECT_NEAR(ate->ape_translation_m.max, sorted.back(), 1e-12);
  EXPECT_EQ(ate->ape_translation_m.count, 51u);
}

TEST(Association, InterpolatesPositionsAndSlerpsRotations) {
  std::vector<StampedPose> gt = {
      {0, Pose(QuaternionFromEuler({0, 0, 0.0}), Eigen::Vector3d(0, 0, 0))},
      {100, Pose(QuaternionFromEuler({0, 0, 1.0}), Eigen::Vector3d(1, 2, 3))}};
  const std::vector<StampedPose> est = {{25, Pose()}, {100, Pose()}, {200, Pose()}};
  const auto pairs = AssociatePoses(est, gt, 1.0);
  ASSERT_EQ(pairs.size(), 2u);  // t = 200 is outside the ground truth
  EXPECT_TRUE(pairs[0].T_W_B_gt.p.isApprox(Eigen::Vector3d(0.25, 0.5, 0.75)));
  EXPECT_NEAR(EulerFromQuaternion(pairs[0].T_W_B_gt.q).yaw, 0.25, 1e-12);
  // Nearest within a tolerance.
  const auto nearest = AssociatePoses(est, gt, 30e-9, AssociationMode::kNearest);
  ASSERT_EQ(nearest.size(), 2u);
  EXPECT_TRUE(nearest[0].T_W_B_gt.p.isZero());
  EXPECT_TRUE(AssociatePoses(est, gt, 10e-9, AssociationMode::kNearest).size() == 1u);
}

TEST(Association, AngleQuantitiesInterpolateAlongTheShorterArc) {
  QuantityTable truth = MakeQuantityTable({"yaw", "x"});
  truth.Append(0, {M_PI - 0.1, 0.0});
  truth.Append(100, {-M_PI + 0.1, 1.0});
  const auto at = TruthQuantitiesAt(truth, {50}, 1.0);
  ASSERT_EQ(at.size(), 1u);
  EXPECT_NEAR(std::abs(at.rows[0][0]), M_PI, 1e-12);
  EXPECT_NEAR(at.rows[0][1], 0.5, 1e-12);
}

TEST(Rpe, ExactForAConstantRelativeError) {
  // est drifts by 1 cm per metre along x: over 1 m windows the translation RPE is 1 cm.
  std::vector<StampedPose> gt, est;
  for (int i = 0; i <= 100; ++i) {
    gt.push_back(
        {i * 10'000'000LL, Pose(Eigen::Quaterniond::Identity(), Eigen::Vector3d(0.1 * i, 0, 0))});
    est.push_back(
        {i * 10'000'000LL, Pose(Eigen::Quaterniond::Identity(), Eigen::Vector3d(0.101 * i, 0, 0))});
  }
  const auto pairs = AssociatePoses(est, gt, 1e-3);
  auto rpe_over = [&](double delta, DeltaUnit unit) {
    RpeDelta window;
    window.delta = delta;
    window.unit = unit;
    window.pairs_from_reference = true;  // 1 m along the truth
    return ComputeRpeEvo(pairs, window);
  };
  const auto rpe = rpe_over(1.0, DeltaUnit::kMetres);
  ASSERT_TRUE(rpe.has_value());
  EXPECT_NEAR(rpe->translation_m.mean, 0.01, 1e-9);
  EXPECT_NEAR(rpe->translation_m.max, 0.01, 1e-9);
  const auto rpe_time = rpe_over(0.5, DeltaUnit::kSeconds);  // 50 samples = 5 m
  ASSERT_TRUE(rpe_time.has_value());
  EXPECT_NEAR(rpe_time->translation_m.mean, 0.05, 1e-9);
  EXPECT_FALSE(rpe_over(100.0, DeltaUnit::kMetres).has_value());
}

}  // namespace
}  // namespace mavloc
