// Camera and IMU calibrations from the files calibration tools write: yac's config.yaml (real,
// ../shared/data/euroc_imu_april), EuRoC's sensor.yaml files and mav0/ folder (real,
// euroc_v1_01_easy), Kalibr's camchain.yaml and imu.yaml (written here from EuRoC's values), and
// bad input.
#include "datasets/io/calibration_io.h"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "core/errors.h"
#include "core/rotation.h"
#include "tests/test_support.h"

namespace fs = std::filesystem;

namespace mavloc {
namespace {

std::string Data() { return testing::SharedDataDir(); }

// EuRoC's official T_BS of cam0 and cam1 (euroc_v1_01_easy/mav0/cam{0,1}/sensor.yaml).
Pose EurocT_B_C(int camera) {
  Eigen::Matrix4d T;
  if (camera == 0)
    T << 0.0148655429818, -0.999880929698, 0.00414029679422, -0.0216401454975, 0.999557249008,
        0.0149672133247, 0.025715529948, -0.064676986768, -0.0257744366974, 0.00375618835797,
        0.999660727178, 0.00981073058949, 0, 0, 0, 1;
  else
    T << 0.0125552670891, -0.999755099723, 0.0182237714554, -0.0198435579556, 0.999598781151,
        0.0130119051815, 0.0251588363115, 0.0453689425024, -0.0253898008918, 0.0179005838253,
        0.999517347078, 0.00786212447038, 0, 0, 0, 1;
  return Pose::FromMatrix(T);
}

double PoseGap(const Pose& a, const Pose& b) {
  return (a.p - b.p).norm() + RotationAngleBetween(a.q, b.q);
}

std::string Nested(const Pose& T) {
  const Eigen::Matrix4d M = T.Matrix();
  std::string text;
  for (int r = 0; r < 4; ++r)
    text += fmt::format("  - [{:.17g}, {:.17g}, {:.17g}, {:.17g}]\n", M(r, 0), M(r, 1), M(r, 2),
                        M(r, 3));
  return text;
}

std::string WriteFile(const std::string& dir, const std::string& name, const std::string& text) {
  const std::string path = dir + "/" + name;
  fs::create_directories(fs::path(path).parent_path());
  std::ofstream(path) << text;
  return path;
}

std::string ErrorOf(const std::string& path, std::optional<int> camera = std::nullopt) {
  try {
    ReadCalibrationSource(path, camera);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(CalibrationIo, YacConfigOfTheImuAprilLog) {
  REQUIRE_SHARED_DATA();
  const CalibrationSource s = ReadCalibrationSource(Data() + "/euroc_imu_april/config.yaml");
  ASSERT_TRUE(s.target.has_value());
  EXPECT_EQ(s.target->tag_rows, 6);
  ASSERT_EQ(s.cameras.size(), 2u);
  const CameraCalibration& cam0 = s.cameras.at(0);
  ASSERT_TRUE(cam0.model.has_value());
  EXPECT_EQ(cam0.model->width(), 752);
  EXPECT_EQ(cam0.model->height(), 480);
  EXPECT_DOUBLE_EQ(cam0.model->fu(), 458.654);
  EXPECT_DOUBLE_EQ(cam0.model->cv(), 248.375);
  EXPECT_EQ(cam0.model->distortion_model(), DistortionModel::kRadialTangential);
  EXPECT_DOUBLE_EQ(cam0.model->distortion()[3], 1.76187114e-05);
  EXPECT_FALSE(cam0.T_B_C.has_value());  // yac's config knows no camera-IMU extrinsics
  const CameraCalibration& cam1 = s.cameras.at(1);
  EXPECT_DOUBLE_EQ(cam1.model->fu(), 457.587);
  EXPECT_DOUBLE_EQ(cam1.model->distortion()[0], -0.28368365);
  ASSERT_TRUE(cam1.T_C0_C.has_value());
  EXPECT_NEAR(cam1.T_C0_C->p.x(), 0.110074137800, 1e-12);
  EXPECT_NEAR(cam1.T_C0_C->R()(1, 2), -0.014090668453, 1e-9);
  EXPECT_NE(cam1.T_C0_C_from.find("T_cam0_cam1"), std::string::npos);
  // The pose in cam0 agrees with EuRoC's two T_BS to 0.1 mm and 0.01 deg.
  const Pose euroc_T_C0_C1 = EurocT_B_C(0).Inverse() * EurocT_B_C(1);
  EXPECT_LT((euroc_T_C0_C1.p - cam1.T_C0_C->p).norm(), 1e-4);
  EXPECT_LT(RotationAngleBetween(euroc_T_C0_C1.q, cam1.T_C0_C->q), 0.01 * kDeg);
  ASSERT_TRUE(s.imu.has_value());
  EXPECT_DOUBLE_EQ(s.imu->noise.gyroscope_noise_density, 1.6968e-04);
  EXPECT_DOUBLE_EQ(s.imu->noise.gyroscope_random_walk, 1.9393e-05);
  EXPECT_DOUBLE_EQ(s.imu->noise.accelerometer_noise_density, 0.002);
  EXPECT_DOUBLE_EQ(s.imu->noise.accelerometer_random_walk, 0.003);
  EXPECT_EQ(s.imu->rate_hz, std::optional<double>(200.0));
}

TEST(CalibrationIo, EurocMav0FolderCameraFolderAndSensorYaml) {
  REQUIRE_SHARED_DATA();
  const std::string mav0 = Data() + "/euroc_v1_01_easy/mav0";
  for (const std::string& path : {mav0, Data() + "/euroc_v1_01_easy"}) {
    const CalibrationSource s = ReadCalibrationSource(path);
    ASSERT_EQ(s.cameras.size(), 2u) << path;
    for (int n : {0, 1}) {
      ASSERT_TRUE(s.cameras.at(n).T_B_C.has_value());
      EXPECT_LT(PoseGap(*s.cameras.at(n).T_B_C, EurocT_B_C(n)), 1e-9);
      EXPECT_EQ(s.cameras.at(n).rate_hz, std::optional<double>(20.0));
    }
    EXPECT_DOUBLE_EQ(s.cameras.at(1).model->cu(), 379.999);
    ASSERT_TRUE(s.imu.has_value());
    EXPECT_DOUBLE_EQ(s.imu->noise.accelerometer_random_walk, 3e-3);
    EXPECT_FALSE(s.target.has_value());
  }
  // A camN/ folder or its sensor.yaml is camera N; "camN=" restricts a multi-camera source.
  EXPECT_EQ(ReadCalibrationSource(mav0 + "/cam1").cameras.count(1), 1u);
  EXPECT_EQ(ReadCalibrationSource(mav0 + "/cam1/sensor.yaml").cameras.count(1), 1u);
  const CalibrationSource only1 = ReadCalibrationSource(mav0, 1);
  ASSERT_EQ(only1.cameras.size(), 1u);
  EXPECT_EQ(only1.cameras.count(1), 1u);
  EXPECT_NE(ErrorOf(mav0 + "/cam1", 0).find("describes no cam0"), std::string::npos);
}

TEST(CalibrationIo, KalibrCamchainAndImuYaml) {
  const std::string dir = testing::MakeTempDir();
  const Pose T_C1_C0 = EurocT_B_C(1).Inverse() * EurocT_B_C(0);
  const std::string camchain = WriteFile(
      dir, "camchain.yaml",
      "cam0:\n  T_cam_imu:\n" + Nested(EurocT_B_C(0).Inverse()) +
          "  camera_model: pinhole\n  distortion_coeffs: [-0.28, 0.07, 0.0002, 1.8e-05]\n"
          "  distortion_model: radtan\n  intrinsics: [458.654, 457.296, 367.215, 248.375]\n"
          "  resolution: [752, 480]\n  rostopic: /cam0/image_raw\n  timeshift_cam_imu: 0.0\n"
          "cam1:\n  T_cam_imu:\n" +
          Nested(EurocT_B_C(1).Inverse()) + "  T_cn_cnm1:\n" + Nested(T_C1_C0) +
          "  camera_model: pinhole\n  distortion_coeffs: [0.1, 0.01, -0.002, 0.0003]\n"
          "  distortion_model: equidistant\n  intrinsics: [457.587, 456.134, 379.999, 255.238]\n"
          "  resolution: [752, 480]\n");
  const CalibrationSource s = ReadCalibrationSource(camchain);
  ASSERT_EQ(s.cameras.size(), 2u);
  for (int n : {0, 1}) {
    ASSERT_TRUE(s.cameras.at(n).T_B_C.has_value());
    EXPECT_LT(PoseGap(*s.cameras.at(n).T_B_C, EurocT_B_C(n)), 1e-12) << n;
    EXPECT_NE(s.cameras.at(n).T_B_C_from.find("T_cam_imu"), std::string::npos);
  }
  EXPECT_EQ(s.cameras.at(1).model->distortion_model(), DistortionModel::kEquidistant);
  EXPECT_DOUBLE_EQ(s.cameras.at(1).model->distortion()[3], 0.0003);
  ASSERT_TRUE(s.cameras.at(1).T_C0_C.has_value());
  EXPECT_LT(PoseGap(*s.cameras.at(1).T_C0_C, EurocT_B_C(0).Inverse() * EurocT_B_C(1)), 1e-12);
  EXPECT_FALSE(s.imu.has_value());

  const std::string imu = WriteFile(dir, "imu.yaml",
                                    "accelerometer_noise_density: 0.01\n"
                                    "accelerometer_random_walk: 0.0002\n"
                                    "gyroscope_noise_density: 0.005\n"
                                    "gyroscope_random_walk: 4.0e-06\n"
                                    "rostopic: /imu0\nupdate_rate: 200.0\n");
  const CalibrationSource i = ReadCalibrationSource(imu);
  ASSERT_TRUE(i.imu.has_value());
  EXPECT_DOUBLE_EQ(i.imu->noise.gyroscope_random_walk, 4e-6);
  EXPECT_DOUBLE_EQ(i.imu->noise.accelerometer_noise_density, 0.01);
  EXPECT_EQ(i.imu->rate_hz, std::optional<double>(200.0));
  EXPECT_TRUE(i.cameras.empty());
}

TEST(CalibrationIo, CameraPrefix) {
  EXPECT_EQ(SplitCameraPrefix("cam1=/a/b"),
            std::make_pair(std::optional<int>(1), std::string("/a/b")));
  EXPECT_EQ(SplitCameraPrefix("/a/cam1=b"),
            std::make_pair(std::optional<int>(), std::string("/a/cam1=b")));
  EXPECT_EQ(SplitCameraPrefix("dir"), std::make_pair(std::optional<int>(), std::string("dir")));
}

TEST(CalibrationIo, BadInputNamesFileLineAndField) {
  const std::string dir = testing::MakeTempDir();
  {
    std::string text = "cam0:\n";
    for (const std::string line : {"resolution: [752, 480]", "proj_model: pinhole",
                                   "proj_params: [458, 457, 367, 248]", "dist_model: fov1"})
      text += "  " + line + "\n";
    const std::string e = ErrorOf(WriteFile(dir, "b.yaml", text));
    EXPECT_NE(e.find("b.yaml:5: field 'cam0.dist_model': unknown model 'fov1'"), std::string::npos)
        << e;
  }
  {
    const std::string e = ErrorOf(WriteFile(
        dir, "c.yaml",
        "cam0:\n  resolution: [752, 480]\n  proj_model: omni\n  proj_params: [1, 1, 0, 0]\n"));
    EXPECT_NE(e.find("c.yaml:3: field 'cam0.proj_model'"), std::string::npos) << e;
  }
  {
    const std::string e = ErrorOf(
        WriteFile(dir, "d.yaml",
                  "T_cam0_cam1:\n  rows: 4\n  cols: 4\n  data: [1, 0, 0, 0, 0, 2, 0, 0, 0, 0, "
                  "1, 0, 0, 0, 0, 1]\n"));
    EXPECT_NE(e.find("d.yaml:2: field 'T_cam0_cam1': not a rigid transform"), std::string::npos)
        << e;
  }
  {
    const std::string e = ErrorOf(WriteFile(dir, "e.yaml", "imu0:\n  sigma_g_c: 0.001\n"));
    EXPECT_NE(e.find("field 'sigma_gw_c': missing"), std::string::npos) << e;
  }
  {
    // A lone camera sensor.yaml outside a camN/ folder: which camera is it?
    const std::string path = WriteFile(dir, "left/sensor.yaml",
                                       "sensor_type: camera\nresolution: [752, 480]\n"
                                       "intrinsics: [458, 457, 367, 248]\n");
    EXPECT_NE(ErrorOf(path).find("say which camera with camN="), std::string::npos);
    EXPECT_EQ(ReadCalibrationSource(path, 1).cameras.count(1), 1u);
  }
  {
    // A complex key (YAML `? ...`): found by fuzz_calibration, where yaml-cpp's "bad conversion"
    // escaped as an internal error.
    const std::string e = ErrorOf(
        WriteFile(dir, "g.yaml", "settings:\n  verbose: true\n? {a: 1}\n: 2\nimu0:\n  rate: 1\n"));
    EXPECT_NE(e.find("g.yaml:3: a key must be a single value, found a map"), std::string::npos)
        << e;
  }
  EXPECT_NE(ErrorOf(WriteFile(dir, "f.yaml", "settings: {verbose: true}\n"))
                .find("holds no camera, IMU or aprilgrid calibration"),
            std::string::npos);
  EXPECT_NE(ErrorOf(dir + "/absent.yaml").find("does not exist"), std::string::npos);
  EXPECT_NE(ErrorOf(dir + "/left").find("no calibration here"), std::string::npos);
}

}  // namespace
}  // namespace mavloc
