// `mavloc track-features`, and the smoother on feature tracks, on the real EuRoC frames of
// ../shared/data (95 cam0 frames before take-off, real IMU, 3.7 s of ground truth; cam1 lists 99
// frames of which 10 exist, so the run is mono), and the bad inputs of an image log.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <string>

#include "core/image_codec.h"
#include "tests/report_support.h"
#include "tests/test_support.h"

namespace fs = std::filesystem;

namespace mavloc {
namespace {

// A writable copy of the real EuRoC folder: links to every file (the test may replace some).
std::string EurocCopy() {
  const std::string dir = testing::MakeTempDir() + "/euroc";
  const fs::path source = testing::SharedDataDir() + "/euroc_v1_01_easy";
  fs::create_directories(dir);
  for (const auto& entry : fs::recursive_directory_iterator(source)) {
    const fs::path target = dir / fs::relative(entry.path(), source);
    if (entry.is_directory())
      fs::create_directories(target);
    else
      fs::create_symlink(entry.path(), target);
  }
  return dir;
}

std::string FirstFrame(const std::string& dir) {
  return dir + "/mav0/cam0/data/1403715273262142976.png";
}

TEST(TrackFeatures, RealEurocFramesGiveLongMonoTracks) {
  REQUIRE_SHARED_DATA();
  const std::string dir = EurocCopy();
  const testing::CliRun run = testing::RunCliIn(dir, "track-features --dataset " + dir);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.out.find("tracking mono (cam0 only)"), std::string::npos) << run.out;
  for (const char* file : {"data.csv", "tracking.csv", "frontend.yaml"})
    EXPECT_TRUE(fs::exists(dir + "/mav0/features0/" + file)) << file;
  EXPECT_FALSE(fs::exists(dir + "/mav0/features1/data.csv"));
  // The tracks live on average at least 30 frames (measured: 84.6 of the 95).
  std::ifstream yaml(dir + "/mav0/features0/frontend.yaml");
  std::string line;
  double mean_length = 0.0;
  while (std::getline(yaml, line))
    if (line.find("mean_track_length_frames:") != std::string::npos)
      mean_length = std::stod(line.substr(line.find(':') + 1));
  EXPECT_GE(mean_length, 30.0);
  // A second run does not replace the stream without --force.
  const testing::CliRun again = testing::RunCliIn(dir, "track-features --dataset " + dir);
  EXPECT_EQ(again.exit_code, 2);
  EXPECT_NE(again.err.find("features0/data.csv"), std::string::npos) << again.err;
}

// compare on the image log: the frontend runs by itself, and the smoother's positions stay closer
// to the truth than dead reckoning's (measured: ATE 8 mm against 400 mm).
TEST(TrackFeatures, SmootherOnTheRealFramesBeatsDeadReckoning) {
  REQUIRE_SHARED_DATA();
  const std::string dir = testing::MakeTempDir();
  const std::string data = testing::SharedDataDir() + "/euroc_v1_01_easy";
  const testing::CliRun run = testing::RunCliIn(
      dir, "compare --dataset " + data + " --estimators smoother,imu-dead-reckoning --report rep");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.out.find("feature tracks from the images (mono cam0)"), std::string::npos);
  std::ifstream in(dir + "/rep/report.json");
  const nlohmann::json report = nlohmann::json::parse(in);
  EXPECT_TRUE(report["details"].contains("frontend"));
  const double smoother = testing::MetricStatistics(testing::ReportEstimator(report, "smoother"),
                                                    "ate_translation")["max"];
  const double dead_reckoning = testing::MetricStatistics(
      testing::ReportEstimator(report, "imu-dead-reckoning"), "ate_translation")["rmse"];
  EXPECT_LT(smoother, 0.5 * dead_reckoning);
}

struct BadImageCase {
  std::string name;
  std::function<void(const std::string& dir)> damage;
  std::string expected;  // in the one stderr line
};

class TrackFeaturesBadInput : public ::testing::TestWithParam<BadImageCase> {};

TEST_P(TrackFeaturesBadInput, ExitsTwoNamingTheFileAndWritesNothing) {
  REQUIRE_SHARED_DATA();
  const std::string dir = EurocCopy();
  GetParam().damage(dir);
  const testing::CliRun run = testing::RunCliIn(dir, "track-features --dataset " + dir);
  EXPECT_EQ(run.exit_code, 2) << run.out << run.err;
  EXPECT_NE(run.err.find(GetParam().expected), std::string::npos) << run.err;
  EXPECT_FALSE(fs::exists(dir + "/mav0/features0")) << "nothing half-written";
}

void Replace(const std::string& path, const cv::Mat& image) {
  fs::remove(path);
  testing::WriteFileBytes(path, EncodePng(image));
}

INSTANTIATE_TEST_SUITE_P(
    Rows, TrackFeaturesBadInput,
    ::testing::Values(
        BadImageCase{"ImageOfAnotherSize",
                     [](const std::string& dir) {
                       Replace(FirstFrame(dir), cv::Mat(240, 376, CV_8U, cv::Scalar(90)));
                     },
                     "1403715273262142976.png: field 'resolution'"},
        BadImageCase{"UndecodableImage",
                     [](const std::string& dir) {
                       fs::remove(FirstFrame(dir));
                       testing::WriteFileBytes(FirstFrame(dir), "not a png");
                     },
                     "1403715273262142976.png"},
        BadImageCase{"NoImageAtAll",
                     [](const std::string& dir) { fs::remove_all(dir + "/mav0/cam0/data"); },
                     "none of the listed images exists on disk"},
        BadImageCase{"CameraWithoutCalibration",
                     [](const std::string& dir) { fs::remove(dir + "/mav0/cam0/sensor.yaml"); },
                     "cam0/sensor.yaml"}),
    [](const ::testing::TestParamInfo<BadImageCase>& info) { return info.param.name; });

// All-black frames are tracked as what they are: no corner, and a warning that says so.
TEST(TrackFeatures, BlackFramesAreAWarningNotAnError) {
  REQUIRE_SHARED_DATA();
  const std::string dir = EurocCopy();
  for (const auto& entry : fs::directory_iterator(dir + "/mav0/cam0/data"))
    Replace(entry.path().string(), cv::Mat(480, 752, CV_8U, cv::Scalar(0)));
  const testing::CliRun run = testing::RunCliIn(dir, "track-features --dataset " + dir);
  EXPECT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.out.find("95 frames without any corner"), std::string::npos) << run.out;
}

}  // namespace
}  // namespace mavloc
