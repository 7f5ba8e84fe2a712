// Scenario "stereo-obstacles" and its ray-cast renderer
// (datasets/rendering/stereo_room_renderer.h).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <opencv2/imgproc.hpp>

#include "core/image_codec.h"
#include "core/rotation.h"
#include "datasets/rendering/stereo_room_renderer.h"
#include "datasets/scenarios/scenario.h"
#include "datasets/scenarios/stereo_obstacles.h"
#include "tests/test_support.h"

namespace mavloc {
namespace {

Dataset Generate(const ScenarioOptions& options = {}) {
  const ScenarioEntry* entry = FindScenario("stereo-obstacles");
  EXPECT_NE(entry, nullptr);
  return entry->generate(options);
}

TEST(StereoObstaclesScenarioTest, StereoPairOfThePaper) {
  const Dataset d = Generate();
  const CameraSensor* cam0 = d.Camera("cam0");
  const CameraSensor* cam1 = d.Camera("cam1");
  ASSERT_NE(cam0, nullptr);
  ASSERT_NE(cam1, nullptr);
  for (const CameraSensor* camera : {cam0, cam1}) {
    EXPECT_EQ(camera->model.width(), 640);
    EXPECT_EQ(camera->model.height(), 480);
    EXPECT_DOUBLE_EQ(camera->model.fu(), 645.0);
    EXPECT_DOUBLE_EQ(camera->model.fv(), 645.0);
  }
  // cam1 sits 5 cm to the right of cam0 (+x of cam0), both looking forward (+x of the body).
  const Pose T_C0_C1 = cam0->T_B_C.Inverse() * cam1->T_B_C;
  EXPECT_NEAR(T_C0_C1.p.norm(), 0.05, 1e-12);
  EXPECT_NEAR(T_C0_C1.p.x(), 0.05, 1e-12);
  EXPECT_NEAR((cam0->T_B_C.R() * Eigen::Vector3d::UnitZ() - Eigen::Vector3d::UnitX()).norm(), 0.0,
              1e-12);
  // Synchronous frames, default 5 Hz over 10 s; IMU at 200 Hz with ground truth.
  ASSERT_EQ(cam0->frames.size(), cam1->frames.size());
  for (size_t i = 0; i < cam0->frames.size(); ++i)
    EXPECT_EQ(cam0->frames[i].t_ns, cam1->frames[i].t_ns);
  EXPECT_EQ(cam0->frames.size(), 51u);
  EXPECT_EQ(d.imu.samples.size(), 2001u);
  EXPECT_EQ(d.ground_truth.size(), d.imu.samples.size());
  EXPECT_NEAR(NsToSeconds(d.ground_truth.back().t_ns - d.ground_truth.front().t_ns), 10.0, 1e-9);
  // Without --render there are no images.
  EXPECT_TRUE(cam0->frames.front().image_path.empty());
}

// The obstacles pass the true trajectory at the documented gaps, four inside the 0.75 m clearance.
TEST(StereoObstaclesScenarioTest, ObstaclesAtTheirGaps) {
  const Dataset d = Generate();
  std::string reason;
  const auto room = StereoRoomFromMapParameters(d.map.parameters, &reason);
  ASSERT_TRUE(room.has_value()) << reason;
  ASSERT_EQ(room->obstacles.size(), 6u);
  const std::vector<double> gaps = {0.45, 1.10, 0.55, 0.60, 1.30, 0.50};
  int within = 0;
  for (size_t i = 0; i < gaps.size(); ++i) {
    double closest = 1e9;
    for (const auto& gt : d.ground_truth)
      closest = std::min(closest, DistanceToObstacle(room->obstacles[i], gt.T_W_B.p));
    EXPECT_NEAR(closest, gaps[i], 0.01) << "obstacle " << i;
    within += closest < 0.75;
    // Standing on the floor, inside the room.
    const RoomObstacle& o = room->obstacles[i];
    const double half_height =
        o.shape == ObstacleShape::kBox ? 0.5 * o.box_size_m.z() : 0.5 * o.height_m;
    EXPECT_NEAR(o.center_W.z() - half_height, room->min_W.z(), 1e-12);
  }
  EXPECT_EQ(within, 4);
  // Walls, floor and ceiling stay farther than the clearance from the path.
  for (const auto& gt : d.ground_truth) {
    EXPECT_GT((gt.T_W_B.p - room->min_W).minCoeff(), 0.75);
    EXPECT_GT((room->max_W - gt.T_W_B.p).minCoeff(), 0.75);
  }
}

TEST(StereoObstaclesScenarioTest, SameSeedSameData) {
  ScenarioOptions options;
  options.seed = 7;
  const Dataset a = Generate(options), b = Generate(options);
  ASSERT_EQ(a.imu.samples.size(), b.imu.samples.size());
  for (size_t i = 0; i < a.imu.samples.size(); ++i) {
    EXPECT_EQ(a.imu.samples[i].accel_m_s2, b.imu.samples[i].accel_m_s2);
    EXPECT_EQ(a.imu.samples[i].gyro_rad_s, b.imu.samples[i].gyro_rad_s);
  }
  EXPECT_EQ(a.map.parameters, b.map.parameters);
  options.seed = 8;
  EXPECT_NE(Generate(options).imu.samples[100].accel_m_s2, a.imu.samples[100].accel_m_s2);
}

TEST(StereoObstaclesScenarioTest, RejectsBadSettings) {
  ScenarioOptions options;
  options.settings["camera_rate_hz"] = "0";
  EXPECT_ANY_THROW(Generate(options));
  options.settings.clear();
  options.duration_s = 4.0;
  EXPECT_ANY_THROW(Generate(options));
}

TEST(StereoRoomTest, MapParametersRoundTrip) {
  StereoRoom room;
  room.texture_seed = 1234;
  RoomObstacle box;
  box.center_W = {1.0, 2.0, 0.5};
  box.box_size_m = {0.3, 0.4, 1.0};
  box.yaw_rad = 0.25;
  RoomObstacle cylinder;
  cylinder.shape = ObstacleShape::kCylinder;
  cylinder.center_W = {3.0, -1.0, 0.9};
  cylinder.radius_m = 0.2;
  cylinder.height_m = 1.8;
  room.obstacles = {box, cylinder};
  std::map<std::string, double> parameters = {{"D", 0.1}};
  StereoRoomToMapParameters(room, &parameters);
  std::string reason;
  const auto back = StereoRoomFromMapParameters(parameters, &reason);
  ASSERT_TRUE(back.has_value()) << reason;
  EXPECT_EQ(back->texture_seed, 1234u);
  ASSERT_EQ(back->obstacles.size(), 2u);
  EXPECT_EQ(back->obstacles[0].shape, ObstacleShape::kBox);
  EXPECT_EQ(back->obstacles[0].box_size_m, box.box_size_m);
  EXPECT_EQ(back->obstacles[0].yaw_rad, box.yaw_rad);
  EXPECT_EQ(back->obstacles[1].shape, ObstacleShape::kCylinder);
  EXPECT_EQ(back->obstacles[1].radius_m, 0.2);
  EXPECT_EQ(back->obstacles[1].center_W, cylinder.center_W);

  // No room: nullopt without a reason. Incomplete: nullopt with one naming the key.
  EXPECT_FALSE(StereoRoomFromMapParameters({{"D", 0.1}}, &reason).has_value());
  EXPECT_EQ(reason, "");
  parameters.erase("obstacle_1_radius");
  EXPECT_FALSE(StereoRoomFromMapParameters(parameters, &reason).has_value());
  EXPECT_NE(reason.find("obstacle_1_radius"), std::string::npos) << reason;
  parameters["obstacle_1_radius"] = 0.2;
  parameters["obstacle_0_shape"] = 3.0;
  EXPECT_FALSE(StereoRoomFromMapParameters(parameters, &reason).has_value());
  EXPECT_NE(reason.find("obstacle_0_shape"), std::string::npos) << reason;
}

TEST(StereoRoomTest, DistanceToObstacleSurfaces) {
  RoomObstacle box;
  box.center_W = {0, 0, 1};
  box.box_size_m = {2, 1, 2};
  box.yaw_rad = M_PI / 2;                                         // the 2 m side now runs along y
  EXPECT_NEAR(DistanceToObstacle(box, {1.5, 0, 1}), 1.0, 1e-12);  // 0.5 m half-width along x
  EXPECT_NEAR(DistanceToObstacle(box, {0, 1.5, 1}), 0.5, 1e-12);
  EXPECT_NEAR(DistanceToObstacle(box, {0, 0, 1}), 0.0, 1e-12);                     // inside
  EXPECT_NEAR(DistanceToObstacle(box, {1.5, 2, 1}), std::hypot(1.0, 1.0), 1e-12);  // corner
  RoomObstacle cylinder;
  cylinder.shape = ObstacleShape::kCylinder;
  cylinder.center_W = {0, 0, 1};
  cylinder.radius_m = 0.5;
  cylinder.height_m = 2.0;
  EXPECT_NEAR(DistanceToObstacle(cylinder, {0.6, 0.8, 1.5}), 0.5, 1e-12);
  EXPECT_NEAR(DistanceToObstacle(cylinder, {0, 0, 2.5}), 0.5, 1e-12);  // above the top cap
  EXPECT_NEAR(DistanceToObstacle(cylinder, {1.1, 0, 2.8}), std::hypot(0.6, 0.8), 1e-12);
}

// Depth of the rendered view against independent analytic intersections.
TEST(StereoRoomRendererTest, TrueDepthMatchesAnalyticGeometry) {
  StereoRoom room;
  room.min_W = {-1, -2, 0};
  room.max_W = {6, 2, 3};
  RoomObstacle box;
  box.center_W = {3.0, 0.0, 1.2};  // a floating block from z = 0.9 to 1.5 m
  box.box_size_m = {0.5, 0.6, 0.6};
  room.obstacles = {box};
  const CameraSensor camera = StereoObstaclesCamera(0, 5.0, 0.0);
  const StereoRoomRenderer renderer(camera.model, room);
  const Pose T_W_B(Eigen::Matrix3d::Identity(), Eigen::Vector3d(0.0, -0.025, 1.2));
  const Pose T_W_C = T_W_B * camera.T_B_C;  // camera at (0.08, 0, 1.2) looking along +x
  cv::Mat depth;
  const cv::Mat image = renderer.RenderIdeal(T_W_C, &depth);
  ASSERT_EQ(depth.size(), cv::Size(640, 480));
  // Centre ray: the box's front face at x = 2.75.
  EXPECT_NEAR(depth.at<float>(240, 320), 2.75 - 0.08, 1e-4);
  // A ray above the box hits the far wall at x = 6 (row 0 looks up by atan(239.5/645) = 20 deg,
  // 0.08 + 6 * tan(20 deg) > 3 m is the ceiling, so take row 150: up by 89.5 px).
  const double up = 89.5 / 645.0;  // tan of the elevation
  const double z_wall = 6.0 - 0.08;
  const double height_at_wall = 1.2 + up * z_wall;
  ASSERT_LT(height_at_wall, 3.0);
  ASSERT_GT(1.2 + up * (2.75 - 0.08), 1.5);  // passes above the block
  EXPECT_NEAR(depth.at<float>(150, 320), z_wall, 1e-4);
  // A ray down to the floor (row 479: down by 239.5 px): z = 1.2 / (239.5 / 645) to the floor.
  const double z_floor = 1.2 / (239.5 / 645.0);
  EXPECT_NEAR(depth.at<float>(479, 40), z_floor, 1e-3);
  // Every pixel hits something inside the room, and the image is textured.
  double min_depth, max_depth;
  cv::minMaxLoc(depth, &min_depth, &max_depth);
  EXPECT_GT(min_depth, 0.0);
  EXPECT_LT(max_depth, 10.0);
  cv::Scalar mean, stddev;
  cv::meanStdDev(image, mean, stddev);
  EXPECT_GT(stddev[0], 15.0);
}

// The texture is fixed to the surfaces: a point seen by cam0 has the same grey level in cam1.
TEST(StereoRoomRendererTest, BothCamerasSeeTheSameTexture) {
  const Dataset d = Generate();
  std::string reason;
  const auto room = StereoRoomFromMapParameters(d.map.parameters, &reason);
  ASSERT_TRUE(room.has_value()) << reason;
  const CameraSensor& cam0 = *d.Camera("cam0");
  const CameraSensor& cam1 = *d.Camera("cam1");
  const StereoRoomRenderer r0(cam0.model, *room), r1(cam1.model, *room);
  const Pose T_W_B = d.ground_truth[d.ground_truth.size() / 3].T_W_B;
  cv::Mat depth0, depth1;
  const cv::Mat image0 = r0.RenderIdeal(T_W_B * cam0.T_B_C, &depth0);
  const cv::Mat image1 = r1.RenderIdeal(T_W_B * cam1.T_B_C, &depth1);
  const Pose T_C1_C0 = cam1.T_B_C.Inverse() * cam0.T_B_C;
  std::vector<double> differences;
  for (int v = 10; v < 470; v += 7) {
    for (int u = 10; u < 630; u += 7) {
      const double z = depth0.at<float>(v, u);
      if (!(z < 3.5)) continue;  // within the stereo range
      const Eigen::Vector3d p_C0 = z * Eigen::Vector3d((u - 319.5) / 645.0, (v - 239.5) / 645.0, 1);
      const auto uv = cam1.model.Project(T_C1_C0 * p_C0);
      if (!uv || !cam1.model.IsInside(*uv, 2.0)) continue;
      const int u1 = static_cast<int>(std::lround(uv->x())),
                v1 = static_cast<int>(std::lround(uv->y()));
      // Skip pixels that cam1 sees occluded (its own depth disagrees).
      if (std::abs(depth1.at<float>(v1, u1) - (T_C1_C0 * p_C0).z()) > 0.01) continue;
      cv::Mat patch;
      cv::getRectSubPix(image1, {1, 1},
                        cv::Point2f(static_cast<float>(uv->x()), static_cast<float>(uv->y())),
                        patch);
      differences.push_back(std::abs(patch.at<float>(0, 0) - image0.at<float>(v, u)));
    }
  }
  ASSERT_GT(differences.size(), 500u);
  std::nth_element(differences.begin(), differences.begin() + differences.size() / 2,
                   differences.end());
  EXPECT_LT(differences[differences.size() / 2], 3.0);  // grey levels (of 255)
}

TEST(StereoRoomRendererTest, SameSeedSameBytes) {
  const Dataset d = Generate();
  std::string reason;
  const auto room = StereoRoomFromMapParameters(d.map.parameters, &reason);
  ASSERT_TRUE(room.has_value()) << reason;
  const CameraSensor& cam0 = *d.Camera("cam0");
  const StereoRoomRenderer renderer(cam0.model, *room);
  const Pose T_W_C = d.ground_truth[d.ground_truth.size() / 2].T_W_B * cam0.T_B_C;
  const cv::Mat a = renderer.Render(T_W_C, 42), b = renderer.Render(T_W_C, 42);
  const cv::Mat c = renderer.Render(T_W_C, 43);
  EXPECT_EQ(cv::countNonZero(a != b), 0);
  EXPECT_GT(cv::countNonZero(a != c), 0);
}

TEST(StereoObstaclesScenarioTest, RendersBothCameras) {
  const std::string folder = testing::MakeTempDir();
  ScenarioOptions options;
  options.duration_s = 5.0;
  options.render_images = true;
  options.settings["camera_rate_hz"] = "1";
  options.settings["image_dir"] = folder;
  const Dataset d = Generate(options);
  for (const std::string name : {"cam0", "cam1"}) {
    const CameraSensor* camera = d.Camera(name);
    ASSERT_NE(camera, nullptr);
    ASSERT_EQ(camera->frames.size(), 6u);
    for (const CameraFrame& frame : camera->frames) {
      ASSERT_TRUE(std::filesystem::exists(frame.image_path)) << frame.image_path;
      std::string why;
      const cv::Mat image =
          DecodeImage(testing::ReadFileBytes(frame.image_path), ImageDecodeMode::kUnchanged, &why);
      EXPECT_EQ(image.type(), CV_8UC1);
      EXPECT_EQ(image.size(), cv::Size(640, 480));
    }
  }
  std::filesystem::remove_all(folder);
}

}  // namespace
}  // namespace mavloc
