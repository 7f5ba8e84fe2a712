// `mavloc import-aprilgrid` end to end: the real 72 s EuRoC imu_april log (both cameras, yac's
// config.yaml, EuRoC's T_BS) becomes a dataset that reads back; broken logs made in a temp folder
// (a grid point off the target, a frame listed twice, a camera without intrinsics, a NaN) give one
// line naming the file and row, exit code 2, and no --out folder.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>

#include "core/rotation.h"
#include "datasets/io/calibration_io.h"
#include "datasets/io/euroc_io.h"
#include "tests/test_support.h"

namespace fs = std::filesystem;

namespace mavloc {
namespace {

using testing::CliPath;
using testing::MakeTempDir;
using testing::RunCommand;

std::string Log() { return testing::SharedDataDir() + "/euroc_imu_april"; }

std::string Import(const std::string& corners0, const std::string& corners1,
                   const std::string& config, const std::string& out,
                   const std::string& extra = "") {
  std::string command = CliPath() + " import-aprilgrid --imu " + Log() + "/imu0.csv --config " +
                        config + " --corners cam0=" + corners0 + " --out " + out;
  if (!corners1.empty()) command += " --corners cam1=" + corners1;
  return command + " " + extra;
}

TEST(CliImportAprilgrid, RealImuAprilLog) {
  REQUIRE_SHARED_DATA();
  const std::string dir = MakeTempDir();
  const std::string out = dir + "/imu_april";
  const auto r =
      RunCommand(Import(Log() + "/cam0", Log() + "/cam1", Log() + "/config.yaml", out,
                        "--extrinsics " + testing::SharedDataDir() + "/euroc_v1_01_easy/mav0"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::printf("%s", r.output.c_str());
  for (const char* camera : {"cam0", "cam1"}) {
    const std::regex line(std::string(camera) +
                          ": 1439 frames \\(23 without detections\\), [0-9]+ tags, [0-9]+ "
                          "corners read");
    EXPECT_TRUE(std::regex_search(r.output, line)) << r.output;
  }
  for (const char* file :
       {"/mav0/imu0/data.csv", "/mav0/imu0/sensor.yaml", "/mav0/cam0/sensor.yaml",
        "/mav0/cam0/data.csv", "/mav0/cam1/sensor.yaml", "/mav0/cam1/data.csv",
        "/mav0/tags0/data.csv", "/mav0/tags1/data.csv", "/map.yaml", "/import.yaml"})
    EXPECT_TRUE(fs::exists(out + file)) << file;
  EXPECT_FALSE(fs::exists(out + "/scenario.yaml"));
  for (const auto& entry : fs::directory_iterator(dir))
    EXPECT_EQ(entry.path().filename(), "imu_april") << "left behind: " << entry.path();

  // The dataset reads back: 1439 frames per camera (images absent), the tags, EuRoC's T_BS.
  const Dataset d = ReadEurocDataset(out);
  EXPECT_EQ(d.imu.samples.size(), 14374u);
  EXPECT_DOUBLE_EQ(d.imu.noise.gyroscope_random_walk, 1.9393e-05);
  ASSERT_EQ(d.cameras.size(), 2u);
  const CalibrationSource euroc =
      ReadCalibrationSource(testing::SharedDataDir() + "/euroc_v1_01_easy/mav0");
  for (int n : {0, 1}) {
    EXPECT_EQ(d.cameras[n].frames.size(), 1439u);
    EXPECT_EQ(d.cameras[n].missing_images.size(), 1439u);
    const Pose& expected = *euroc.cameras.at(n).T_B_C;
    EXPECT_LT((d.cameras[n].T_B_C.p - expected.p).norm(), 1e-12);
    EXPECT_LT(RotationAngleBetween(d.cameras[n].T_B_C.q, expected.q), 1e-9);
  }
  EXPECT_DOUBLE_EQ(d.cameras[1].model.fv(), 456.134);
  EXPECT_GT(d.tags.size(), 30000u);
  EXPECT_GT(d.tags1.size(), 30000u);
  EXPECT_EQ(d.tags1.front().camera, 1);
  EXPECT_EQ(d.map.frame, MapFrame::kBoard);
  EXPECT_EQ(d.map.tags.size(), 36u);
  // A second import into the same folder needs --force.
  const auto again = RunCommand(Import(Log() + "/cam0", "", Log() + "/config.yaml", out));
  EXPECT_EQ(again.exit_code, 2) << again.output;
  EXPECT_NE(again.output.find("not empty"), std::string::npos) << again.output;
  const auto forced =
      RunCommand(Import(Log() + "/cam0", "", Log() + "/config.yaml", out, "--force"));
  ASSERT_EQ(forced.exit_code, 0) << forced.output;
  EXPECT_NE(forced.output.find("cam0: T_B_C unknown"), std::string::npos) << forced.output;
  EXPECT_FALSE(fs::exists(out + "/mav0/tags1"));
}

// A copy of the first frames of the real log, to break.
class CliImportBroken : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!testing::HasSharedData()) GTEST_SKIP() << "../shared/data is absent";
    dir_ = MakeTempDir();
    for (const char* camera : {"cam0", "cam1"}) {
      std::vector<fs::path> files;
      for (const auto& entry : fs::directory_iterator(Log() + "/" + camera))
        files.push_back(entry.path());
      std::sort(files.begin(), files.end());
      fs::create_directories(dir_ + "/" + camera);
      for (size_t i = 0; i < 20; ++i)
        fs::copy_file(files[i], dir_ + "/" + camera + "/" + files[i].filename().string());
      if (std::string(camera) == "cam0") first_ = files[0].filename().string();
    }
  }

  // Replaces line `line` (1-based) of cam0's first file.
  void ReplaceLine(int line, const std::string& text) {
    const std::string path = dir_ + "/cam0/" + first_;
    std::ifstream in(path);
    std::vector<std::string> lines;
    for (std::string l; std::getline(in, l);) lines.push_back(l);
    lines.at(line - 1) = text;
    std::ofstream write(path);
    for (const auto& l : lines) write << l << "\n";
  }

  void ExpectCleanFailure(const std::string& extra, const std::string& must_contain,
                          const std::string& config = "") {
    const auto r =
        RunCommand(Import(dir_ + "/cam0", dir_ + "/cam1",
                          config.empty() ? Log() + "/config.yaml" : config, dir_ + "/out", extra));
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find(must_contain), std::string::npos) << r.output;
    EXPECT_LE(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
    EXPECT_FALSE(fs::exists(dir_ + "/out")) << r.output;
    for (const auto& entry : fs::directory_iterator(dir_))
      EXPECT_EQ(entry.path().filename().string().find(".tmp-"), std::string::npos) << entry.path();
  }

  std::string dir_;
  std::string first_;
};

TEST_F(CliImportBroken, TheUnbrokenCopyImports) {
  const auto r =
      RunCommand(Import(dir_ + "/cam0", dir_ + "/cam1", Log() + "/config.yaml", dir_ + "/out"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("cam0: 20 frames"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("cam0: T_B_C unknown"), std::string::npos) << r.output;
}

TEST_F(CliImportBroken, GridPointOffTheTarget) {
  // Line 3 is tag 0 corner 1 at (0.088, 0, 0); move it to x = 0.0881.
  ReplaceLine(3,
              "1404733405732800000,6,6,0.088000,0.300000,213.3338928223,334.5094604492,0.088100,"
              "0.000000,0.000000,0,1");
  ExpectCleanFailure("", "cam0/" + first_ +
                             ":3: field 'p_x': grid point (0.088100, 0.000000, "
                             "0.000000) is not tag 0 corner 1");
}

TEST_F(CliImportBroken, FrameListedTwice) {
  fs::copy_file(dir_ + "/cam1/" + first_, dir_ + "/cam1/0" + first_);
  ExpectCleanFailure("", "frame 1404733405732800000 listed twice");
  fs::remove(dir_ + "/cam1/0" + first_);
  // A corner listed twice in one file.
  ReplaceLine(3,
              "1404733405732800000,6,6,0.088000,0.300000,175.9866943359,336.8252258301,0.000000,"
              "0.000000,0.000000,0,0");
  ExpectCleanFailure("", "cam0/" + first_ + ":3: field 'corner_idx': tag 0 corner 0 listed twice");
}

TEST_F(CliImportBroken, CameraWithoutIntrinsics) {
  std::ifstream in(Log() + "/config.yaml");
  std::string text(std::istreambuf_iterator<char>(in), {});
  text = text.substr(0, text.find("cam1:"));  // drop cam1 and T_cam0_cam1
  std::ofstream(dir_ + "/config.yaml") << text;
  ExpectCleanFailure("", dir_ + "/cam1: cam1 has corners but no intrinsics", dir_ + "/config.yaml");
}

TEST_F(CliImportBroken, NanTimestampMismatchAndBadOptions) {
  ReplaceLine(2,
              "1404733405732800000,6,6,0.088000,0.300000,nan,336.8252258301,0.000000,0.000000,"
              "0.000000,0,0");
  ExpectCleanFailure("", "cam0/" + first_ + ":2: field 'kp_x': 'nan' is not finite");
  ReplaceLine(2,
              "1404733405732800001,6,6,0.088000,0.300000,175.9866943359,336.8252258301,0.000000,"
              "0.000000,0.000000,0,0");
  ExpectCleanFailure("", "cam0/" + first_ + ":2: field 'ts': 1404733405732800001 disagrees");
  ExpectCleanFailure("--extrinsics /nonexistent/mav0",
                     "/nonexistent/mav0: file or folder does "
                     "not exist");
}

}  // namespace
}  // namespace mavloc
