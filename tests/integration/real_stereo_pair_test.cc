// The frontend's stereo matching on a real EuRoC stereo pair (../shared/data/euroc_cam_april/
// images: cam0 and cam1 of one instant of the calibration sequence, an aprilgrid in front of the
// rig) with EuRoC's own calibration (euroc_v1_01_easy's sensor.yaml, the same rig). Each match is
// checked independently of the tracker: its bearing in cam1 lies on the epipolar plane of T_C1_C0
// within the tracker's tolerance, and the point it triangulates to is in front of both cameras at
// the distance of the board (the frames show it at about 1-3 m).
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <algorithm>
#include <map>
#include <vector>

#include "core/dataset.h"
#include "datasets/io/euroc_io.h"
#include "frontends/features/feature_tracker.h"
#include "frontends/image_io.h"
#include "tests/test_support.h"

namespace mavloc {
namespace {

// The depth in cam0 of the midpoint of the closest points of the two rays (0 when parallel).
double TriangulatedDepth(const Eigen::Vector3d& f0, const Eigen::Vector3d& f1_in_C0,
                         const Eigen::Vector3d& c1_in_C0) {
  // Solve s f0 - u f1 = c1 in least squares.
  Eigen::Matrix<double, 3, 2> A;
  A.col(0) = f0;
  A.col(1) = -f1_in_C0;
  const Eigen::Vector2d su = A.colPivHouseholderQr().solve(c1_in_C0);
  return (0.5 * (su[0] * f0 + c1_in_C0 + su[1] * f1_in_C0)).z();
}

TEST(RealStereoPair, EveryMatchIsOnItsEpipolarPlaneAndAtTheBoardsDistance) {
  REQUIRE_SHARED_DATA();
  const std::string data = testing::SharedDataDir();
  const Dataset euroc = ReadEurocDataset(data + "/euroc_v1_01_easy");
  const CameraSensor* cam0 = euroc.Camera("cam0");
  const CameraSensor* cam1 = euroc.Camera("cam1");
  ASSERT_NE(cam0, nullptr);
  ASSERT_NE(cam1, nullptr);
  const std::string images = data + "/euroc_cam_april/images/";
  const cv::Mat gray0 = LoadGrayImage(images + "cam0_1403709395937837056.png");
  const cv::Mat gray1 = LoadGrayImage(images + "cam1_1403709395937837056.png");
  FeatureTrackerOptions options;
  FeatureTracker tracker(*cam0, cam1, options);
  const FeatureFrameOutput out = tracker.Track(1403709395937837056, gray0, gray1, std::nullopt);
  std::printf("%zu corners, %zu stereo matches, %d rejected, %d by the epipolar test\n",
              out.cam0.size(), out.cam1.size(), out.statistics.stereo_rejected,
              out.statistics.stereo_rejected_epipolar);
  EXPECT_GE(out.cam1.size(), out.cam0.size() / 2);
  ASSERT_GE(out.cam1.size(), 50u);

  const Pose T_C1_C0 = cam1->T_B_C.Inverse() * cam0->T_B_C;
  const Eigen::Vector3d t = T_C1_C0.p;
  const Eigen::Matrix3d R = T_C1_C0.q.toRotationMatrix();
  std::map<int, Eigen::Vector3d> f0_by_id;
  for (const FeatureObservation& o : out.cam0)
    f0_by_id[o.landmark_id] = Eigen::Vector3d(o.xy.x(), o.xy.y(), 1.0).normalized();
  std::vector<double> depths;
  for (const FeatureObservation& o : out.cam1) {
    ASSERT_TRUE(f0_by_id.count(o.landmark_id)) << "a cam1 match without its cam0 track";
    const Eigen::Vector3d f0 = f0_by_id[o.landmark_id];
    const Eigen::Vector3d f1 = Eigen::Vector3d(o.xy.x(), o.xy.y(), 1.0).normalized();
    const Eigen::Vector3d normal = t.cross(R * f0).normalized();
    EXPECT_LE(std::abs(f1.dot(normal)) * cam1->model.fu(), options.stereo_epipolar_px)
        << "track " << o.landmark_id;
    // In C0: cam1's centre and the cam1 ray.
    const Eigen::Vector3d c1_in_C0 = T_C1_C0.Inverse().p;
    const double depth = TriangulatedDepth(f0, R.transpose() * f1, c1_in_C0);
    EXPECT_GT(depth, 0.0) << "track " << o.landmark_id;
    depths.push_back(depth);
  }
  std::sort(depths.begin(), depths.end());
  const double median = depths[depths.size() / 2];
  std::printf("depths: median %.2f m, 10 %% %.2f m, 90 %% %.2f m\n", median,
              depths[depths.size() / 10], depths[depths.size() * 9 / 10]);
  EXPECT_GT(median, 0.5);
  EXPECT_LT(median, 5.0);
}

}  // namespace
}  // namespace mavloc
