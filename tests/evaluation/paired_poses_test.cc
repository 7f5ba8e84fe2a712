// Pairs by index (evaluation/paired_poses.h) give, pose for pose and bit for bit, the pairs that
// AssociatePoses copies out (its own bracketing and interpolation) where the truth is
// interpolated, the truth sample itself where a stamp falls on one (AssociatePoses slerps it with
// weight 0, a few ulp away), and the aligned estimate of ApplySimilarity.
#include "evaluation/paired_poses.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/rotation.h"
#include "evaluation/association.h"

namespace mavloc {
namespace {

// Truth at 100 Hz, estimate at 70 Hz: every seventh estimate stamp falls on a truth stamp, the
// others between two.
void Trajectories(std::vector<StampedPose>* truth, std::vector<StampedPose>* estimate) {
  for (int i = 0; i < 1000; ++i) {
    const double t = 0.01 * i;
    truth->push_back(
        {i * kNsPerSecond / 100, Pose(Eigen::Quaterniond(Rz(0.7 * t) * Rx(0.2 * std::sin(t))),
                                      Eigen::Vector3d(std::cos(t), std::sin(2 * t), 0.1 * t))});
  }
  for (int i = 0; i < 700; ++i) {
    const double t = i / 70.0;
    estimate->push_back({static_cast<TimeNs>(std::llround(t * kNsPerSecond)),
                         Pose(Eigen::Quaterniond(Ry(0.1 * t)), Eigen::Vector3d(t, 0.0, 1.0))});
  }
}

void ExpectSameBits(const Pose& a, const Pose& b) {
  EXPECT_EQ(a.q.coeffs(), b.q.coeffs());
  EXPECT_EQ(a.p, b.p);
}

TEST(PairedPoses, InterpolatedPairsEqualAssociatePoses) {
  std::vector<StampedPose> truth, estimate;
  Trajectories(&truth, &estimate);
  const auto copied = AssociatePoses(estimate, truth, 0.01, AssociationMode::kInterpolate);
  const PairedPoses pairs =
      AssociatePairs(estimate, truth, {AssociationMode::kInterpolate, 0.01, 0.0});
  ASSERT_EQ(pairs.size(), copied.size());
  ASSERT_GT(pairs.size(), 600u);
  size_t exact = 0;
  for (size_t i = 0; i < pairs.size(); ++i) {
    const PosePair pair = pairs[i];
    EXPECT_EQ(pair.t_ns, copied[i].t_ns);
    EXPECT_EQ(pairs.t_ns(i), copied[i].t_ns);
    ExpectSameBits(pair.T_W_B_est, copied[i].T_W_B_est);
    EXPECT_EQ(pairs.p_gt(i), pair.T_W_B_gt.p);
    const StampedPose& low = truth[pairs.truth_index(i)];
    if (low.t_ns == pair.t_ns) {
      ++exact;
      ExpectSameBits(pair.T_W_B_gt, low.T_W_B);
      EXPECT_LT(pair.T_W_B_gt.q.angularDistance(copied[i].T_W_B_gt.q), 1e-15);
      EXPECT_EQ(pair.T_W_B_gt.p, copied[i].T_W_B_gt.p);
    } else {
      ExpectSameBits(pair.T_W_B_gt, copied[i].T_W_B_gt);
    }
  }
  EXPECT_GT(exact, 0u);                // stamps on a truth sample: taken as they are
  EXPECT_LT(exact, pairs.size() / 2);  // the others interpolated
}

TEST(PairedPoses, NearestPairsTakeTheTruthSampleAndTheOffset) {
  std::vector<StampedPose> truth, estimate;
  Trajectories(&truth, &estimate);
  const PairedPoses pairs =
      AssociatePairs(estimate, truth, {AssociationMode::kNearest, 0.004, 0.002});
  ASSERT_GT(pairs.size(), 100u);
  for (size_t i = 0; i < pairs.size(); ++i) {
    const PosePair pair = pairs[i];
    const StampedPose& est = estimate[pairs.estimate_index(i)];
    EXPECT_EQ(pair.t_ns, est.t_ns + 2'000'000);
    ExpectSameBits(pair.T_W_B_gt, truth[pairs.truth_index(i)].T_W_B);
    EXPECT_LE(std::llabs(truth[pairs.truth_index(i)].t_ns - pair.t_ns), 4'000'000);
  }
}

TEST(PairedPoses, AlignmentMapsTheEstimateAsApplySimilarity) {
  std::vector<StampedPose> truth, estimate;
  Trajectories(&truth, &estimate);
  Similarity S;
  S.scale = 1.3;
  S.R = Rz(0.4) * Rx(-0.1);
  S.t = Eigen::Vector3d(1.0, -2.0, 0.5);
  PairedPoses indexed = AssociatePairs(estimate, truth, {AssociationMode::kInterpolate, 0.01, 0.0});
  PairedPoses whole(AssociatePoses(estimate, truth, 0.01));
  indexed.SetAlignment(S);
  whole.SetAlignment(S);
  ASSERT_EQ(indexed.size(), whole.size());
  for (size_t i = 0; i < indexed.size(); ++i) {
    const Pose expected = ApplySimilarity(S, estimate[indexed.estimate_index(i)].T_W_B);
    ExpectSameBits(indexed[i].T_W_B_est, expected);
    ExpectSameBits(whole[i].T_W_B_est, expected);
    EXPECT_EQ(indexed[i].T_W_B_gt.p, whole[i].T_W_B_gt.p);
  }
  size_t visited = 0;
  for (const PosePair pair : indexed) visited += pair.t_ns == indexed.t_ns(visited);
  EXPECT_EQ(visited, indexed.size());
}

TEST(PairedPoses, NothingToPair) {
  std::vector<StampedPose> truth, estimate;
  Trajectories(&truth, &estimate);
  EXPECT_TRUE(AssociatePairs({}, truth, {}).empty());
  EXPECT_TRUE(AssociatePairs(estimate, {}, {}).empty());
  // The estimate shifted past the truth's end.
  EXPECT_TRUE(
      AssociatePairs(estimate, truth, {AssociationMode::kInterpolate, 0.01, 100.0}).empty());
}

}  // namespace
}  // namespace mavloc
