// Comparing without ground truth: against a reference estimate (evaluation/reference.h) and by the
// reprojection of tag corners (evaluation/reprojection.h), on the tag arena with fixed seeds.
#include <gtest/gtest.h>

#include <cmath>

#include "core/board_frame.h"
#include "core/rotation.h"
#include "datasets/scenarios/scenario.h"
#include "evaluation/association.h"
#include "evaluation/comparison.h"
#include "evaluation/reference.h"
#include "evaluation/reprojection.h"

namespace mavloc {
namespace {

Dataset TagArena(double corner_noise_px, uint64_t seed) {
  ScenarioOptions options;
  options.seed = seed;
  options.duration_s = 8.0;
  options.settings = {{"corner_noise_px", std::to_string(corner_noise_px)}};
  return FindScenario("tag-arena-dynamic")->generate(options);
}

Estimate TruthAsEstimate(const Dataset& dataset) {
  Estimate estimate;
  estimate.poses = GroundTruthPoses(dataset);
  estimate.quantities = MakeQuantityTable(PoseQuantityNames(false));
  for (const auto& p : estimate.poses)
    estimate.quantities.Append(p.t_ns, PoseQuantityValues(p.T_W_B));
  return estimate;
}

TEST(TagReprojection, TruePosesReprojectWithThePixelNoise) {
  // Corner noise sigma per axis: the RMS of the 2-D error norm is sigma * sqrt(2).
  const double sigma = 0.5;
  const Dataset dataset = TagArena(sigma, 11);
  const auto stats = ComputeTagReprojection(dataset, TruthAsEstimate(dataset));
  ASSERT_EQ(stats.size(), 1u);
  EXPECT_EQ(stats[0].camera, "cam0");
  EXPECT_GT(stats[0].corners, 400);
  EXPECT_EQ(stats[0].unmatched, 0);
  EXPECT_NEAR(stats[0].rms_px, sigma * std::sqrt(2.0), 0.05);
}

TEST(TagReprojection, NoiselessCornersReprojectExactlyAndAPoseErrorShows) {
  const Dataset dataset = TagArena(0.0, 12);
  Estimate estimate = TruthAsEstimate(dataset);
  const auto exact = ComputeTagReprojection(dataset, estimate);
  ASSERT_EQ(exact.size(), 1u);
  EXPECT_LT(exact[0].max_px, 1e-3);
  for (auto& p : estimate.poses) p.T_W_B.p.x() += 0.02;  // 2 cm off
  const auto off = ComputeTagReprojection(dataset, estimate);
  EXPECT_GT(off[0].rms_px, 3.0);
}

TEST(TagReprojection, BoardMapUsesTheEstimatesMapToWorldTransform) {
  // The same data with the map expressed in a tilted board frame M: reprojecting through the
  // estimate's T_W_M gives the same statistics; without it (identity) it does not.
  const Dataset world = TagArena(0.0, 13);
  Dataset board = world;
  const Eigen::Vector3d up_M = Eigen::Vector3d(0.3, -0.9, 0.2).normalized();
  const Pose T_W_M = BoardToWorld(up_M);
  board.map.frame = MapFrame::kBoard;
  for (auto& [id, tag] : board.map.tags) tag.T_W_T = T_W_M.Inverse() * tag.T_W_T;
  Estimate estimate = TruthAsEstimate(world);
  estimate.T_W_M = T_W_M;
  const auto stats = ComputeTagReprojection(board, estimate);
  ASSERT_EQ(stats.size(), 1u);
  EXPECT_LT(stats[0].max_px, 1e-3);
  estimate.T_W_M.reset();
  const auto wrong = ComputeTagReprojection(board, estimate);
  ASSERT_EQ(wrong.size(), 1u);
  EXPECT_TRUE(wrong[0].corners == 0 || wrong[0].rms_px > 10.0) << wrong[0].rms_px;
}

TEST(ReferenceComparison, DifferencesToAReferenceEstimator) {
  Dataset dataset = TagArena(0.3, 14);
  const auto truth_reference = ReferenceFromEstimate("truth-copy", TruthAsEstimate(dataset));
  dataset.ground_truth.clear();  // a log without ground truth
  EvaluationOptions options;
  options.reference = &truth_reference;
  const auto e = RunAndEvaluate("tag-pnp", {}, dataset, options);
  ASSERT_TRUE(e.ran);
  ASSERT_TRUE(e.ate.has_value());
  EXPECT_FALSE(e.is_reference);
  // Against a reference that happens to be the truth, the differences are tag-pnp's errors:
  // millimetres to centimetres, not zero.
  EXPECT_GT(e.ate->translation_m.rmse, 1e-4);
  EXPECT_LT(e.ate->translation_m.rmse, 0.05);
  ASSERT_FALSE(e.reprojection.empty());
  EXPECT_LT(e.reprojection[0].rms_px, 1.0);

  // The reference estimator itself is flagged, not compared with itself.
  const auto self = ReferenceFromEstimate("tag-pnp", e.estimate);
  options.reference = &self;
  const auto again = EvaluateEstimate("tag-pnp", e.estimate, dataset, options);
  EXPECT_TRUE(again.is_reference);
  EXPECT_TRUE(again.quantity_errors.empty());
  EXPECT_TRUE(EvaluationToJson(again)["reference"].get<bool>());
}

TEST(ReferenceComparison, TrajectoryFileReferenceCarriesVelocityOnlyWhenGiven) {
  std::vector<GroundTruthState> states(3);
  for (int i = 0; i < 3; ++i) states[i].t_ns = i * 100'000'000;
  EXPECT_FALSE(ReferenceFromTrajectory("f.txt", states).quantities.Has("vx"));
  states[1].v_W = Eigen::Vector3d(1, 0, 0);
  const auto r = ReferenceFromTrajectory("f.csv", states);
  EXPECT_TRUE(r.quantities.Has("vx"));
  EXPECT_EQ(r.poses.size(), 3u);
  EXPECT_NE(r.Describe().find("trajectory file"), std::string::npos);
}

}  // namespace
}  // namespace mavloc
