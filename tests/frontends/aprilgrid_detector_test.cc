// Aprilgrid detection (frontends/apriltag/aprilgrid_family.h, aprilgrid_detector.h) on the real
// EuRoC stereo pair of a Kalibr aprilgrid (../shared/data/euroc_cam_april/images, 752x480): every
// tag found, and corners good enough that a PnP against the board geometry (core/aprilgrid.h) with
// EuRoC's calibration reprojects them to well under half a pixel, which also pins down that the
// detector's (tag_id, corner k) and Kalibr's (tag_id, corner_idx) name the same board points.
// Rendered grids (known corners) are checked in tests/evaluation/aprilgrid_render_detect_test.cc
// (the renderer is in mavloc_datasets, which this suite does not link).
#include <apriltag/apriltag.h>
#include <apriltag/tag36h11.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>
#include <set>
#include <sstream>

#include "core/aprilgrid.h"
#include "frontends/apriltag/aprilgrid_detector.h"
#include "frontends/apriltag/aprilgrid_family.h"
#include "frontends/apriltag/tag_detector.h"
#include "frontends/image_io.h"
#include "tests/test_support.h"

namespace mavloc {
namespace {

constexpr const char* kStamp = "1403709395937837056";

// EuRoC's calibration of cam0 / cam1 (pinhole fu fv cu cv, radial-tangential k1 k2 p1 p2;
// euroc_v1_01_easy/mav0/cam*/sensor.yaml, the same as euroc_cam_april's stereo_config.yaml).
struct EurocCamera {
  double fu, fv, cu, cv;
  double k1, k2, p1, p2;
};
constexpr EurocCamera kEurocCameras[2] = {
    {458.654, 457.296, 367.215, 248.375, -0.28340811, 0.07395907, 0.00019359, 1.76187114e-05},
    {457.587, 456.134, 379.999, 255.238, -0.28368365, 0.07451284, -0.00010473, -3.555907e-05},
};

// Kalibr's target.yaml of euroc_cam_april: 6x6 tags of 0.088 m, spacing 0.3.
AprilgridTarget EurocTarget() { return AprilgridTarget{6, 6, 0.088, 0.3}; }

std::string ImagePath(int camera) {
  return testing::SharedDataDir() + "/euroc_cam_april/images/cam" + std::to_string(camera) + "_" +
         kStamp + ".png";
}

struct PnpFit {
  double rms_px = 0.0;
  double max_px = 0.0;
  cv::Mat rvec, tvec;
};

// Planar PnP (IPPE, then Levenberg-Marquardt on the distorted reprojection error) of the detected
// corners against the board points AprilgridCorner(tag_id, k).
PnpFit FitBoard(const std::vector<TagDetection>& detections, const EurocCamera& cam) {
  const AprilgridTarget target = EurocTarget();
  std::vector<cv::Point3d> p_M;
  std::vector<cv::Point2d> uv;
  for (const auto& det : detections) {
    for (int k = 0; k < 4; ++k) {
      const Eigen::Vector3d p = AprilgridCorner(target, det.id, k);
      p_M.emplace_back(p.x(), p.y(), p.z());
      uv.emplace_back(det.corners_px[k].x(), det.corners_px[k].y());
    }
  }
  const cv::Mat K = (cv::Mat_<double>(3, 3) << cam.fu, 0, cam.cu, 0, cam.fv, cam.cv, 0, 0, 1);
  const cv::Mat D = (cv::Mat_<double>(1, 4) << cam.k1, cam.k2, cam.p1, cam.p2);
  PnpFit fit;
  cv::solvePnP(p_M, uv, K, D, fit.rvec, fit.tvec, false, cv::SOLVEPNP_IPPE);
  cv::solvePnPRefineLM(p_M, uv, K, D, fit.rvec, fit.tvec);
  std::vector<cv::Point2d> projected;
  cv::projectPoints(p_M, fit.rvec, fit.tvec, K, D, projected);
  double sum = 0.0;
  for (size_t i = 0; i < uv.size(); ++i) {
    const double e = cv::norm(projected[i] - uv[i]);
    sum += e * e;
    fit.max_px = std::max(fit.max_px, e);
  }
  fit.rms_px = std::sqrt(sum / static_cast<double>(uv.size()));
  return fit;
}

TagDetectorOptions AprilgridOptions() {
  TagDetectorOptions options;
  options.family = "aprilgrid";
  return options;
}

// ---------------------------------------------------------------------------------------------
// The family.

// The bitmap of tag36h11 id `id` (10x10) and of the aprilgrid family (12x12), 0 black, 255 white.
cv::Mat FamilyBitmap(apriltag_family_t* family, int id) {
  image_u8_t* image = apriltag_to_image(family, id);
  cv::Mat bitmap(image->height, image->width, CV_8UC1);
  for (int r = 0; r < image->height; ++r)
    for (int c = 0; c < image->width; ++c)
      bitmap.at<uint8_t>(r, c) = image->buf[r * image->stride + c];
  std::free(image->buf);  // libapriltag allocates with calloc and exports no destructor
  std::free(image);
  return bitmap;
}

TEST(AprilgridFamily, Tag36h11CodesInsideATwoCellBlackBorder) {
  apriltag_family_t* stock = tag36h11_create();
  apriltag_family_t* grid = AprilgridFamilyCreate();
  EXPECT_EQ(grid->ncodes, 587u);
  EXPECT_EQ(grid->nbits, 36u);
  EXPECT_EQ(grid->h, 11u);
  EXPECT_EQ(grid->width_at_border, 10);
  EXPECT_EQ(grid->total_width, 12);
  EXPECT_STREQ(grid->name, "aprilgrid");
  for (int id = 0; id < static_cast<int>(grid->ncodes); ++id) {
    const cv::Mat small = FamilyBitmap(stock, id);
    const cv::Mat big = FamilyBitmap(grid, id);
    ASSERT_EQ(big.rows, 12);
    // Expected: white ring, two black rings, then tag36h11's 6x6 data (its 10x10 bitmap without
    // its white ring and black ring).
    for (int r = 0; r < 12; ++r) {
      for (int c = 0; c < 12; ++c) {
        const int ring = std::min({r, c, 11 - r, 11 - c});
        const int expected = ring == 0 ? 255 : ring <= 2 ? 0 : small.at<uint8_t>(r - 1, c - 1);
        ASSERT_EQ(big.at<uint8_t>(r, c), expected) << "id " << id << " cell " << r << "," << c;
      }
    }
  }
  AprilgridFamilyDestroy(grid);
  tag36h11_destroy(stock);
}

TEST(AprilgridFamily, SelectableByNameAndAlias) {
  const auto names = SupportedTagFamilies();
  EXPECT_NE(std::find(names.begin(), names.end(), "aprilgrid"), names.end());
  EXPECT_NE(std::find(names.begin(), names.end(), "tag36h11b2"), names.end());
  EXPECT_TRUE(IsAprilgridFamily("aprilgrid"));
  EXPECT_TRUE(IsAprilgridFamily("tag36h11b2"));
  EXPECT_FALSE(IsAprilgridFamily("tag36h11"));
  TagDetectorOptions options;
  options.family = "tag36h11b2";
  EXPECT_NO_THROW(TagDetector{options});
}

// ---------------------------------------------------------------------------------------------
// Undoing the junction separation.

// The 2x2 erosion of a convex polygon moves every edge inwards by max(0, n_x) + max(0, n_y).
TEST(AprilgridDetector, UndoJunctionSeparationInvertsTheErosion) {
  for (const double angle : {0.0, 0.3, -0.7, 1.2, 2.5}) {
    const Eigen::Vector2d centre(40.3, 27.9);
    std::array<Eigen::Vector2d, 4> truth;
    for (int k = 0; k < 4; ++k) {
      const double a = angle + k * M_PI / 2.0;
      // A slightly irregular quad (a projective view of a square).
      truth[k] = centre + (10.0 + 1.5 * k) * Eigen::Vector2d(std::cos(a), std::sin(a));
    }
    // Erode: move each edge inwards by its support value and re-intersect.
    std::array<Eigen::Vector2d, 4> n;
    std::array<double, 4> c;
    for (int k = 0; k < 4; ++k) {
      const Eigen::Vector2d t = truth[(k + 1) % 4] - truth[k];
      n[k] = Eigen::Vector2d(t.y(), -t.x()).normalized();
      if (n[k].dot(truth[k] - centre) < 0.0) n[k] = -n[k];
      c[k] = n[k].dot(truth[k]) - std::max(0.0, n[k].x()) - std::max(0.0, n[k].y());
    }
    std::array<Eigen::Vector2d, 4> eroded;
    for (int k = 0; k < 4; ++k) {
      const int prev = (k + 3) % 4;
      Eigen::Matrix2d A;
      A << n[prev].transpose(), n[k].transpose();
      eroded[k] = A.inverse() * Eigen::Vector2d(c[prev], c[k]);
    }
    const auto restored = UndoJunctionSeparation(eroded);
    for (int k = 0; k < 4; ++k)
      EXPECT_LT((restored[k] - truth[k]).norm(), 1e-9) << "angle " << angle << " corner " << k;
  }
}

// A black axis-aligned rectangle (pixels [10, 29] x [5, 24]) after SeparateDiagonalJunctions
// covers [10, 28] x [5, 23]: its right and bottom sides lose one pixel; and two squares touching at
// a single pixel corner (an X-junction bridge) are no longer 4-connected.
TEST(AprilgridDetector, SeparateDiagonalJunctionsErodesRightAndBottom) {
  cv::Mat image(40, 50, CV_8UC1, cv::Scalar(255));
  image(cv::Rect(10, 5, 20, 20)).setTo(0);
  const cv::Mat out = SeparateDiagonalJunctions(image);
  for (int v = 0; v < 40; ++v)
    for (int u = 0; u < 50; ++u) {
      const bool black = u >= 10 && u <= 28 && v >= 5 && v <= 23;
      ASSERT_EQ(out.at<uint8_t>(v, u), black ? 0 : 255) << u << "," << v;
    }
  // A tag corner and a corner square joined by one black junction pixel at (20, 20).
  cv::Mat junction(40, 40, CV_8UC1, cv::Scalar(255));
  junction(cv::Rect(5, 21, 15, 15)).setTo(0);  // tag, lower left of the junction
  junction(cv::Rect(21, 5, 10, 15)).setTo(0);  // square, upper right
  junction.at<uint8_t>(20, 20) = 0;            // the bridge pixel
  junction.at<uint8_t>(20, 19) = 0;            // 4-connected to the tag below ...
  junction.at<uint8_t>(19, 20) = 0;            // ... and to the square on the right
  cv::Mat labels;
  EXPECT_EQ(cv::connectedComponents(junction == 0, labels, 4), 2);  // background + one blob
  EXPECT_EQ(cv::connectedComponents(SeparateDiagonalJunctions(junction) == 0, labels, 4), 3);
}

// ---------------------------------------------------------------------------------------------
// The real EuRoC pair.

class AprilgridReal : public ::testing::TestWithParam<int> {};

TEST_P(AprilgridReal, AllTagsFoundAndPnpRmsBelowHalfPixel) {
  const int camera = GetParam();
  if (!testing::HasSharedData()) GTEST_SKIP() << "shared data absent: " << testing::SharedDataDir();
  const std::string path = ImagePath(camera);
  if (!std::filesystem::exists(path)) GTEST_SKIP() << "missing " << path;
  const cv::Mat image = LoadGrayImage(path);
  ASSERT_EQ(image.cols, 752);
  ASSERT_EQ(image.rows, 480);

  TagDetector detector(AprilgridOptions());
  const auto detections = detector.Detect(image);
  std::set<int> ids;
  for (const auto& det : detections) {
    EXPECT_GE(det.id, 0);
    EXPECT_LT(det.id, 36) << "false id";
    EXPECT_TRUE(ids.insert(det.id).second) << "id " << det.id << " found twice";
  }
  EXPECT_EQ(ids.size(), 36u) << "cam" << camera;
  EXPECT_EQ(detections.size(), 36u);

  // The tag corners against the board: identity mapping (tag_id, k) -> AprilgridCorner(tag_id, k).
  const PnpFit fit = FitBoard(detections, kEurocCameras[camera]);
  EXPECT_LT(fit.rms_px, 0.5) << "cam" << camera;
  // The board faces the camera (z_M towards it) about 1.2 m away.
  cv::Mat R;
  cv::Rodrigues(fit.rvec, R);
  EXPECT_LT(R.at<double>(2, 2), -0.8);
  EXPECT_NEAR(fit.tvec.at<double>(2), 1.19, 0.05);

  // libapriltag's own corners (junctions separated, no X-junction refinement) for comparison.
  TagDetectorOptions unrefined = AprilgridOptions();
  unrefined.aprilgrid.refine_corners = false;
  TagDetector plain_detector(unrefined);
  const auto plain = plain_detector.Detect(image);
  const PnpFit plain_fit = FitBoard(plain, kEurocCameras[camera]);
  // Without separating the junctions, libapriltag alone loses tags.
  TagDetectorOptions unseparated = AprilgridOptions();
  unseparated.aprilgrid.separate_junctions = false;
  TagDetector unseparated_detector(unseparated);
  const size_t unseparated_found = unseparated_detector.Detect(image).size();
  EXPECT_LT(unseparated_found, 36u);
  std::printf(
      "cam%d: %zu tags; PnP RMS %.3f px (max %.3f), libapriltag corners only: RMS %.3f px (max "
      "%.3f); without junction separation %zu tags\n",
      camera, detections.size(), fit.rms_px, fit.max_px, plain_fit.rms_px, plain_fit.max_px,
      unseparated_found);
  EXPECT_LT(fit.rms_px, plain_fit.rms_px);
}

INSTANTIATE_TEST_SUITE_P(Euroc, AprilgridReal, ::testing::Values(0, 1));

}  // namespace
}  // namespace mavloc
