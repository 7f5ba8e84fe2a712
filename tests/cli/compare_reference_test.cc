// `mavloc compare` on a dataset without ground truth: it asks for a reference,
// compares against an estimator or a trajectory file, says that the reference is an estimate, and
// reports the reprojection RMS of the tag corners.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "tests/report_support.h"
#include "tests/test_support.h"

namespace fs = std::filesystem;

namespace mavloc {
namespace {

using testing::CliPath;
using testing::MakeTempDir;
using testing::RunCommand;

std::string Cli(const std::string& args) { return CliPath() + " " + args; }

std::string ReadAll(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// A short tag-arena flight with its ground truth removed, as a real log would come.
std::string DatasetWithoutTruth(const std::string& dir) {
  const std::string data = dir + "/data";
  const auto r =
      RunCommand(Cli("simulate --scenario tag-arena-dynamic --duration 8 --seed 5 --out " + data));
  EXPECT_EQ(r.exit_code, 0) << r.output;
  fs::copy_file(data + "/mav0/state_groundtruth_estimate0/data.csv", dir + "/truth.csv");
  fs::remove_all(data + "/mav0/state_groundtruth_estimate0");
  fs::remove_all(data + "/mav0/truth_quantities0");
  return data;
}

TEST(CompareReference, WithoutGroundTruthItAsksForAReference) {
  const std::string dir = MakeTempDir();
  const std::string data = DatasetWithoutTruth(dir);
  const auto r = RunCommand(Cli("compare --dataset " + data + " --report " + dir + "/report"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--reference"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir + "/report/report.md"));
}

TEST(CompareReference, AgainstAnEstimator) {
  const std::string dir = MakeTempDir();
  const std::string data = DatasetWithoutTruth(dir);
  const auto r =
      RunCommand(Cli("compare --dataset " + data +
                     " --estimators tag-ekf --reference tag-pnp --report " + dir + "/report"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("not a truth"), std::string::npos) << r.output;
  const std::string md = ReadAll(dir + "/report/report.md");
  EXPECT_NE(md.find("not a ground truth"), std::string::npos) << md;
  const auto json = nlohmann::json::parse(ReadAll(dir + "/report/report.json"));
  EXPECT_EQ(json["protocol"]["reference"], "estimate");
  EXPECT_EQ(json["details"]["reference"]["name"], "tag-pnp");
  EXPECT_FALSE(json["details"]["reference"]["is_truth"].get<bool>());
  EXPECT_TRUE(testing::ReportEstimator(json, "tag-pnp")["is_reference"].get<bool>());
  const auto ekf = testing::ReportEstimator(json, "tag-ekf");
  const auto ate = testing::MetricStatistics(ekf, "ate_translation");
  ASSERT_TRUE(ate.is_object()) << ekf.dump();
  EXPECT_GT(ate["rmse"].get<double>(), 0.0);
  EXPECT_LT(ate["rmse"].get<double>(), 0.2);
  ASSERT_TRUE(ekf["metrics"].contains("reprojection_cam0")) << ekf.dump();
  EXPECT_LT(ekf["metrics"]["reprojection_cam0"]["value"].get<double>(), 5.0);
}

TEST(CompareReference, AgainstATrajectoryFileAndBadReferences) {
  const std::string dir = MakeTempDir();
  const std::string data = DatasetWithoutTruth(dir);
  auto r = RunCommand(Cli("compare --dataset " + data + " --estimators tag-pnp --reference " + dir +
                          "/truth.csv --align se3 --report " + dir + "/report"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto json = nlohmann::json::parse(ReadAll(dir + "/report/report.json"));
  EXPECT_EQ(json["details"]["reference"]["kind"], "trajectory_file");
  EXPECT_EQ(json["protocol"]["alignment"], "se3");
  // The reference file is the simulation's truth: tag-pnp's differences are its errors (mm-cm).
  const auto ate =
      testing::MetricStatistics(testing::ReportEstimator(json, "tag-pnp"), "ate_translation");
  ASSERT_TRUE(ate.is_object()) << json.dump();
  EXPECT_LT(ate["rmse"].get<double>(), 0.05);
  // The reference is in the folder for the trajectory figure.
  EXPECT_TRUE(fs::exists(dir + "/report/reference.tum"));

  r = RunCommand(
      Cli("compare --dataset " + data + " --reference no-such-thing --report " + dir + "/r2"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("no-such-thing"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir + "/r2/report.md"));
}

}  // namespace
}  // namespace mavloc
