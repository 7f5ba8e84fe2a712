// Rendered Kalibr aprilgrids (datasets/rendering/aprilgrid_renderer.h) through the aprilgrid
// detector (frontends/apriltag, family "aprilgrid"): with the EuRoC cam0 model (radial-tangential
// distortion) and several board poses, every tag whose corners are in the image is found with its
// true id, and the corners lie within 0.1 px (mean) of the true projections of
// AprilgridCorner(tag_id, k): render -> detect agree on ids, corner order and pixel convention.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "core/aprilgrid.h"
#include "core/image_codec.h"
#include "core/rotation.h"
#include "datasets/io/euroc_io.h"
#include "datasets/rendering/aprilgrid_renderer.h"
#include "datasets/scenarios/scenario.h"
#include "frontends/apriltag/tag_detector.h"
#include "tests/test_support.h"

namespace mavloc {
namespace {

AprilgridTarget EurocTarget() { return AprilgridTarget{6, 6, 0.088, 0.3}; }

// The board seen from the camera: R_C_M = R_view * Rx(pi) (z_M towards the camera, y_M up in the
// image when R_view = I), with the board point p_M_look at p_C_look.
Pose BoardInCamera(const Eigen::Matrix3d& R_view, const Eigen::Vector3d& p_M_look,
                   const Eigen::Vector3d& p_C_look) {
  const Eigen::Matrix3d R_C_M = R_view * Rx(M_PI);
  return Pose(R_C_M, p_C_look - R_C_M * p_M_look);
}

struct Case {
  const char* name;
  Pose T_C_M;
};

std::vector<Case> Cases() {
  const AprilgridTarget target = EurocTarget();
  const double half = 0.5 * (target.tag_cols * target.PitchM() - target.tag_spacing * 0.088);
  const Eigen::Vector3d centre_M(half, half, 0.0);
  return {
      {"fronto-parallel 1.2 m", BoardInCamera(Eigen::Matrix3d::Identity(), centre_M, {0, 0, 1.2})},
      {"tilted 35 deg about x, 1.0 m",
       BoardInCamera(Rx(0.6) * Rz(0.1), centre_M, {0.05, -0.03, 1.0})},
      {"rolled 40 deg, tilted about y, 0.9 m",
       BoardInCamera(Ry(-0.5) * Rz(0.7), centre_M, {-0.08, 0.04, 0.9})},
      {"far 1.6 m (tags of 22 px)", BoardInCamera(Rx(0.2), centre_M, {0.0, 0.0, 1.6})},
      {"1.1 m near the image corner (strong distortion)",
       BoardInCamera(Rx(-0.2) * Ry(0.3), centre_M, {-0.43, -0.24, 1.1})},
      {"close 0.55 m, partly outside the image",
       BoardInCamera(Rx(0.25) * Ry(-0.2) * Rz(-0.3), centre_M, {0.1, 0.05, 0.55})},
  };
}

TEST(AprilgridRenderDetect, AllVisibleTagsFoundWithSubTenthPixelCorners) {
  const CameraModel camera = EurocCam0Model();
  const AprilgridTarget target = EurocTarget();
  TagRenderOptions render;
  render.noise_sigma_grey = 1.0;  // low noise
  // 8 x 8 samples on edge pixels: with the default 4 x 4, an axis-aligned edge's coverage is
  // quantized to quarters of a pixel, i.e. the rendered edge itself is off by up to 0.125 px.
  render.supersampling = 8;
  TagDetectorOptions options;
  options.family = "aprilgrid";
  TagDetector detector(options);
  TagDetectorOptions unrefined_options = options;
  unrefined_options.aprilgrid.refine_corners = false;
  TagDetector unrefined(unrefined_options);

  double sum = 0.0, worst = 0.0, sum_unrefined = 0.0;
  int corners = 0, corners_unrefined = 0, seed = 1;
  for (const auto& c : Cases()) {
    const cv::Mat image = RenderAprilgrid(camera, target, c.T_C_M, render, seed++);
    // The true projections, and the tags fully inside the image (with its 12-cell bitmap, and a
    // margin for the corner windows).
    std::map<int, std::array<Eigen::Vector2d, 4>> truth;
    int visible = 0;
    for (int id = 0; id < target.NumTags(); ++id) {
      std::array<Eigen::Vector2d, 4> uv;
      bool inside = true;
      for (int k = 0; k < 4; ++k) {
        const auto p = camera.Project(c.T_C_M * AprilgridCorner(target, id, k));
        ASSERT_TRUE(p.has_value());
        uv[k] = *p;
        // The corner of the white ring (one cell outside the black square) must be visible too.
        const Eigen::Vector3d outward =
            AprilgridCorner(target, id, k) +
            (AprilgridCorner(target, id, k) - AprilgridCorner(target, id, (k + 2) % 4)) * 0.1;
        const auto q = camera.Project(c.T_C_M * outward);
        inside = inside && camera.IsInside(*p, 8.0) && q && camera.IsInside(*q, 1.0);
      }
      truth[id] = uv;
      if (inside) ++visible;
    }
    const auto detections = detector.Detect(image);
    int found_visible = 0;
    double case_sum = 0.0, case_worst = 0.0;
    std::map<int, int> seen;
    for (const auto& det : detections) {
      ASSERT_TRUE(truth.count(det.id)) << c.name << ": false id " << det.id;
      EXPECT_EQ(++seen[det.id], 1) << c.name << ": id " << det.id << " twice";
      for (int k = 0; k < 4; ++k) {
        const double e = (det.corners_px[k] - truth[det.id][k]).norm();
        EXPECT_LT(e, 0.5) << c.name << " tag " << det.id << " corner " << k;
        case_sum += e;
        case_worst = std::max(case_worst, e);
      }
      bool inside = true;
      for (int k = 0; k < 4; ++k) inside = inside && camera.IsInside(truth[det.id][k], 8.0);
      if (inside) ++found_visible;
    }
    for (const auto& det : unrefined.Detect(image)) {
      for (int k = 0; k < 4; ++k) {
        sum_unrefined += (det.corners_px[k] - truth[det.id][k]).norm();
        ++corners_unrefined;
      }
    }
    EXPECT_GE(static_cast<int>(detections.size()), visible) << c.name;
    EXPECT_GT(visible, 0) << c.name;
    const int n = 4 * static_cast<int>(detections.size());
    std::printf("%-52s visible %2d found %2d (%2d inside), corner error mean %.3f max %.3f px\n",
                c.name, visible, static_cast<int>(detections.size()), found_visible,
                n > 0 ? case_sum / n : 0.0, case_worst);
    sum += case_sum;
    worst = std::max(worst, case_worst);
    corners += n;
  }
  ASSERT_GT(corners, 0);
  const double mean = sum / corners;
  std::printf("all: %d corners, mean %.3f px, max %.3f px (libapriltag corners only: mean %.3f)\n",
              corners, mean, worst, sum_unrefined / std::max(1, corners_unrefined));
  EXPECT_LT(mean, 0.1);
}

// The renderer's aprilgrid bitmaps are the detector family's (frontends/apriltag/aprilgrid_family.h
// pads tag36h11 the same way): 12 x 12 cells, black square of 10, and the border count is 10.
TEST(AprilgridRenderDetect, RendererFamilyMatchesTheDetectorFamily) {
  EXPECT_EQ(TagFamilyBorderCells("aprilgrid"), 10);
  EXPECT_EQ(TagFamilyBorderCells("tag36h11b2"), 10);
  const cv::Mat bitmap = TagFamilyBitmap("aprilgrid", 7);
  ASSERT_EQ(bitmap.rows, 12);
  ASSERT_EQ(bitmap.cols, 12);
  const cv::Mat stock = TagFamilyBitmap("tag36h11", 7);
  for (int r = 0; r < 12; ++r) {
    for (int c = 0; c < 12; ++c) {
      const int ring = std::min({r, c, 11 - r, 11 - c});
      const int expected = ring == 0 ? 255 : ring <= 2 ? 0 : stock.at<uint8_t>(r - 1, c - 1);
      EXPECT_EQ(bitmap.at<uint8_t>(r, c), expected) << r << "," << c;
    }
  }
}

// Rows of a tags CSV: tag ids per timestamp.
std::map<long long, std::set<int>> ReadTagIds(const std::string& path) {
  std::map<long long, std::set<int>> ids;
  std::ifstream in(path);
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') continue;
    long long t = 0;
    int id = 0;
    char comma = 0;
    std::istringstream row(line);
    row >> t >> comma >> id;
    ids[t].insert(id);
  }
  return ids;
}

// `mavloc detect-tags --family aprilgrid`: a dataset with cam0 (the real EuRoC frame, then a
// rendered one) and cam1 (the real frame) -> tags0 and tags1; and one image -> one row per tag.
TEST(AprilgridCli, DetectTagsWritesTags0AndTags1AndReadsOneImage) {
  if (!testing::HasSharedData()) GTEST_SKIP() << "shared data absent: " << testing::SharedDataDir();
  const std::string images = testing::SharedDataDir() + "/euroc_cam_april/images/";
  const std::string real0 = images + "cam0_1403709395937837056.png";
  const std::string real1 = images + "cam1_1403709395937837056.png";
  if (!std::filesystem::exists(real0) || !std::filesystem::exists(real1))
    GTEST_SKIP() << "missing " << images;
  const std::string dir = testing::MakeTempDir();
  const AprilgridTarget target = EurocTarget();
  const TimeNs t0 = 1403709395937837056, t1 = t0 + 50000000;

  Dataset d;
  for (TimeNs t = t0 - 100000000; t <= t1 + 100000000; t += 5000000)
    d.imu.samples.push_back({t, Eigen::Vector3d::Zero(), Eigen::Vector3d(0, 0, 9.81)});
  CameraSensor cam0, cam1;
  cam0.name = "cam0";
  cam0.rate_hz = 20.0;
  cam0.model = EurocCam0Model();
  cam1 = cam0;
  cam1.name = "cam1";
  cam1.model = CameraModel(752, 480, Eigen::Vector4d(457.587, 456.134, 379.999, 255.238),
                           DistortionModel::kRadialTangential,
                           {-0.28368365, 0.07451284, -0.00010473, -3.555907e-05});
  const std::string rendered = dir + "/rendered.png";
  const double half = 0.5 * (target.tag_cols * target.PitchM() - target.tag_spacing * 0.088);
  const Pose T_C_M = BoardInCamera(Rx(0.2), Eigen::Vector3d(half, half, 0), {0.0, 0.0, 1.1});
  testing::WriteFileBytes(rendered, EncodePng(RenderAprilgrid(cam0.model, target, T_C_M)));
  cam0.frames = {{t0, real0}, {t1, rendered}};
  cam1.frames = {{t0, real1}};
  d.cameras = {cam0, cam1};
  d.map.frame = MapFrame::kBoard;
  d.map.tags = AprilgridTags(target);
  WriteEurocDataset(d, dir + "/ds");

  const std::string cli = testing::CliPath();
  auto r = testing::RunCommand(cli + " detect-tags --dataset " + dir +
                               "/ds --family aprilgrid --camera all");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto tags0 = ReadTagIds(dir + "/ds/mav0/tags0/data.csv");
  const auto tags1 = ReadTagIds(dir + "/ds/mav0/tags1/data.csv");
  ASSERT_EQ(tags0.size(), 2u);
  EXPECT_EQ(tags0.at(t0).size(), 36u);
  EXPECT_EQ(tags0.at(t1).size(), 36u);
  ASSERT_EQ(tags1.size(), 1u);
  EXPECT_EQ(tags1.at(t0).size(), 36u);
  EXPECT_TRUE(std::filesystem::exists(dir + "/ds/mav0/tags1/poses.csv"));
  // The dataset reads back with both streams.
  const Dataset back = ReadEurocDataset(dir + "/ds");
  EXPECT_EQ(back.tags.size(), 72u);
  EXPECT_EQ(back.tags1.size(), 36u);

  r = testing::RunCommand(cli + " detect-tags --images " + real1 + " --family tag36h11b2 --out " +
                          dir + "/one.csv");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::ifstream one(dir + "/one.csv");
  int rows = 0;
  for (std::string line; std::getline(one, line);) rows += (!line.empty() && line[0] != '#');
  EXPECT_EQ(rows, 36);
  // The stock family finds none of the aprilgrid's tags (1-bit border).
  r = testing::RunCommand(cli + " detect-tags --images " + real1 + " --out " + dir + "/stock.csv");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("0 detections"), std::string::npos) << r.output;
  // A camera the dataset does not have: one line, exit code 2.
  r = testing::RunCommand(cli + " detect-tags --dataset " + dir + "/ds --camera cam7");
  EXPECT_EQ(r.exit_code, 2) << r.output;
}

}  // namespace
}  // namespace mavloc
