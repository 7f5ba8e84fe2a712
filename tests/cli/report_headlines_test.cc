// Headlines that do not mislead: every table shows RMSE as its headline with the coverage beside
// it (and a warning when the truth covers less than 90 % of an estimate), frames without a pose
// apart from rejected measurements, estimated calibration with its sigma, and an ill-conditioned
// alignment says so.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iomanip>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "tests/report_support.h"
#include "tests/test_support.h"

namespace fs = std::filesystem;

namespace mavloc {
namespace {

using testing::CliPath;
using testing::MakeTempDir;
using testing::ReadFileBytes;
using testing::RunCommand;
using testing::SharedDataDir;

// Dead reckoning on the real EuRoC sequence: 145 s of IMU against 5 s of ground truth. The old
// headline was "ATE 0.40 m" with no count; now the coverage and a warning stand beside the RMSE.
TEST(ReportHeadlines, CoverageAndAWarningWhenTheTruthCoversLittle) {
  REQUIRE_SHARED_DATA();
  const std::string dir = MakeTempDir();
  const auto run =
      RunCommand("MAVLOC_FIGURES=0 " + CliPath() + " compare --dataset " + SharedDataDir() +
                 "/euroc_v1_01_easy --estimators imu-dead-reckoning --report " + dir + "/r");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("ATE RMSE [m]"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("covers only"), std::string::npos) << run.output;
  const auto report = nlohmann::json::parse(ReadFileBytes(dir + "/r/report.json"));
  const nlohmann::json e = testing::ReportEstimator(report, "imu-dead-reckoning");
  ASSERT_TRUE(e.is_object());
  const auto& coverage = e["coverage"];
  EXPECT_LT(coverage["fraction"].get<double>(), 0.1) << coverage.dump();
  EXPECT_GT(coverage["estimate_span_s"].get<double>(), 140.0) << coverage.dump();
  const std::string md = ReadFileBytes(dir + "/r/report.md");
  EXPECT_NE(md.find("250/"), std::string::npos) << md;
  EXPECT_NE(md.find("(3 %)"), std::string::npos) << md;
}

// tag-ekf's gated-out tags are rejected measurements, not frames without a pose.
TEST(ReportHeadlines, FramesWithoutPoseApartFromRejectedMeasurements) {
  const std::string dir = MakeTempDir();
  const auto run = RunCommand("MAVLOC_FIGURES=0 " + CliPath() +
                              " compare --scenario tag-arena-dynamic --duration 8 --estimators "
                              "tag-ekf,tag-pnp --option tag-ekf:gate_chi2=0.5 --report " +
                              dir + "/r");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("frames without pose"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("rejected measurements"), std::string::npos) << run.output;
  const auto report = nlohmann::json::parse(ReadFileBytes(dir + "/r/report.json"));
  const nlohmann::json ekf = testing::ReportEstimator(report, "tag-ekf");
  ASSERT_TRUE(ekf.is_object());
  EXPECT_GT(ekf["rejected_measurements"].get<int>(), 0) << ekf.dump();
  // Every output of the filter has a pose: the rejections do not count as frames without one.
  EXPECT_LT(ekf["frames_without_pose"].get<int>(), ekf["rejected_measurements"].get<int>());
}

// A calibration the smoother estimated stands in the tables, with its sigma.
TEST(ReportHeadlines, EstimatedCalibrationIsInTheTables) {
  const std::string dir = MakeTempDir();
  const auto run = RunCommand(
      "MAVLOC_FIGURES=0 " + CliPath() +
      " compare --scenario aprilgrid-calibration --duration 8 --estimators smoother --option "
      "smoother:estimate_time_offset=1 --option smoother:calibration_covariance=1 --report " +
      dir + "/r");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("Estimated calibration"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("time_offset"), std::string::npos) << run.output;
  const auto report = nlohmann::json::parse(ReadFileBytes(dir + "/r/report.json"));
  const nlohmann::json smoother = testing::ReportEstimator(report, "smoother");
  ASSERT_TRUE(smoother.is_object());
  const auto& offset = smoother["parameters"]["time_offset"];
  EXPECT_EQ(offset["unit"], "s");
  EXPECT_TRUE(offset["sigma"].is_number()) << offset.dump();
}

// se3 on a near-static window of real EuRoC data (the 3.7 s before take-off): the rotation of
// the alignment is fitted to noise, and the report says so instead of a silent rotation "error".
TEST(ReportHeadlines, AnIllConditionedAlignmentIsNamed) {
  REQUIRE_SHARED_DATA();
  const std::string dir = MakeTempDir();
  std::ifstream in(SharedDataDir() + "/euroc_v1_01_easy/groundtruth_full_tum.txt");
  std::ofstream truth(dir + "/gt.tum"), estimate(dir + "/est.tum");
  std::string line;
  double t0 = -1.0;
  int k = 0;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    double t, x, y, z, qx, qy, qz, qw;
    std::istringstream(line) >> t >> x >> y >> z >> qx >> qy >> qz >> qw;
    if (t0 < 0) t0 = t;
    if (t - t0 > 3.7) break;
    truth << line << "\n";
    // 1 mm of alternating noise on the estimate's positions.
    const double e = (++k % 2 ? 1e-3 : -1e-3);
    estimate << std::setprecision(16) << t << " " << x + e << " " << y - e << " " << z << " " << qx
             << " " << qy << " " << qz << " " << qw << "\n";
  }
  truth.close();
  estimate.close();
  const auto run = RunCommand(CliPath() + " eval --gt " + dir + "/gt.tum --est " + dir +
                              "/est.tum --align se3 --out " + dir + "/r");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("ill-conditioned"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("--align-origin"), std::string::npos) << run.output;
  EXPECT_NE(ReadFileBytes(dir + "/r/report.md").find("ill-conditioned"), std::string::npos);
}

// The Cramér–Rao table's smoothing and filtering rows are over the same keyframes: the filtering
// bound (data up to each keyframe) is then never below the smoothing bound (all data).
TEST(ReportHeadlines, SmoothingAndFilteringBoundsOverTheSameKeyframes) {
  const std::string dir = MakeTempDir();
  const auto run = RunCommand("MAVLOC_FIGURES=0 " + CliPath() +
                              " compare --scenario tag-arena-dynamic --duration 8 --estimators "
                              "smoother,tag-ekf --report " +
                              dir + "/r");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const auto report = nlohmann::json::parse(ReadFileBytes(dir + "/r/report.json"));
  const auto& bound = report["details"]["cramer_rao"]["quantity_sigma_rms"];
  ASSERT_TRUE(bound.is_object()) << report["details"].dump(1);
  EXPECT_EQ(bound["smoothing"]["keyframes"], bound["filtering"]["keyframes"]);
  for (const char* q : {"x", "y", "z", "roll", "pitch", "yaw"})
    EXPECT_GE(bound["filtering"][q].get<double>(), bound["smoothing"][q].get<double>() * 0.999)
        << q << ": " << bound.dump();
}

}  // namespace
}  // namespace mavloc
