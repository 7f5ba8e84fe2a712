// The AprilTag paper's arena scenarios and the tag renderer: map, rates, the paper's initial state,
// projected tags0, determinism, and rendered pixels that show each tag's bitmap where the true
// homography puts it (the detector's side of the check is tests/evaluation/apriltag_repro_test.cc).
#include "datasets/scenarios/tag_arena.h"
#include "core/image_codec.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "core/random.h"
#include "core/rotation.h"
#include "core/tag_geometry.h"
#include "datasets/io/euroc_io.h"
#include "datasets/rendering/tag_renderer.h"
#include "tests/test_support.h"

namespace mavloc {
namespace {

TEST(TagArena, MapRatesAndThePapersInitialState) {
  ScenarioOptions options;
  options.duration_s = 12.0;
  const Dataset d = GenerateTagArenaDynamic(options);
  ASSERT_EQ(d.map.tags.size(), 21u);
  for (const auto& [id, tag] : d.map.tags) {
    EXPECT_DOUBLE_EQ(tag.size_m, 0.20);
    EXPECT_NEAR(tag.T_W_T.p.z(), 0.0, 1e-12);
  }
  EXPECT_NEAR(d.imu.rate_hz, 100.0, 1e-9);
  ASSERT_EQ(d.cameras.size(), 1u);
  EXPECT_NEAR(d.cameras[0].rate_hz, 10.0, 1e-9);
  EXPECT_EQ(d.imu.samples[1].t_ns - d.imu.samples[0].t_ns, 10'000'000);
  EXPECT_EQ(d.cameras[0].frames[1].t_ns - d.cameras[0].frames[0].t_ns, 100'000'000);
  // x0 = [0 0 0.08 0_{1x12}]: at rest on the ground, level, zero biases.
  const GroundTruthState& gt0 = d.ground_truth.front();
  EXPECT_LT((gt0.T_W_B.p - Eigen::Vector3d(0, 0, 0.08)).norm(), 1e-9);
  EXPECT_LT(gt0.v_W.norm(), 1e-9);
  EXPECT_LT(RotationAngleBetween(gt0.T_W_B.q, Eigen::Quaterniond::Identity()), 1e-9);
  EXPECT_LT(gt0.b_a.norm() + gt0.b_g.norm(), 1e-12);
  EXPECT_EQ(d.scenario_info.at("processing_delay_s"), "0.05");
  EXPECT_EQ(d.scenario_info.at("filter_init"), "zero");
  // Fast turns: the yaw rate exceeds 1 rad/s somewhere; the speed stays near 1.1 m/s.
  double max_yaw_rate = 0.0, max_speed = 0.0;
  for (const auto& gt : d.ground_truth) max_speed = std::max(max_speed, gt.v_W.norm());
  for (size_t i = 1; i < d.ground_truth.size(); ++i) {
    const double dyaw = WrapAngle(EulerFromQuaternion(d.ground_truth[i].T_W_B.q).yaw -
                                  EulerFromQuaternion(d.ground_truth[i - 1].T_W_B.q).yaw);
    max_yaw_rate = std::max(max_yaw_rate, std::abs(dyaw) / 0.01);
  }
  EXPECT_GT(max_yaw_rate, 1.0);
  EXPECT_GT(max_speed, 0.8);
  EXPECT_LT(max_speed, 2.0);
}

TEST(TagArena, ProjectedTagsAreTheTrueCornersPlusNoiseAndAppearAfterTakeOff) {
  ScenarioOptions options;
  options.duration_s = 10.0;
  options.settings["corner_noise_px"] = "0";
  const Dataset d = GenerateTagArenaDynamic(options);
  ASSERT_FALSE(d.tags.empty());
  const CameraSensor& cam = d.cameras[0];
  const TimeNs t0 = d.ground_truth.front().t_ns;
  for (const auto& obs : d.tags) {
    // Before take-off (camera 5 cm above the floor) no whole tag page fits in the image.
    EXPECT_GT(obs.t_ns - t0, kNsPerSecond);
    const size_t i = static_cast<size_t>((obs.t_ns - t0) / 10'000'000);
    ASSERT_EQ(d.ground_truth[i].t_ns, obs.t_ns);
    const Pose T_C_W = (d.ground_truth[i].T_W_B * cam.T_B_C).Inverse();
    const auto corners_W = TagCornersInWorld(d.map.tags.at(obs.tag_id));
    for (int k = 0; k < 4; ++k) {
      const auto uv = cam.model.Project(T_C_W * corners_W[k]);
      ASSERT_TRUE(uv.has_value());
      EXPECT_LT((*uv - obs.corners_px[k]).norm(), 1e-9);
      EXPECT_TRUE(cam.model.IsInside(obs.corners_px[k]));
    }
  }
  // Several tags per frame once airborne.
  EXPECT_GT(static_cast<double>(d.tags.size()) / cam.frames.size(), 1.5);
}

TEST(TagArena, SameSeedSameDataDifferentSeedDifferentNoise) {
  ScenarioOptions options;
  options.duration_s = 3.0;
  const Dataset a = GenerateTagArenaHover(options);
  const Dataset b = GenerateTagArenaHover(options);
  options.seed = 2;
  const Dataset c = GenerateTagArenaHover(options);
  ASSERT_EQ(a.tags.size(), b.tags.size());
  ASSERT_FALSE(a.tags.empty());
  for (size_t i = 0; i < a.tags.size(); ++i)
    EXPECT_EQ(a.tags[i].corners_px[2], b.tags[i].corners_px[2]);
  EXPECT_NE(a.tags[0].corners_px[0], c.tags[0].corners_px[0]);
  EXPECT_EQ(a.imu.samples[5].accel_m_s2, b.imu.samples[5].accel_m_s2);
  // The hover is stationary.
  EXPECT_LT((a.ground_truth.front().T_W_B.p - a.ground_truth.back().T_W_B.p).norm(), 1e-9);
}

TEST(TagArena, BadSettingsAreInputErrors) {
  ScenarioOptions options;
  options.settings["processing_delay_s"] = "-1";
  EXPECT_ANY_THROW(GenerateTagArenaHover(options));
  options.settings["processing_delay_s"] = "abc";
  EXPECT_ANY_THROW(GenerateTagArenaHover(options));
}

// Every cell of every tag the camera sees fully shows the bitmap's value at the pixel where the
// cell centre projects: this pins the bitmap orientation (row 0 at the tag's +y edge) and the
// homography, through the distortion.
TEST(TagRenderer, CellsAppearWhereTheCameraModelProjectsThem) {
  const auto tags = TagArenaTags();
  const CameraSensor cam = TagArenaCamera(10.0);
  TagRenderOptions render_options;
  const TagRenderer renderer(cam.model, tags, render_options);
  const Pose T_W_B(Eigen::Matrix3d(Rz(0.4) * Rx(0.05)), Eigen::Vector3d(0.35, 0.35, 1.1));
  const Pose T_W_C = T_W_B * cam.T_B_C;
  const cv::Mat image = renderer.RenderIdeal(T_W_C);
  const Pose T_C_W = T_W_C.Inverse();
  int tags_checked = 0, cells_checked = 0;
  for (const auto& [id, tag] : tags) {
    const cv::Mat bitmap = TagFamilyBitmap("tag36h11", id);
    const double cell = tag.size_m / 8.0;
    bool inside = true;
    for (const auto& c : TagCornersInWorld(tag)) {
      const auto uv = cam.model.Project(T_C_W * c);
      inside = inside && uv && cam.model.IsInside(*uv, 20.0);
    }
    if (!inside) continue;
    ++tags_checked;
    for (int r = 0; r < 10; ++r) {
      for (int col = 0; col < 10; ++col) {
        const Eigen::Vector3d p_T((col + 0.5 - 5.0) * cell, (5.0 - r - 0.5) * cell, 0.0);
        const auto uv = cam.model.Project(T_C_W * (tag.T_W_T * p_T));
        ASSERT_TRUE(uv.has_value());
        const float grey = image.at<float>(static_cast<int>(std::lround(uv->y())),
                                           static_cast<int>(std::lround(uv->x())));
        const double expected =
            bitmap.at<uint8_t>(r, col) < 128 ? render_options.ink_grey : render_options.paper_grey;
        EXPECT_NEAR(grey, expected, 1e-6) << "tag " << id << " cell " << r << "," << col;
        ++cells_checked;
      }
    }
  }
  EXPECT_GE(tags_checked, 3);
  EXPECT_EQ(cells_checked, tags_checked * 100);
}

TEST(TagRenderer, EdgesAreAreaAveragedAndNoiseAndBlurChangeTheImage) {
  const auto tags = TagArenaTags();
  const CameraSensor cam = TagArenaCamera(10.0);
  TagRenderOptions render_options;
  render_options.noise_sigma_grey = 0.0;
  const TagRenderer renderer(cam.model, tags, render_options);
  const Pose T_W_C = Pose(Eigen::Matrix3d(Rz(0.2)), Eigen::Vector3d(0.0, 0.0, 1.0)) * cam.T_B_C;
  const cv::Mat ideal = renderer.RenderIdeal(T_W_C);
  // Anti-aliasing: some pixels lie strictly between ink and paper.
  int mixed = 0;
  for (int v = 0; v < ideal.rows; ++v)
    for (int u = 0; u < ideal.cols; ++u) {
      const float g = ideal.at<float>(v, u);
      if (g > render_options.ink_grey + 0.05 && g < render_options.paper_grey - 0.05) ++mixed;
    }
  EXPECT_GT(mixed, 100);
  const cv::Mat a = renderer.Render({T_W_C}, 1);
  const cv::Mat b = renderer.Render({T_W_C}, 1);
  EXPECT_EQ(cv::norm(a, b, cv::NORM_INF), 0.0);  // deterministic
  TagRenderOptions noisy_options;
  const TagRenderer noisy(cam.model, tags, noisy_options);
  const cv::Mat n1 = noisy.Render({T_W_C}, 1), n2 = noisy.Render({T_W_C}, 2);
  EXPECT_GT(cv::norm(n1, n2, cv::NORM_L1) / (n1.rows * n1.cols), 1.0);
  std::vector<Pose> exposure;
  for (int k = 0; k < 5; ++k)
    exposure.push_back(Pose(Eigen::Quaterniond::Identity(), Eigen::Vector3d(0.004 * k, 0, 0)) *
                       T_W_C);
  const cv::Mat blurred = renderer.Render(exposure, 1);
  EXPECT_GT(cv::norm(a, blurred, cv::NORM_L1) / (a.rows * a.cols), 0.5);
}

TEST(TagArena, RenderedImagesAreWrittenAsCam0) {
  ScenarioOptions options;
  options.duration_s = 1.0;
  options.render_images = true;
  const std::string dir = testing::MakeTempDir();
  options.settings["image_dir"] = dir + "/render";
  options.settings["supersampling"] = "2";
  const Dataset d = GenerateTagArenaHover(options);
  EXPECT_TRUE(d.tags.empty());  // tags0 comes from the detector on rendered data
  ASSERT_EQ(d.cameras[0].frames.size(), 11u);
  WriteEurocDataset(d, dir + "/dataset");
  const Dataset back = ReadEurocDataset(dir + "/dataset");
  ASSERT_EQ(back.cameras.size(), 1u);
  EXPECT_TRUE(back.cameras[0].missing_images.empty());
  ASSERT_EQ(back.cameras[0].frames.size(), 11u);
  std::string why;
  const cv::Mat image = DecodeImage(testing::ReadFileBytes(back.cameras[0].frames[3].image_path),
                                    ImageDecodeMode::kGray8, &why);
  EXPECT_EQ(image.cols, 752);
  EXPECT_EQ(image.rows, 480);
  EXPECT_EQ(back.map.tags.size(), 21u);
}

}  // namespace
}  // namespace mavloc
