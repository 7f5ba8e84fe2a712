// Reading the real EuRoC excerpt in ../shared/data, writing and reading back, and every bad-input
// case with its file:line and field in the message.
#include "datasets/io/euroc_io.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <functional>

#include "core/errors.h"
#include "datasets/io/tum_io.h"
#include "tests/test_support.h"

namespace fs = std::filesystem;

namespace mavloc {
namespace {

std::string Euroc() { return testing::SharedDataDir() + "/euroc_v1_01_easy"; }

TEST(EurocReader, LoadsTheV101EasyExcerpt) {
  REQUIRE_SHARED_DATA();
  const Dataset d = ReadEurocDataset(Euroc());
  // imu0: the whole V1_01_easy stream, 200 Hz, 29,120 rows.
  ASSERT_EQ(d.imu.samples.size(), 29120u);
  EXPECT_EQ(d.imu.samples.front().t_ns, 1403715273262142976);
  EXPECT_NEAR(d.imu.samples.front().accel_m_s2.x(), 9.0874956666666655, 1e-12);
  EXPECT_NEAR(NsToSeconds(d.imu.samples.back().t_ns - d.imu.samples.front().t_ns), 145.6, 0.01);
  EXPECT_DOUBLE_EQ(d.imu.rate_hz, 200.0);
  EXPECT_DOUBLE_EQ(d.imu.noise.gyroscope_noise_density, 1.6968e-04);
  EXPECT_DOUBLE_EQ(d.imu.noise.accelerometer_random_walk, 3.0e-3);
  // Ground truth: the first 999 rows, starting about 1 s after the first image.
  ASSERT_EQ(d.ground_truth.size(), 999u);
  EXPECT_EQ(d.ground_truth.front().t_ns, 1403715274302142976);
  EXPECT_NEAR(d.ground_truth.front().T_W_B.p.x(), 0.878612, 1e-12);
  EXPECT_NEAR(d.ground_truth.front().T_W_B.q.w(), 0.060514, 1e-6);
  EXPECT_NEAR(d.ground_truth.front().b_a.y(), 0.547666, 1e-12);
  EXPECT_NEAR(NsToSeconds(d.ground_truth.back().t_ns - d.ground_truth.front().t_ns), 4.99, 0.01);
  // cam0: 95 frames, all present; calibration from sensor.yaml (with a %YAML:1.0 first line).
  ASSERT_EQ(d.cameras.size(), 2u);
  const CameraSensor* cam0 = d.Camera("cam0");
  ASSERT_NE(cam0, nullptr);
  EXPECT_EQ(cam0->frames.size(), 95u);
  EXPECT_TRUE(cam0->missing_images.empty());
  EXPECT_EQ(cam0->frames.front().t_ns, 1403715273262142976);
  EXPECT_EQ(cam0->model.width(), 752);
  EXPECT_EQ(cam0->model.height(), 480);
  EXPECT_DOUBLE_EQ(cam0->model.fu(), 458.654);
  EXPECT_DOUBLE_EQ(cam0->model.cv(), 248.375);
  EXPECT_EQ(cam0->model.distortion_model(), DistortionModel::kRadialTangential);
  EXPECT_DOUBLE_EQ(cam0->model.distortion()[0], -0.28340811);
  EXPECT_NEAR(cam0->T_B_C.p.x(), -0.0216401454975, 1e-12);
  EXPECT_NEAR(cam0->T_B_C.R()(0, 1), -0.999880929698, 1e-9);
  EXPECT_DOUBLE_EQ(cam0->rate_hz, 20.0);
  // cam1 lists 99 images of which only 10 exist: reported, not fatal.
  const CameraSensor* cam1 = d.Camera("cam1");
  ASSERT_NE(cam1, nullptr);
  EXPECT_EQ(cam1->frames.size(), 99u);
  EXPECT_EQ(cam1->missing_images.size(), 89u);
}

TEST(EurocReader, SensorYamlWithoutTheOpenCvDirective) {
  REQUIRE_SHARED_DATA();
  const std::string dir = testing::MakeTempDir();
  fs::create_directories(dir + "/mav0/imu0");
  fs::create_directories(dir + "/mav0/cam0");
  fs::copy_file(Euroc() + "/mav0/imu0/data.csv", dir + "/mav0/imu0/data.csv");
  // Original EuRoC files have no %YAML:1.0 line.
  std::ifstream in(Euroc() + "/mav0/cam0/sensor.yaml");
  std::ofstream out(dir + "/mav0/cam0/sensor.yaml");
  std::string line;
  std::getline(in, line);
  ASSERT_EQ(line.rfind("%YAML", 0), 0u);
  out << in.rdbuf();
  out.close();
  const Dataset d = ReadEurocDataset(dir);
  ASSERT_EQ(d.cameras.size(), 1u);
  EXPECT_DOUBLE_EQ(d.cameras[0].model.fv(), 457.296);
}

TEST(TumReader, ReadsTheFullGroundTruth) {
  REQUIRE_SHARED_DATA();
  const auto poses = ReadTumTrajectory(Euroc() + "/groundtruth_full_tum.txt");
  ASSERT_EQ(poses.size(), 28712u);
  EXPECT_EQ(poses.front().t_ns, 1403715274302140000);  // exact decimal conversion
  EXPECT_NEAR(poses.front().T_W_B.q.w(), 0.060514, 1e-6);
  EXPECT_NEAR(poses.front().T_W_B.q.x(), -0.828459, 1e-6);
}

Dataset SmallDataset() {
  Dataset d;
  d.imu.rate_hz = 100;
  d.imu.noise = {1e-3, 1e-4, 1e-2, 1e-3};
  d.imu.gyroscope_bias_sigma = 0.002;
  for (int i = 0; i < 5; ++i)
    d.imu.samples.push_back(
        {1000 + i * 10'000'000, Eigen::Vector3d(0.1 * i, 0.2, 0.3), Eigen::Vector3d(0, 0, 9.81)});
  GroundTruthState gt;
  gt.t_ns = 1000;
  gt.T_W_B = Pose(Eigen::Quaterniond(0.5, 0.5, 0.5, 0.5), Eigen::Vector3d(1, 2, 3));
  gt.v_W = {0.1, 0.2, 0.3};
  d.ground_truth = {gt};
  d.features = {{1000, 1, {0.1, 0.2}}, {1000, 2, {0.3, 0.4}}};
  d.laser = {{1000, {0.01, -0.02}}};
  TagObservation tag;
  tag.t_ns = 1000;
  tag.tag_id = 3;
  tag.corners_px = {Eigen::Vector2d(1, 2), Eigen::Vector2d(3, 4), Eigen::Vector2d(5, 6),
                    Eigen::Vector2d(7, 8)};
  d.tags = {tag};
  d.map.landmarks_W = {{1, {0, 0, 0}}, {2, {0.1, 0, 0}}};
  d.map.tags[3] = {3, 0.16, Pose(Eigen::Quaterniond::Identity(), Eigen::Vector3d(1, 1, 0))};
  d.map.plane = Plane{Eigen::Vector3d(0, 0, 1), 0.5};
  d.map.parameters["D"] = 0.1;
  d.truth_quantities = QuantityTable({"d", "alpha"}, {"m", "rad"});
  d.truth_quantities.Append(1000, {1.5, 0.39});
  CameraSensor cam;
  cam.name = "cam0";
  cam.rate_hz = 10;
  cam.model = CameraModel(640, 480, Eigen::Vector4d(400, 401, 320, 240),
                          DistortionModel::kEquidistant, {0.01, 0.02, 0.03, 0.04});
  cam.T_B_C = Pose(Eigen::Quaterniond(0, 1, 0, 0), Eigen::Vector3d(0.1, 0, 0));
  cam.frames = {{1000, "/nonexistent/1000.png"}};
  d.cameras = {cam};
  d.scenario = "unit";
  d.scenario_info = {{"seed", "7"}};
  return d;
}

TEST(EurocWriter, RoundTrip) {
  const std::string dir = testing::MakeTempDir();
  const Dataset in = SmallDataset();
  WriteEurocDataset(in, dir);
  const Dataset out = ReadEurocDataset(dir);
  ASSERT_EQ(out.imu.samples.size(), 5u);
  EXPECT_EQ(out.imu.samples[3].t_ns, in.imu.samples[3].t_ns);
  EXPECT_TRUE(out.imu.samples[3].gyro_rad_s.isApprox(in.imu.samples[3].gyro_rad_s));
  EXPECT_DOUBLE_EQ(out.imu.noise.gyroscope_random_walk, 1e-4);
  // The turn-on bias sigmas (mavloc's sensor.yaml keys) round-trip, and stay unset when absent.
  EXPECT_EQ(out.imu.gyroscope_bias_sigma, std::optional<double>(0.002));
  EXPECT_EQ(out.imu.accelerometer_bias_sigma, std::nullopt);
  ASSERT_EQ(out.ground_truth.size(), 1u);
  EXPECT_TRUE(out.ground_truth[0].T_W_B.p.isApprox(in.ground_truth[0].T_W_B.p));
  EXPECT_TRUE(out.ground_truth[0].T_W_B.q.isApprox(in.ground_truth[0].T_W_B.q));
  EXPECT_TRUE(out.ground_truth[0].v_W.isApprox(in.ground_truth[0].v_W));
  ASSERT_EQ(out.features.size(), 2u);
  EXPECT_EQ(out.features[1].landmark_id, 2);
  ASSERT_EQ(out.laser.size(), 1u);
  ASSERT_EQ(out.tags.size(), 1u);
  EXPECT_EQ(out.tags[0].tag_id, 3);
  EXPECT_TRUE(out.tags[0].corners_px[3].isApprox(Eigen::Vector2d(7, 8)));
  EXPECT_EQ(out.map.landmarks_W.size(), 2u);
  ASSERT_EQ(out.map.tags.count(3), 1u);
  EXPECT_DOUBLE_EQ(out.map.tags.at(3).size_m, 0.16);
  ASSERT_TRUE(out.map.plane.has_value());
  EXPECT_DOUBLE_EQ(out.map.plane->d_m, 0.5);
  EXPECT_DOUBLE_EQ(out.map.parameters.at("D"), 0.1);
  ASSERT_EQ(out.truth_quantities.names, (std::vector<std::string>{"d", "alpha"}));
  EXPECT_EQ(out.truth_quantities.units[1], "rad");
  ASSERT_EQ(out.cameras.size(), 1u);
  EXPECT_EQ(out.cameras[0].model.distortion_model(), DistortionModel::kEquidistant);
  EXPECT_DOUBLE_EQ(out.cameras[0].model.distortion()[3], 0.04);
  EXPECT_TRUE(out.cameras[0].T_B_C.q.isApprox(in.cameras[0].T_B_C.q) ||
              out.cameras[0].T_B_C.q.isApprox(Eigen::Quaterniond(-in.cameras[0].T_B_C.q.coeffs())));
  EXPECT_EQ(out.cameras[0].missing_images.size(), 1u);
  EXPECT_EQ(out.scenario, "unit");
  EXPECT_EQ(out.scenario_info.at("seed"), "7");
  // Writing is deterministic: the same dataset gives the same bytes.
  const std::string dir2 = dir + "_again";
  fs::remove_all(dir2);
  fs::create_directories(dir2);
  WriteEurocDataset(in, dir2);
  for (const char* file :
       {"/mav0/imu0/data.csv", "/mav0/state_groundtruth_estimate0/data.csv", "/map.yaml"}) {
    std::ifstream a(dir + file), b(dir2 + file);
    EXPECT_EQ(std::string(std::istreambuf_iterator<char>(a), {}),
              std::string(std::istreambuf_iterator<char>(b), {}));
  }
  // No temporary files are left behind.
  for (const auto& entry : fs::recursive_directory_iterator(dir))
    EXPECT_EQ(entry.path().string().find(".tmp-"), std::string::npos) << entry.path();
}

// ---- bad input: one InputError naming file, line and field ----

std::string WriteImuCsv(const std::string& body) {
  const std::string dir = testing::MakeTempDir();
  fs::create_directories(dir + "/mav0/imu0");
  std::ofstream(dir + "/mav0/imu0/data.csv")
      << "#timestamp [ns],w_RS_S_x [rad s^-1],w_RS_S_y [rad s^-1],w_RS_S_z [rad s^-1],"
         "a_RS_S_x [m s^-2],a_RS_S_y [m s^-2],a_RS_S_z [m s^-2]\n"
      << body;
  return dir;
}

std::string ErrorOf(const std::string& dir) {
  try {
    ReadEurocDataset(dir);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(EurocReaderBadInput, MalformedRowNamesFileLineAndField) {
  const std::string dir = WriteImuCsv("1,0,0,0,0,0,9.81\n2,0,0,abc,0,0,9.81\n");
  const std::string error = ErrorOf(dir);
  EXPECT_NE(error.find("imu0/data.csv:3"), std::string::npos) << error;
  EXPECT_NE(error.find("w_RS_S_z [rad s^-1]"), std::string::npos) << error;
  EXPECT_NE(error.find("'abc' is not a number"), std::string::npos) << error;
}

TEST(EurocReaderBadInput, MissingField) {
  const std::string error = ErrorOf(WriteImuCsv("1,0,0,0,0,0,9.81\n2,0,0,0,0\n"));
  EXPECT_NE(error.find("data.csv:3"), std::string::npos) << error;
  EXPECT_NE(error.find("expected 7 fields, found 5"), std::string::npos) << error;
}

TEST(EurocReaderBadInput, NonMonotonicTimestamps) {
  const std::string error = ErrorOf(WriteImuCsv("5,0,0,0,0,0,9.81\n4,0,0,0,0,0,9.81\n"));
  EXPECT_NE(error.find("data.csv:3"), std::string::npos) << error;
  EXPECT_NE(error.find("earlier than the previous"), std::string::npos) << error;
}

TEST(EurocReaderBadInput, DuplicateTimestamps) {
  const std::string error = ErrorOf(WriteImuCsv("5,0,0,0,0,0,9.81\n5,0,0,0,0,0,9.81\n"));
  EXPECT_NE(error.find("data.csv:3"), std::string::npos) << error;
  EXPECT_NE(error.find("duplicate timestamp 5"), std::string::npos) << error;
}

TEST(EurocReaderBadInput, NanAndInf) {
  for (const char* value : {"nan", "inf", "-inf", "1e999"}) {
    const std::string error = ErrorOf(WriteImuCsv(std::string("1,0,0,0,0,") + value + ",9.81\n"));
    EXPECT_NE(error.find("data.csv:2"), std::string::npos) << error;
    EXPECT_NE(error.find("a_RS_S_y [m s^-2]"), std::string::npos) << error;
    EXPECT_NE(error.find("not finite"), std::string::npos) << value << ": " << error;
  }
}

TEST(EurocReaderBadInput, EmptyFile) {
  const std::string error = ErrorOf(WriteImuCsv(""));
  EXPECT_NE(error.find("imu0/data.csv"), std::string::npos) << error;
  EXPECT_NE(error.find("no data rows"), std::string::npos) << error;
}

TEST(EurocReaderBadInput, MissingFolders) {
  EXPECT_NE(ErrorOf("/nonexistent/dataset").find("dataset folder does not exist"),
            std::string::npos);
  const std::string dir = testing::MakeTempDir();
  EXPECT_NE(ErrorOf(dir).find("no mav0/ folder"), std::string::npos);
}

TEST(EurocReaderBadInput, NegativeBiasSigma) {
  const std::string dir = WriteImuCsv("1,0,0,0,0,0,9.81\n");
  std::ofstream(dir + "/mav0/imu0/sensor.yaml") << "rate_hz: 200\naccelerometer_bias_sigma: -0.1\n";
  const std::string error = ErrorOf(dir);
  EXPECT_NE(error.find("imu0/sensor.yaml:2: field 'accelerometer_bias_sigma'"), std::string::npos)
      << error;
  EXPECT_NE(error.find("-0.1 is outside [0, 200] m/s^2"), std::string::npos) << error;
}

TEST(EurocReaderBadInput, BadSensorYamlField) {
  const std::string dir = WriteImuCsv("1,0,0,0,0,0,9.81\n");
  fs::create_directories(dir + "/mav0/cam0");
  std::ofstream(dir + "/mav0/cam0/sensor.yaml")
      << "T_BS:\n  cols: 4\n  rows: 4\n  data: [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1]\n"
         "resolution: [752, 480]\nintrinsics: [1, 2, x, 4]\n";
  const std::string error = ErrorOf(dir);
  EXPECT_NE(error.find("cam0/sensor.yaml"), std::string::npos) << error;
  EXPECT_NE(error.find("intrinsics"), std::string::npos) << error;
}

TEST(TumReaderBadInput, Cases) {
  const std::string dir = testing::MakeTempDir();
  auto error_of = [&](const std::string& body) {
    std::ofstream(dir + "/t.txt") << body;
    try {
      ReadTumTrajectory(dir + "/t.txt");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(error_of("# only a comment\n").find("no data rows"), std::string::npos);
  EXPECT_NE(error_of("1.0 0 0 0 0 0 0 1\n1.0 0 0 0 0 0 0 1\n").find("t.txt:2"), std::string::npos);
  EXPECT_NE(error_of("1.0 0 0 nan 0 0 0 1\n").find("field 'tz'"), std::string::npos);
  EXPECT_NE(error_of("1.0 0 0 0 0 0 0\n").find("expected 8 fields"), std::string::npos);
  EXPECT_NE(error_of("1.0 0 0 0 0 0 0 3\n").find("not unit length"), std::string::npos);
}

TEST(TumWriter, RoundTripKeepsNanoseconds) {
  const std::string dir = testing::MakeTempDir();
  std::vector<StampedPose> poses = {
      {1403715274302142976,
       Pose(Eigen::Quaterniond(0.5, -0.5, 0.5, 0.5), Eigen::Vector3d(1, 2, 3))},
      {1403715274307142912, Pose()}};
  WriteTumTrajectory(poses, dir + "/t.txt");
  const auto back = ReadTumTrajectory(dir + "/t.txt");
  ASSERT_EQ(back.size(), 2u);
  EXPECT_EQ(back[0].t_ns, poses[0].t_ns);
  EXPECT_EQ(back[1].t_ns, poses[1].t_ns);
  EXPECT_TRUE(back[0].T_W_B.q.isApprox(poses[0].T_W_B.q, 1e-12));
}

// ---- tags1 (cam1), map frame, atomic folder writes, the yac IMU CSV ----

TEST(EurocWriter, Tags1AndBoardFrameRoundTrip) {
  const std::string dir = testing::MakeTempDir();
  Dataset in = SmallDataset();
  TagObservation right = in.tags[0];
  right.camera = 1;
  right.tag_id = 5;
  right.corners_px[2] = {50.25, 60.5};
  in.tags1 = {right};
  in.map.tags[5] = {5, 0.16, Pose(Eigen::Quaterniond::Identity(), Eigen::Vector3d(2, 1, 0))};
  CameraSensor cam1 = in.cameras[0];
  cam1.name = "cam1";
  cam1.frames = {};
  in.cameras.push_back(cam1);
  in.map.frame = MapFrame::kBoard;
  WriteEurocDataset(in, dir);
  const Dataset out = ReadEurocDataset(dir);
  ASSERT_EQ(out.tags.size(), 1u);
  EXPECT_EQ(out.tags[0].camera, 0);
  ASSERT_EQ(out.tags1.size(), 1u);
  EXPECT_EQ(out.tags1[0].camera, 1);
  EXPECT_EQ(out.tags1[0].tag_id, 5);
  EXPECT_EQ(out.tags1[0].t_ns, 1000);
  EXPECT_TRUE(out.tags1[0].corners_px[2].isApprox(Eigen::Vector2d(50.25, 60.5)));
  EXPECT_EQ(out.map.frame, MapFrame::kBoard);
  ASSERT_EQ(out.cameras.size(), 2u);
  EXPECT_EQ(out.cameras[1].name, "cam1");
  EXPECT_TRUE(out.cameras[1].frames.empty());
  // A world map writes no frame key and reads back as world; so does a map.yaml without one.
  in.map.frame = MapFrame::kWorld;
  in.tags1.clear();
  const std::string dir2 = dir + "_world";
  fs::remove_all(dir2);
  fs::create_directories(dir2);
  WriteEurocDataset(in, dir2);
  std::ifstream map(dir2 + "/map.yaml");
  EXPECT_EQ(std::string(std::istreambuf_iterator<char>(map), {}).find("\nframe:"),
            std::string::npos);
  const Dataset world = ReadEurocDataset(dir2);
  EXPECT_EQ(world.map.frame, MapFrame::kWorld);
  EXPECT_TRUE(world.tags1.empty());
  EXPECT_FALSE(fs::exists(dir2 + "/mav0/tags1"));
  std::ofstream(dir2 + "/map.yaml") << "frame: world\n";
  EXPECT_EQ(ReadEurocDataset(dir2).map.frame, MapFrame::kWorld);
}

TEST(EurocReaderBadInput, UnknownMapFrameAndBadTags1Row) {
  const std::string dir = WriteImuCsv("1,0,0,0,0,0,9.81\n");
  std::ofstream(dir + "/map.yaml") << "# map\nframe: ceiling\n";
  std::string error = ErrorOf(dir);
  EXPECT_NE(error.find("map.yaml:2: field 'frame': 'ceiling' is not a map frame"),
            std::string::npos)
      << error;
  fs::remove(dir + "/map.yaml");
  fs::create_directories(dir + "/mav0/tags1");
  std::ofstream(dir + "/mav0/tags1/data.csv") << "#timestamp [ns],tag_id,u0,v0,u1,v1,u2,v2,u3,v3\n"
                                                 "5,1,0,0,1,0,1,1,0,nan\n";
  error = ErrorOf(dir);
  EXPECT_NE(error.find("tags1/data.csv:2: field 'v3'"), std::string::npos) << error;
}

// Silent degradation on the ASL reader: each mutation of a written dataset would otherwise load
// without a word (an estimator then failing on every frame, or a column or coefficient dropped);
// each is refused naming the file and the field.
TEST(EurocReaderBadInput, SilentDegradationIsRefused) {
  struct Case {
    const char* name;
    std::function<void(const std::string& dir)> mutate;
    const char* file;
    const char* message;
  };
  const auto rewrite = [](const std::string& path, const std::string& text) {
    std::ofstream(path, std::ios::trunc) << text;
  };
  const auto replace_in = [](const std::string& path, const std::string& from,
                             const std::string& to) {
    std::ifstream in(path);
    std::string text((std::istreambuf_iterator<char>(in)), {});
    const auto at = text.find(from);
    ASSERT_NE(at, std::string::npos) << path << " has no '" << from << "'";
    text.replace(at, from.size(), to);
    std::ofstream(path, std::ios::trunc) << text;
  };
  const std::vector<Case> cases = {
      {"imu0 is a file",
       [&](const std::string& dir) {
         fs::remove_all(dir + "/mav0/imu0");
         rewrite(dir + "/mav0/imu0", "x\n");
       },
       "mav0/imu0", "is not a folder"},
      {"camera folder without sensor.yaml",
       [](const std::string& dir) { fs::remove(dir + "/mav0/cam0/sensor.yaml"); },
       "cam0/sensor.yaml", "has data.csv but no sensor.yaml"},
      {"no tag of the map",
       [&](const std::string& dir) {
         replace_in(dir + "/mav0/tags0/data.csv", "\n1000,3,", "\n1000,999,");
       },
       "tags0/data.csv:2: field 'tag_id'", "none of the 1 detections names a tag of map.yaml"},
      {"tags1 without cam1",
       [](const std::string& dir) {
         fs::create_directories(dir + "/mav0/tags1");
         fs::copy_file(dir + "/mav0/tags0/data.csv", dir + "/mav0/tags1/data.csv");
       },
       "tags1/data.csv", "there is no cam1/ folder"},
      {"five distortion coefficients",
       [&](const std::string& dir) {
         replace_in(dir + "/mav0/cam0/sensor.yaml", "0.04]", "0.04, 0.5]");
       },
       "cam0/sensor.yaml",
       "field 'distortion_coefficients': expected 4 values (k1 k2 k3 k4), got 5"},
      {"accelerometer columns first",
       [&](const std::string& dir) {
         replace_in(dir + "/mav0/imu0/data.csv",
                    "w_RS_S_x [rad s^-1],w_RS_S_y [rad s^-1],w_RS_S_z [rad s^-1],a_RS_S_x [m "
                    "s^-2],a_RS_S_y [m s^-2],a_RS_S_z [m s^-2]",
                    "a_RS_S_x [m s^-2],a_RS_S_y [m s^-2],a_RS_S_z [m s^-2],w_RS_S_x [rad "
                    "s^-1],w_RS_S_y [rad s^-1],w_RS_S_z [rad s^-1]");
       },
       "imu0/data.csv:1: field 'a_RS_S_x [m s^-2]'", "column 2 must be the gyroscope"},
      {"an IMU row with an extra column",
       [&](const std::string& dir) {
         replace_in(dir + "/mav0/imu0/data.csv", ",9.81\n", ",9.81,7.5\n");
       },
       "imu0/data.csv:2", "row has 8 fields; an IMU row has 7"},
      {"a truth quantity named twice",
       [&](const std::string& dir) {
         replace_in(dir + "/mav0/truth_quantities0/data.csv", "alpha [rad]", "d [rad]");
       },
       "truth_quantities0/data.csv:1", "quantity 'd' is named twice in the header"},
  };
  for (const Case& c : cases) {
    const std::string dir = testing::MakeTempDir();
    WriteEurocDataset(SmallDataset(), dir);
    ASSERT_EQ(ErrorOf(dir), "") << c.name << ": the unmutated dataset must load";
    c.mutate(dir);
    const std::string error = ErrorOf(dir);
    EXPECT_NE(error.find(c.file), std::string::npos) << c.name << ": " << error;
    EXPECT_NE(error.find(c.message), std::string::npos) << c.name << ": " << error;
  }
}

TEST(EurocWriter, AtomicFolderWrite) {
  const std::string parent = testing::MakeTempDir();
  const std::string root = parent + "/out";
  WriteEurocDatasetAtomically(SmallDataset(), root, {{"import.yaml", "a: 1\n"}});
  EXPECT_EQ(ReadEurocDataset(root).imu.samples.size(), 5u);
  EXPECT_TRUE(fs::exists(root + "/import.yaml"));
  // A non-empty folder is not overwritten unless asked.
  try {
    WriteEurocDatasetAtomically(SmallDataset(), root);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("not empty"), std::string::npos) << e.what();
  }
  Dataset smaller = SmallDataset();
  smaller.imu.samples.resize(3);
  WriteEurocDatasetAtomically(smaller, root + "/", {}, /*replace=*/true);  // trailing slash
  EXPECT_EQ(ReadEurocDataset(root).imu.samples.size(), 3u);
  EXPECT_FALSE(fs::exists(root + "/import.yaml"));  // the old folder is gone, not merged
  // A failure half-way (an extra file where a folder is) leaves nothing behind.
  const std::string failed = parent + "/failed";
  EXPECT_THROW(WriteEurocDatasetAtomically(SmallDataset(), failed, {{"mav0", "not a folder"}}),
               InputError);
  EXPECT_FALSE(fs::exists(failed));
  for (const auto& entry : fs::directory_iterator(parent))
    EXPECT_EQ(entry.path().filename(), "out") << entry.path();
}

TEST(ImuCsv, ReadsTheYacImuAprilLog) {
  REQUIRE_SHARED_DATA();
  const auto samples = ReadImuCsv(testing::SharedDataDir() + "/euroc_imu_april/imu0.csv");
  ASSERT_EQ(samples.size(), 14374u);
  EXPECT_EQ(samples.front().t_ns, 1404733405747800064);
  EXPECT_EQ(samples.back().t_ns, 1404733477612800000);
  EXPECT_DOUBLE_EQ(samples.front().gyro_rad_s.z(), 0.125664);
  EXPECT_DOUBLE_EQ(samples.front().accel_m_s2.x(), 9.365351);
  EXPECT_DOUBLE_EQ(samples.front().accel_m_s2.z(), -3.277056);
}

}  // namespace
}  // namespace mavloc
