// The natural-feature frontend on images whose true motion is known: a real photograph
// (../shared/data/textures) shifted by a sub-pixel translation, and rotated as a camera turning
// about its centre (a homography K R K^-1, which the gyro prediction must undo).
#include "frontends/features/feature_tracker.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "core/rotation.h"
#include "frontends/features/grid_detector.h"
#include "frontends/features/gyro_rotation.h"
#include "frontends/image_io.h"
#include "tests/test_support.h"

namespace mavloc {
namespace {

constexpr int kWidth = 376, kHeight = 240;

CameraSensor TestCamera() {
  CameraSensor camera;
  camera.name = "cam0";
  camera.model = CameraModel(kWidth, kHeight, Eigen::Vector4d(230.0, 230.0, 188.0, 120.0));
  return camera;
}

cv::Mat Photo() {
  const std::string path = testing::SharedDataDir() + "/textures/graf1.png";
  const cv::Mat full = LoadGrayImage(path);
  return full(cv::Rect(100, 100, kWidth + 40, kHeight + 40)).clone();
}

// The photo seen through a camera that moved by (dx, dy) px and turned by R_C1_C0 about its
// centre: pixel u1 = K R K^-1 (u0 + shift).
cv::Mat View(const cv::Mat& photo, const CameraModel& model, const Eigen::Matrix3d& R_C1_C0,
             double dx, double dy) {
  const Eigen::Matrix3d K = model.K();
  Eigen::Matrix3d shift = Eigen::Matrix3d::Identity();
  shift(0, 2) = 20.0 - dx;  // the view starts 20 px into the photo
  shift(1, 2) = 20.0 - dy;
  const Eigen::Matrix3d H_photo_to_view = K * R_C1_C0 * K.inverse() * shift.inverse();
  cv::Mat H(3, 3, CV_64F);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) H.at<double>(r, c) = H_photo_to_view(r, c);
  cv::Mat view;
  cv::warpPerspective(photo, view, H, cv::Size(kWidth, kHeight), cv::INTER_LINEAR);
  return view;
}

class FeatureTrackerTest : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!testing::HasSharedData()) GTEST_SKIP() << "shared data absent";
  }
};

TEST_F(FeatureTrackerTest, GridCornersCoverTheImageAndKeepTheirSpacing) {
  GridDetectorOptions options;
  options.max_features = 120;
  const std::vector<cv::Point2f> corners = DetectInGrid(
      View(Photo(), TestCamera().model, Eigen::Matrix3d::Identity(), 0, 0), {}, options);
  ASSERT_GE(corners.size(), 60u);  // half the target at least, spread over the cells
  std::vector<int> per_cell(options.grid_cols * options.grid_rows, 0);
  for (size_t i = 0; i < corners.size(); ++i) {
    ++per_cell[static_cast<int>(corners[i].y * options.grid_rows / kHeight) * options.grid_cols +
               static_cast<int>(corners[i].x * options.grid_cols / kWidth)];
    for (size_t j = 0; j < i; ++j)
      EXPECT_GE(cv::norm(corners[i] - corners[j]), options.min_distance_px - 1.0);
  }
  int empty = 0;
  for (int n : per_cell) empty += n == 0 ? 1 : 0;
  EXPECT_LE(empty, 4) << "cells without a corner (a tenth of the grid: the photo has flat patches)";
}

TEST_F(FeatureTrackerTest, FlatImageGivesNoCorner) {
  EXPECT_TRUE(DetectInGrid(cv::Mat(kHeight, kWidth, CV_8U, cv::Scalar(0)), {}, {}).empty());
  EXPECT_TRUE(DetectInGrid(cv::Mat(kHeight, kWidth, CV_8U, cv::Scalar(128)), {}, {}).empty());
}

// The median of a set of errors.
double Median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

// A sub-pixel shift: the tracks move by it, to a twentieth of a pixel in the median (measured:
// 0.04 px; the largest 0.23 px), and none is a wrong association (off by more than 1 px).
TEST_F(FeatureTrackerTest, TracksFollowASubPixelShift) {
  const cv::Mat photo = Photo();
  const CameraSensor camera = TestCamera();
  FeatureTracker tracker(camera, nullptr, {});
  const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
  const FeatureFrameOutput first =
      tracker.Track(0, View(photo, camera.model, I, 0, 0), {}, Eigen::Quaterniond::Identity());
  const FeatureFrameOutput second = tracker.Track(
      50'000'000, View(photo, camera.model, I, 2.3, -1.7), {}, Eigen::Quaterniond::Identity());
  ASSERT_GT(first.cam0.size(), 60u);
  EXPECT_GE(second.statistics.tracked, static_cast<int>(0.9 * first.cam0.size()));
  std::vector<double> errors_px;
  for (const FeatureObservation& b : second.cam0) {
    for (const FeatureObservation& a : first.cam0) {
      if (a.landmark_id != b.landmark_id) continue;
      const Eigen::Vector2d moved_px = (b.xy - a.xy) * camera.model.fu();
      errors_px.push_back((moved_px - Eigen::Vector2d(2.3, -1.7)).norm());
    }
  }
  ASSERT_GT(errors_px.size(), 50u);
  EXPECT_LT(Median(errors_px), 0.05);
  EXPECT_LT(*std::max_element(errors_px.begin(), errors_px.end()), 1.0);
}

// A turn of 6 deg between frames moves the image by about 24 px: with the gyro's rotation the
// tracks start where they go and survive; each lands where the rotation puts it (measured: median
// 0.25 px, the largest 1.2 px: the turn also shears the patches, which Lucas-Kanade's translation
// model does not follow), and at most 2 % are wrong associations (off by more than 2 px).
TEST_F(FeatureTrackerTest, GyroPredictionFollowsAFastTurn) {
  const cv::Mat photo = Photo();
  const CameraSensor camera = TestCamera();  // T_B_C identity: body and camera turn alike
  const Eigen::Quaterniond q_B0_B1 = ExpQuaternion(Eigen::Vector3d(0.0, 6.0 * M_PI / 180.0, 0.0));
  const Eigen::Matrix3d R_C1_C0 = q_B0_B1.conjugate().toRotationMatrix();
  FeatureTrackerOptions options;
  options.klt_pyramid_levels = 1;  // a search too short for 24 px without the prediction
  FeatureTracker tracker(camera, nullptr, options);
  const FeatureFrameOutput first =
      tracker.Track(0, View(photo, camera.model, Eigen::Matrix3d::Identity(), 0, 0), {},
                    Eigen::Quaterniond::Identity());
  const FeatureFrameOutput second =
      tracker.Track(50'000'000, View(photo, camera.model, R_C1_C0, 0, 0), {}, q_B0_B1);
  ASSERT_GT(first.cam0.size(), 60u);
  std::vector<double> errors_px;
  for (const FeatureObservation& b : second.cam0) {
    for (const FeatureObservation& a : first.cam0) {
      if (a.landmark_id != b.landmark_id) continue;
      const Eigen::Vector3d f = R_C1_C0 * Eigen::Vector3d(a.xy.x(), a.xy.y(), 1.0);
      const Eigen::Vector2d expected = f.head<2>() / f.z();
      errors_px.push_back((b.xy - expected).norm() * camera.model.fu());
    }
  }
  ASSERT_GT(errors_px.size(), 0.5 * first.cam0.size());
  EXPECT_LT(Median(errors_px), 0.4);
  const auto wrong =
      std::count_if(errors_px.begin(), errors_px.end(), [](double e) { return e > 2.0; });
  EXPECT_LE(wrong, static_cast<long>(errors_px.size() / 50));
}

TEST(GyroRotation, ConstantRateIntegratesToItsAngle) {
  std::vector<ImuSample> samples;
  for (int i = 0; i <= 200; ++i) {
    ImuSample s;
    s.t_ns = i * 5'000'000LL;
    s.gyro_rad_s = Eigen::Vector3d(0.0, 0.0, 0.5);
    samples.push_back(s);
  }
  const auto q = GyroRotation(samples, 12'000'000, 512'000'000);
  ASSERT_TRUE(q.has_value());
  EXPECT_NEAR(Eigen::AngleAxisd(*q).angle(), 0.25, 1e-12);
  EXPECT_FALSE(GyroRotation(samples, 0, 2'000'000'000).has_value());  // past the samples
}

}  // namespace
}  // namespace mavloc
