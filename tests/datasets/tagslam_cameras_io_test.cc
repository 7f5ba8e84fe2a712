// TagSLAM's cameras.yaml + camera_poses.yaml -> mavloc cameras: the real files of tests 11, 21
// and 22 (models, intrinsics, T_B_C = T_rig_cam, cameras without pose or with an unsupported
// model), the equidistant model checked against TagSLAM's Cal3FS2 formula, and bad input.
#include "datasets/io/tagslam/tagslam_cameras_io.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "core/errors.h"
#include "core/rotation.h"
#include "tests/test_support.h"

namespace mavloc {
namespace {

std::vector<TagslamCamera> ReadTest(const std::string& test) {
  const std::string dir = testing::SharedDataDir() + "/tagslam/" + test;
  return ReadTagslamCameras(dir + "/cameras.yaml", dir + "/camera_poses.yaml");
}

TEST(TagslamCameras, Test11StereoEquidistant) {
  REQUIRE_SHARED_DATA();
  const std::vector<TagslamCamera> cameras = ReadTest("test_11");
  ASSERT_EQ(cameras.size(), 2u);
  const TagslamCamera& cam0 = cameras[0];
  ASSERT_TRUE(cam0.model.has_value());
  EXPECT_EQ(cam0.model->distortion_model(), DistortionModel::kEquidistant);
  EXPECT_EQ(cam0.model->width(), 1280);
  EXPECT_EQ(cam0.model->height(), 1024);
  EXPECT_DOUBLE_EQ(cam0.model->fu(), 603.924);
  EXPECT_DOUBLE_EQ(cam0.model->cv(), 554.34);
  EXPECT_DOUBLE_EQ(cam0.model->distortion()[3], -0.00247881);
  EXPECT_EQ(cam0.tag_topic, "/fla/ovc_node/left/tags");
  EXPECT_EQ(cam0.rig_body, "rig");
  ASSERT_TRUE(cam0.T_B_C.has_value());
  EXPECT_LT(cam0.T_B_C->p.norm(), 1e-15);
  // T_rig_cam1: the right camera 0.2 m along the left camera's (= the rig's) x axis.
  const TagslamCamera& cam1 = cameras[1];
  ASSERT_TRUE(cam1.T_B_C.has_value());
  EXPECT_NEAR((cam1.T_B_C->p - Eigen::Vector3d(0.20031766, 0.00166686, 0.00093769)).norm(), 0.0,
              1e-12);
  EXPECT_NEAR(LogSO3(cam1.T_B_C->R()).y(), -0.00929578, 1e-10);
}

TEST(TagslamCameras, Test21FisheyesAndTofs) {
  REQUIRE_SHARED_DATA();
  const std::vector<TagslamCamera> cameras = ReadTest("test_21");
  ASSERT_EQ(cameras.size(), 4u);
  EXPECT_TRUE(cameras[0].model && cameras[0].T_B_C);
  EXPECT_EQ(cameras[0].tag_topic, "/t265/fisheye1/tags");
  EXPECT_EQ(cameras[0].model->width(), 848);
  // cam1 (second fisheye): a supported model but no pose in camera_poses.yaml.
  EXPECT_TRUE(cameras[1].model.has_value());
  EXPECT_FALSE(cameras[1].T_B_C.has_value());
  // cam2, cam3 (time-of-flight): plumb_bob with a non-zero k3, which mavloc cannot represent.
  for (int k : {2, 3}) {
    EXPECT_FALSE(cameras[k].model.has_value());
    EXPECT_NE(cameras[k].unsupported.find("k3"), std::string::npos) << cameras[k].unsupported;
  }
}

TEST(TagslamCameras, EquidistantIsTagslamCal3FS2) {
  REQUIRE_SHARED_DATA();
  const CameraModel model = *ReadTest("test_22")[0].model;
  // TagSLAM's Cal3FS2::uncalibrate: theta = atan(r), theta_d = theta + k1 theta^3 + k2 theta^5 +
  // k3 theta^7 + k4 theta^9, u = fx theta_d x / r + u0 (Kalibr's equidistant model).
  const double k1 = 0.00132, k2 = 0.03049, k3 = -0.02875, k4 = 0.0034;
  for (const Eigen::Vector3d& p_C :
       {Eigen::Vector3d(0.3, -0.2, 1.0), Eigen::Vector3d(-1.5, 0.8, 1.0),
        Eigen::Vector3d(2.0, 2.0, 0.5)}) {
    const double x = p_C.x() / p_C.z(), y = p_C.y() / p_C.z(), r = std::hypot(x, y);
    const double t = std::atan(r);
    const double t_d =
        t + k1 * std::pow(t, 3) + k2 * std::pow(t, 5) + k3 * std::pow(t, 7) + k4 * std::pow(t, 9);
    const Eigen::Vector2d expected(283.943 * t_d * x / r + 421.079,
                                   284.986 * t_d * y / r + 400.527);
    const auto uv = model.Project(p_C);
    ASSERT_TRUE(uv.has_value());
    EXPECT_LT((*uv - expected).norm(), 1e-9);
  }
}

struct Files {
  std::string cameras, poses;
};
Files Write(const std::string& cameras, const std::string& poses) {
  const std::string dir = testing::MakeTempDir();
  std::ofstream(dir + "/cameras.yaml") << cameras;
  std::ofstream(dir + "/camera_poses.yaml") << poses;
  return {dir + "/cameras.yaml", dir + "/camera_poses.yaml"};
}

std::string ErrorOf(const std::string& cameras, const std::string& poses) {
  const Files f = Write(cameras, poses);
  try {
    ReadTagslamCameras(f.cameras, f.poses);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

const char* kPose =
    "cam0:\n  pose:\n    position: {x: 0, y: 0, z: 0}\n"
    "    rotation: {x: 0, y: 0, z: 0}\n";

TEST(TagslamCameras, RadtanWithFourOrZeroK3) {
  const Files f = Write(
      "cam0:\n  intrinsics: [500, 500, 320, 240]\n  distortion_model: radtan\n"
      "  distortion_coeffs: [0.1, -0.2, 0.001, 0.002, 0.0]\n  resolution: [640, 480]\n"
      "  tagtopic: /tags\n",
      kPose);
  const std::vector<TagslamCamera> cameras = ReadTagslamCameras(f.cameras, f.poses);
  ASSERT_EQ(cameras.size(), 1u);
  ASSERT_TRUE(cameras[0].model.has_value());
  EXPECT_EQ(cameras[0].model->distortion_model(), DistortionModel::kRadialTangential);
  EXPECT_DOUBLE_EQ(cameras[0].model->distortion()[3], 0.002);
}

TEST(TagslamCamerasBadInput, ErrorsNameFileLineAndField) {
  std::string error = ErrorOf(
      "cam0:\n  intrinsics: [500, 500, 320]\n  distortion_model: equidistant\n"
      "  distortion_coeffs: [0, 0, 0, 0]\n  resolution: [640, 480]\n",
      kPose);
  EXPECT_NE(error.find("cameras.yaml:2"), std::string::npos) << error;
  EXPECT_NE(error.find("'intrinsics'"), std::string::npos) << error;
  EXPECT_NE(error.find("expected 4 values"), std::string::npos) << error;
  error = ErrorOf(
      "cam0:\n  intrinsics: [500, 500, 320, 240]\n  distortion_model: equidistant\n"
      "  distortion_coeffs: [0, 0, 0]\n  resolution: [640, 480]\n",
      kPose);
  EXPECT_NE(error.find("cameras.yaml:4"), std::string::npos) << error;
  EXPECT_NE(error.find("needs 4 coefficients"), std::string::npos) << error;
  error = ErrorOf(
      "cam0:\n  intrinsics: [500, 500, 320, 240]\n  distortion_model: equidistant\n"
      "  distortion_coeffs: [0, 0, 0, 0]\n",
      kPose);
  EXPECT_NE(error.find("'resolution'"), std::string::npos) << error;
  EXPECT_NE(error.find("missing"), std::string::npos) << error;
  // Found by fuzz_tagslam_cameras: a resolution far beyond any camera was cast to int unchecked.
  error = ErrorOf(
      "cam0:\n  intrinsics: [500, 500, 320, 240]\n  distortion_model: equidistant\n"
      "  distortion_coeffs: [0, 0, 0, 0]\n  resolution: [8.3e15, 480]\n",
      kPose);
  EXPECT_NE(error.find("cameras.yaml:5: field 'resolution': expected two integers in [1, 100000]"),
            std::string::npos)
      << error;
  const std::string camera =
      "cam0:\n  intrinsics: [500, 500, 320, 240]\n  distortion_model: equidistant\n"
      "  distortion_coeffs: [0, 0, 0, 0]\n  resolution: [640, 480]\n";
  error = ErrorOf(camera, "cam0:\n  pose:\n    position: {x: 0, y: 0, z: 0}\n");
  EXPECT_NE(error.find("camera_poses.yaml"), std::string::npos) << error;
  EXPECT_NE(error.find("'rotation'"), std::string::npos) << error;
  error = ErrorOf(camera, std::string(kPose) + "cam5:\n  pose: {}\n");
  EXPECT_NE(error.find("camera_poses.yaml:5"), std::string::npos) << error;
  EXPECT_NE(error.find("does not list"), std::string::npos) << error;
  EXPECT_NE(ErrorOf("foo: 1\n", kPose).find("no camera"), std::string::npos);
}

}  // namespace
}  // namespace mavloc
