// End to end for the AprilTag paper: rendered arena images through the real detector match the
// true corners to sub-pixel accuracy (the detector's accuracy check; it lives here because it
// needs both mavloc_datasets (renderer) and mavloc_frontends (detector)); per-tag IPPE poses; the
// estimators on the arena; a small `mavloc repro apriltag` run.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "core/rotation.h"
#include "core/tag_geometry.h"
#include "datasets/rendering/tag_renderer.h"
#include "datasets/scenarios/tag_arena.h"
#include "evaluation/comparison.h"
#include "frontends/apriltag/detect_tags.h"
#include "frontends/apriltag/tag_pose.h"
#include "tests/test_support.h"

namespace mavloc {
namespace {

struct RenderedFrame {
  Pose T_W_C;
  cv::Mat image;
};

// Poses over the arena: level and tilted, various heights and yaws.
std::vector<Pose> TestCameraPoses() {
  const CameraSensor cam = TagArenaCamera(10.0);
  std::vector<Pose> poses;
  const double params[][5] = {// x, y, z, yaw, tilt
                              {0.35, 0.35, 1.0, 0.3, 0.0},
                              {-0.7, 0.1, 0.8, 1.2, 0.08},
                              {1.0, -0.3, 1.3, -2.0, 0.15},
                              {0.0, 0.0, 0.6, 0.7, 0.05}};
  for (const auto& p : params) {
    const Pose T_W_B(Eigen::Matrix3d(Rz(p[3]) * Ry(p[4])), Eigen::Vector3d(p[0], p[1], p[2]));
    poses.push_back(T_W_B * cam.T_B_C);
  }
  return poses;
}

TEST(AprilTagRenderDetect, NoiselessRenderedCornersMatchTheTruthToSubPixel) {
  const CameraSensor cam = TagArenaCamera(10.0);
  const auto tags = TagArenaTags();
  TagRenderOptions render_options;
  render_options.noise_sigma_grey = 0.0;
  const TagRenderer renderer(cam.model, tags, render_options);
  RectifiedTagDetector detector(TagDetectorOptions{}, cam.model);
  int detections = 0, expected = 0;
  double worst = 0.0, sum = 0.0;
  for (const Pose& T_W_C : TestCameraPoses()) {
    const cv::Mat image = renderer.Render({T_W_C}, 1);
    const auto found = detector.Detect(image);
    const Pose T_C_W = T_W_C.Inverse();
    // Every tag whose page is well inside the image must be found.
    for (const auto& [id, tag] : tags) {
      TagInfo page = tag;
      page.size_m *= 12.0 / 8.0;
      bool inside = true;
      for (const auto& c : TagCornersInWorld(page)) {
        const auto uv = cam.model.Project(T_C_W * c);
        inside = inside && uv && cam.model.IsInside(*uv, 3.0);
      }
      if (!inside) continue;
      ++expected;
      const auto it = std::find_if(found.begin(), found.end(),
                                   [tag_id = id](const TagDetection& d) { return d.id == tag_id; });
      ASSERT_NE(it, found.end()) << "tag " << id << " not detected";
    }
    for (const auto& det : found) {
      ASSERT_TRUE(tags.count(det.id)) << "false detection id " << det.id;
      const auto corners_W = TagCornersInWorld(tags.at(det.id));
      for (int k = 0; k < 4; ++k) {
        const Eigen::Vector2d truth = *cam.model.Project(T_C_W * corners_W[k]);
        const double error = (det.corners_px[k] - truth).norm();
        EXPECT_LT(error, 0.3) << "tag " << det.id << " corner " << k;
        worst = std::max(worst, error);
        sum += error;
      }
      ++detections;
    }
  }
  EXPECT_GE(expected, 8);
  EXPECT_GE(detections, expected);
  // Sub-pixel: measured mean 0.06 px, worst 0.14 px (rectified, refine_edges on).
  EXPECT_LT(sum / (4 * detections), 0.1);
  std::printf("noiseless renders: %d detections, mean corner error %.3f px, worst %.3f px\n",
              detections, sum / (4 * detections), worst);
}

TEST(AprilTagRenderDetect, PerTagIppePoseFromRenderedCorners) {
  const CameraSensor cam = TagArenaCamera(10.0);
  const auto tags = TagArenaTags();
  const TagRenderer renderer(cam.model, tags);
  RectifiedTagDetector detector(TagDetectorOptions{}, cam.model);
  const Pose T_W_C = TestCameraPoses()[0];
  const auto found = detector.Detect(renderer.Render({T_W_C}, 3));
  ASSERT_GE(found.size(), 2u);
  for (const auto& det : found) {
    const TagPoseResult pose = EstimateTagPose(det.corners_px, 0.20, cam.model);
    ASSERT_TRUE(pose.ok) << pose.reason;
    const Pose T_C_T = T_W_C.Inverse() * tags.at(det.id).T_W_T;
    EXPECT_LT((pose.T_C_T.p - T_C_T.p).norm(), 0.01);  // 1 cm at 1 m (Table I: sR = 1 cm^2)
    EXPECT_LT(RotationAngleBetween(pose.T_C_T.q, T_C_T.q), 0.05);
    EXPECT_LT(pose.rms_reprojection_px, 1.0);
  }
  // A degenerate input fails with a reason instead of throwing.
  std::array<Eigen::Vector2d, 4> collapsed;
  collapsed.fill(Eigen::Vector2d(300, 200));
  const TagPoseResult bad = EstimateTagPose(collapsed, 0.2, cam.model);
  EXPECT_FALSE(bad.ok && bad.rms_reprojection_px < 1.0);
  EXPECT_FALSE(EstimateTagPose(found[0].corners_px, 0.0, cam.model).ok);
}

// tag-ekf and tag-pnp on projected tags (the path without images): the EKF beats the vision-only
// poses and the dead-reckoning-only ("no tags") run drifts.
TEST(AprilTagEstimators, EkfOnTheDynamicArenaWithAndWithoutTags) {
  ScenarioOptions scenario;
  scenario.duration_s = 20.0;
  const Dataset dataset = GenerateTagArenaDynamic(scenario);
  EvaluationOptions evaluation;
  const auto with_tags = RunAndEvaluate("tag-ekf", EstimatorOptions{}, dataset, evaluation);
  EstimatorOptions no_tags_options;
  no_tags_options.Set("use_tags", "0");
  const auto no_tags = RunAndEvaluate("tag-ekf", no_tags_options, dataset, evaluation);
  const auto pnp = RunAndEvaluate("tag-pnp", EstimatorOptions{}, dataset, evaluation);
  ASSERT_TRUE(with_tags.ran && no_tags.ran && pnp.ran);
  auto max_abs = [](const EstimatorEvaluation& e, const std::string& q, double after_s, TimeNs t0) {
    double worst = 0.0;
    for (const auto& series : e.quantity_errors) {
      if (series.name != q) continue;
      for (size_t i = 0; i < series.t_ns.size(); ++i)
        if (NsToSeconds(series.t_ns[i] - t0) > after_s)
          worst = std::max(worst, std::abs(series.error[i]));
    }
    return worst;
  };
  const TimeNs t0 = dataset.ground_truth.front().t_ns;
  // After the take-off transient: centimetre-level position, no drift.
  for (const char* q : {"x", "y", "z"}) {
    EXPECT_LT(max_abs(with_tags, q, 6.0, t0), 0.06) << q;
    EXPECT_GT(max_abs(no_tags, q, 6.0, t0), 3.0 * max_abs(with_tags, q, 6.0, t0)) << q;
  }
  EXPECT_LT(max_abs(with_tags, "roll", 6.0, t0), 0.03);
  EXPECT_LT(max_abs(with_tags, "pitch", 6.0, t0), 0.03);
  EXPECT_FALSE(with_tags.estimate.covariances.empty());
  // The vision-only baseline: centimetre-level too (noise 0.3 px), but no velocity and no output
  // between frames.
  EXPECT_LT(max_abs(pnp, "x", 6.0, t0), 0.05);
  EXPECT_LT(max_abs(pnp, "z", 6.0, t0), 0.05);
  EXPECT_GT(pnp.estimate.poses.size(), 150u);  // a pose for most of the 200 frames
}

// The command-line chain: simulate --render -> detect-tags --dataset -> run tag-ekf, and
// detect-tags --images on the reference photos.
TEST(AprilTagCli, SimulateRenderDetectRun) {
  const std::string dir = testing::MakeTempDir();
  const std::string cli = testing::CliPath();
  auto r = testing::RunCommand(
      cli + " simulate --scenario tag-arena-hover --duration 2 --render --out " + dir +
      "/ds --set image_dir=" + dir + "/render --set supersampling=1");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = testing::RunCommand(cli + " detect-tags --dataset " + dir + "/ds");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::ifstream tags0(dir + "/ds/mav0/tags0/data.csv");
  int rows = 0;
  for (std::string line; std::getline(tags0, line);) rows += (!line.empty() && line[0] != '#');
  EXPECT_GE(rows, 21 * 2);  // 21 frames, at least 2 tags each
  EXPECT_TRUE(std::filesystem::exists(dir + "/ds/mav0/tags0/poses.csv"));
  r = testing::RunCommand(cli + " run --dataset " + dir + "/ds --estimator tag-ekf --out " + dir +
                          "/ekf.txt");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(std::filesystem::exists(dir + "/ekf.txt"));
  // Bad input: one line, exit code 2.
  r = testing::RunCommand(cli + " detect-tags --images " + dir + "/nothing --out " + dir +
                          "/x.csv");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  r = testing::RunCommand(cli + " detect-tags --dataset " + dir + "/ds --family tag99h99");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  if (!testing::HasSharedData()) GTEST_SKIP() << "shared data absent: " << testing::SharedDataDir();
  r = testing::RunCommand(cli + " detect-tags --images " + testing::SharedDataDir() +
                          "/apriltag_reference --decimate 1 --refine-edges 0 --out " + dir +
                          "/photos.csv");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::ifstream photos(dir + "/photos.csv");
  rows = 0;
  for (std::string line; std::getline(photos, line);) rows += (!line.empty() && line[0] != '#');
  EXPECT_EQ(rows, 47);
}

TEST(AprilTagRepro, SmallRunWritesEveryTable) {
  const std::string dir = testing::MakeTempDir();
  const auto result = testing::RunCommand(
      testing::CliPath() + " repro apriltag --runs 2 --report " + dir +
      " --set hover_duration_s=3 --set dynamic_duration_s=8 --set supersampling=1 "
      "--set decimate=2");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  std::ifstream in(dir + "/report.json");
  ASSERT_TRUE(in.good());
  const nlohmann::json report = nlohmann::json::parse(in)["details"];  // the repro's own layout
  for (const char* table : {"hover", "dynamic", "nees", "images"})
    EXPECT_TRUE(report["tables"].contains(table)) << table;
  EXPECT_EQ(report["tables"]["hover"]["runs"].get<int>(), 2);
  EXPECT_GT(report["tables"]["images"]["detections"].get<int>(), 0);
  EXPECT_TRUE(std::filesystem::exists(dir + "/report.md"));
}

}  // namespace
}  // namespace mavloc
