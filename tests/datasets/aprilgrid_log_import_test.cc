// Assembling a dataset from an aprilgrid calibration log: the real EuRoC imu_april log (counts,
// calibration provenance, EuRoC's T_BS), and small logs written here for the order in which
// T_B_C is found (direct, composed through cam0, guessed) and for every missing-input error.
#include "datasets/io/aprilgrid_log_import.h"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "core/errors.h"
#include "core/rotation.h"
#include "datasets/io/aprilgrid_target_io.h"
#include "tests/test_support.h"

namespace fs = std::filesystem;

namespace mavloc {
namespace {

std::string Data() { return testing::SharedDataDir(); }

TEST(AprilgridLogImport, RealImuAprilLogWithEurocExtrinsics) {
  REQUIRE_SHARED_DATA();
  AprilgridLogInputs inputs;
  inputs.imu_csv = Data() + "/euroc_imu_april/imu0.csv";
  inputs.configs = {Data() + "/euroc_imu_april/config.yaml"};
  inputs.corners = {"cam0=" + Data() + "/euroc_imu_april/cam0",
                    "cam1=" + Data() + "/euroc_imu_april/cam1"};
  inputs.extrinsics = {Data() + "/euroc_v1_01_easy/mav0"};
  const AprilgridLogImport r = ImportAprilgridLog(inputs);
  const Dataset& d = r.dataset;
  EXPECT_EQ(d.imu.samples.size(), 14374u);
  EXPECT_DOUBLE_EQ(d.imu.rate_hz, 200.0);
  EXPECT_DOUBLE_EQ(d.imu.noise.gyroscope_noise_density, 1.6968e-04);
  EXPECT_DOUBLE_EQ(d.imu.noise.accelerometer_random_walk, 0.003);
  ASSERT_EQ(d.cameras.size(), 2u);
  ASSERT_EQ(r.cameras.size(), 2u);
  for (int n : {0, 1}) {
    const CameraSensor& c = d.cameras[n];
    EXPECT_EQ(c.name, fmt::format("cam{}", n));
    EXPECT_EQ(c.frames.size(), 1439u);
    EXPECT_DOUBLE_EQ(c.rate_hz, 20.0);  // EuRoC's sensor.yaml is not an intrinsics source here
    EXPECT_EQ(r.cameras[n].stats.empty_frames, 23);
    EXPECT_TRUE(r.cameras[n].T_B_C_known);
    EXPECT_NE(r.cameras[n].T_B_C_from.find("T_BS"), std::string::npos);
    EXPECT_NE(r.cameras[n].intrinsics_from.find("config.yaml"), std::string::npos);
  }
  EXPECT_DOUBLE_EQ(d.cameras[0].model.fu(), 458.654);
  EXPECT_DOUBLE_EQ(d.cameras[1].model.cu(), 379.999);
  EXPECT_NEAR(d.cameras[0].T_B_C.p.x(), -0.0216401454975, 1e-12);
  EXPECT_NEAR(d.cameras[1].T_B_C.p.y(), 0.0453689425024, 1e-12);
  EXPECT_EQ(static_cast<long>(d.tags.size()), r.cameras[0].stats.tags);
  EXPECT_EQ(static_cast<long>(d.tags1.size()), r.cameras[1].stats.tags);
  EXPECT_GT(d.tags.size(), 30000u);
  EXPECT_EQ(d.tags1.front().camera, 1);
  // The map: the 36 tags in the board frame, and the grid itself.
  EXPECT_EQ(d.map.frame, MapFrame::kBoard);
  ASSERT_EQ(d.map.tags.size(), 36u);
  EXPECT_NEAR(d.map.tags.at(35).T_W_T.p.x(), 5 * 0.1144 + 0.044, 1e-12);
  ASSERT_TRUE(AprilgridFromMap(d.map).has_value());
  EXPECT_EQ(AprilgridFromMap(d.map)->tag_cols, 6);
  // config.yaml's T_cam0_cam1 is compared with EuRoC's two T_BS in the notes.
  bool compared = false;
  for (const auto& note : r.notes) compared |= note.find("cam1: pose in cam0") != std::string::npos;
  EXPECT_TRUE(compared);
  EXPECT_NE(r.ImportYaml().find("empty_frames: 23"), std::string::npos);
}

// A small log in a temp folder: 3 frames of cam0 and cam1, an IMU around them, a yac config.
class SmallLog : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = testing::MakeTempDir();
    std::ofstream imu(dir_ + "/imu.csv");
    imu << "#ts,wx,wy,wz,ax,ay,az\n";
    for (int i = 0; i <= 40; ++i) imu << 1000000000 + i * 5000000 << ",0,0,0,0,0,9.81\n";
    imu.close();
    for (const char* camera : {"cam0", "cam1"}) {
      fs::create_directories(dir_ + "/" + camera);
      for (int k = 0; k < 3; ++k) {
        const long long ts = 1000000000 + k * 50000000;
        std::ofstream file(fmt::format("{}/{}/{}.csv", dir_, camera, ts));
        file << "#ts,tag_rows,tag_cols,tag_size,tag_spacing,kp_x,kp_y,p_x,p_y,p_z,tag_id,"
                "corner_idx\n";
        if (k == 1) continue;  // an empty frame
        for (int c = 0; c < 4; ++c) {
          const Eigen::Vector3d p = AprilgridCorner({2, 2, 0.1, 0.5}, 3, c);
          file << fmt::format("{},2,2,0.1,0.5,{},{},{},{},0,3,{}\n", ts, 10 + c, 20 + c, p.x(),
                              p.y(), c);
        }
      }
    }
    WriteConfig("config.yaml", true);
    // EuRoC-style sensor.yaml files with T_BS (identity rotation, translations of 1 and 2 cm).
    for (int n : {0, 1}) {
      fs::create_directories(fmt::format("{}/euroc/cam{}", dir_, n));
      std::ofstream(fmt::format("{}/euroc/cam{}/sensor.yaml", dir_, n))
          << "sensor_type: camera\nT_BS:\n  rows: 4\n  cols: 4\n  data: [1, 0, 0, "
          << 0.01 * (n + 1)
          << ", 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]\nrate_hz: 20\nresolution: [640, 480]\n"
             "camera_model: pinhole\nintrinsics: [300, 300, 320, 240]\n"
             "distortion_model: radial-tangential\ndistortion_coefficients: [0, 0, 0, 0]\n";
    }
  }

  void WriteConfig(const std::string& name, bool with_cam1, bool with_imu = true,
                   bool with_target = true) {
    std::ofstream config(dir_ + "/" + name);
    if (with_target)
      config << "calib_target:\n  target_type: 'aprilgrid'\n  tag_rows: 2\n  tag_cols: 2\n"
                "  tag_size: 0.1\n  tag_spacing: 0.5\n";
    if (with_imu)
      config << "imu0:\n  rate: 200.0\n  sigma_a_c: 0.002\n  sigma_g_c: 1.7e-04\n"
                "  sigma_aw_c: 0.003\n  sigma_gw_c: 2.0e-05\n";
    for (int n = 0; n < (with_cam1 ? 2 : 1); ++n)
      config << "cam" << n
             << ":\n  resolution: [752, 480]\n  proj_model: pinhole\n  dist_model: radtan4\n"
                "  proj_params: [458.0, 457.0, 367.0, 248.0]\n  dist_params: [-0.28, 0.07, 0, 0]\n";
    config << "T_cam0_cam1:\n  rows: 4\n  cols: 4\n  data: [1, 0, 0, 0.11, 0, 1, 0, 0, 0, 0, 1, "
              "0, 0, 0, 0, 1]\n";
  }

  AprilgridLogInputs Inputs() const {
    AprilgridLogInputs inputs;
    inputs.imu_csv = dir_ + "/imu.csv";
    inputs.configs = {dir_ + "/config.yaml"};
    inputs.corners = {"cam0=" + dir_ + "/cam0", "cam1=" + dir_ + "/cam1"};
    return inputs;
  }

  std::string ErrorOf(const AprilgridLogInputs& inputs) const {
    try {
      ImportAprilgridLog(inputs);
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  }

  std::string dir_;
};

TEST_F(SmallLog, CountsFramesTagsAndEmptyFrames) {
  const AprilgridLogImport r = ImportAprilgridLog(Inputs());
  EXPECT_EQ(r.cameras[0].stats.frames, 3);
  EXPECT_EQ(r.cameras[0].stats.empty_frames, 1);
  EXPECT_EQ(r.cameras[1].stats.tags, 2);
  EXPECT_EQ(r.dataset.tags.size(), 2u);
  EXPECT_EQ(r.dataset.tags1.size(), 2u);
  EXPECT_EQ(r.dataset.cameras[0].frames.size(), 3u);
  EXPECT_DOUBLE_EQ(r.dataset.cameras[0].rate_hz, 20.0);  // from the frame stamps
  EXPECT_DOUBLE_EQ(r.dataset.imu.rate_hz, 200.0);
  EXPECT_EQ(r.dataset.map.tags.size(), 4u);
}

TEST_F(SmallLog, TransformsFoundDirectlyComposedOrGuessed) {
  // No camera-IMU extrinsics: cam0 identity, cam1 its pose in cam0; both said to be guesses.
  {
    const AprilgridLogImport r = ImportAprilgridLog(Inputs());
    EXPECT_FALSE(r.cameras[0].T_B_C_known);
    EXPECT_FALSE(r.cameras[1].T_B_C_known);
    EXPECT_TRUE(r.dataset.cameras[0].T_B_C.p.isZero());
    EXPECT_NEAR(r.dataset.cameras[1].T_B_C.p.x(), 0.11, 1e-15);
    int guesses = 0;
    for (const auto& note : r.notes) guesses += note.find("T_B_C unknown") != std::string::npos;
    EXPECT_EQ(guesses, 2);  // one note per camera
  }
  // cam0's T_BS only: cam1 = T_B_C0 * T_C0_C1.
  {
    AprilgridLogInputs inputs = Inputs();
    inputs.extrinsics = {dir_ + "/euroc/cam0/sensor.yaml"};
    const AprilgridLogImport r = ImportAprilgridLog(inputs);
    EXPECT_TRUE(r.cameras[1].T_B_C_known);
    EXPECT_NEAR(r.dataset.cameras[0].T_B_C.p.x(), 0.01, 1e-15);
    EXPECT_NEAR(r.dataset.cameras[1].T_B_C.p.x(), 0.12, 1e-15);
    EXPECT_NE(r.cameras[1].T_B_C_from.find("composed with"), std::string::npos);
    // Extrinsics sources give no intrinsics: the models are config.yaml's, not the sensor.yaml's.
    EXPECT_DOUBLE_EQ(r.dataset.cameras[0].model.fu(), 458.0);
  }
  // Both T_BS: used directly, and compared with T_cam0_cam1 (1 cm vs 11 cm: 100 mm apart).
  {
    AprilgridLogInputs inputs = Inputs();
    inputs.extrinsics = {dir_ + "/euroc"};
    const AprilgridLogImport r = ImportAprilgridLog(inputs);
    EXPECT_NEAR(r.dataset.cameras[1].T_B_C.p.x(), 0.02, 1e-15);
    bool compared = false;
    for (const auto& note : r.notes)
      compared |= note.find("100.000 mm, 0.00000 deg apart") != std::string::npos;
    EXPECT_TRUE(compared);
  }
  // --intrinsics wins over --config; a camN= prefix picks one camera of a folder.
  {
    AprilgridLogInputs inputs = Inputs();
    inputs.intrinsics = {"cam1=" + dir_ + "/euroc"};
    const AprilgridLogImport r = ImportAprilgridLog(inputs);
    EXPECT_DOUBLE_EQ(r.dataset.cameras[0].model.fu(), 458.0);
    EXPECT_DOUBLE_EQ(r.dataset.cameras[1].model.fu(), 300.0);
    EXPECT_EQ(r.dataset.cameras[1].model.width(), 640);
  }
}

TEST_F(SmallLog, OnlyCam1KeepsItsIndex) {
  AprilgridLogInputs inputs = Inputs();
  inputs.corners = {"cam1=" + dir_ + "/cam1"};
  const AprilgridLogImport r = ImportAprilgridLog(inputs);
  ASSERT_EQ(r.dataset.cameras.size(), 2u);
  EXPECT_TRUE(r.dataset.cameras[0].frames.empty());
  EXPECT_EQ(r.dataset.cameras[1].frames.size(), 3u);
  EXPECT_TRUE(r.dataset.tags.empty());
  EXPECT_EQ(r.dataset.tags1.size(), 2u);
}

TEST_F(SmallLog, MissingInputsAreNamed) {
  {  // cam1 has corners but no source describes it
    WriteConfig("cam0_only.yaml", false);
    AprilgridLogInputs inputs = Inputs();
    inputs.configs = {dir_ + "/cam0_only.yaml"};
    const std::string e = ErrorOf(inputs);
    EXPECT_NE(e.find(dir_ + "/cam1: cam1 has corners but no intrinsics"), std::string::npos) << e;
  }
  {
    WriteConfig("no_imu.yaml", true, false);
    AprilgridLogInputs inputs = Inputs();
    inputs.configs = {dir_ + "/no_imu.yaml"};
    EXPECT_NE(ErrorOf(inputs).find("no IMU noise densities"), std::string::npos);
  }
  {
    WriteConfig("no_target.yaml", true, true, false);
    AprilgridLogInputs inputs = Inputs();
    inputs.configs = {dir_ + "/no_target.yaml"};
    EXPECT_NE(ErrorOf(inputs).find("no aprilgrid description"), std::string::npos);
  }
  {
    AprilgridLogInputs inputs = Inputs();
    inputs.corners.push_back("cam2=" + dir_ + "/cam1");
    EXPECT_NE(ErrorOf(inputs).find("cam0 and cam1 only"), std::string::npos);
    inputs.corners.back() = "cam0=" + dir_ + "/cam1";
    EXPECT_NE(ErrorOf(inputs).find("cam0 has two corner folders"), std::string::npos);
  }
  {  // the IMU does not cover the frames
    std::ofstream(dir_ + "/late_imu.csv") << "#ts,wx,wy,wz,ax,ay,az\n5000000000,0,0,0,0,0,9.81\n"
                                             "5005000000,0,0,0,0,0,9.81\n";
    AprilgridLogInputs inputs = Inputs();
    inputs.imu_csv = dir_ + "/late_imu.csv";
    EXPECT_NE(ErrorOf(inputs).find("lies within the IMU's time range"), std::string::npos);
  }
  {  // a corner file whose grid point disagrees with the target (0.1 m tags, not 0.12)
    AprilgridLogInputs inputs = Inputs();
    std::ofstream(dir_ + "/t.yaml") << "tagRows: 2\ntagCols: 2\ntagSize: 0.12\ntagSpacing: 0.5\n";
    inputs.target = {dir_ + "/t.yaml"};
    const std::string e = ErrorOf(inputs);
    EXPECT_NE(e.find("cam0/1000000000.csv:2: field 'tag_size'"), std::string::npos) << e;
  }
}

}  // namespace
}  // namespace mavloc
