// End to end: `mavloc simulate --scenario stereo-obstacles --render` then `mavloc obstacles`
// (PIXHAWK 7.3): every obstacle that comes within the clearance raises an alert, and the report
// carries the alert count, precision, recall and the Table-1 timing.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "tests/test_support.h"

namespace mavloc {
namespace {

std::string ReadText(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// Simulates the scenario (default: 10 s, 5 Hz stereo, seed 1) into folder/data, rendering the
// images when asked (the only slow step, so only the end-to-end test renders).
testing::CommandResult Simulate(const std::string& folder, bool render) {
  return testing::RunCommand(testing::CliPath() + " simulate --scenario stereo-obstacles --out " +
                             folder + "/data" +
                             (render ? " --render --set image_dir=" + folder + "/render" : ""));
}

TEST(ObstaclesCommandTest, EveryCloseObstacleRaisesAnAlert) {
  const std::string folder = testing::MakeTempDir();
  const auto simulated = Simulate(folder, true);
  ASSERT_EQ(simulated.exit_code, 0) << simulated.output;
  const std::string report = folder + "/report";
  const auto result = testing::RunCommand(testing::CliPath() + " obstacles --dataset " + folder +
                                          "/data --pose-source gt --report " + report);
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const nlohmann::json report_json = nlohmann::json::parse(ReadText(report + "/report.json"));
  EXPECT_EQ(report_json["report_kind"], "obstacles");
  // The report follows the one schema (Debian's python3-jsonschema, where installed).
  if (testing::RunCommand("/usr/bin/python3 -c 'import jsonschema'").exit_code == 0) {
    const auto valid = testing::RunCommand(
        "/usr/bin/python3 " + testing::SourceDir() + "/scripts/validate_report.py " +
        testing::SourceDir() + "/schemas/report.schema.json " + report + "/report.json");
    EXPECT_EQ(valid.exit_code, 0) << valid.output;
  }
  const nlohmann::json& json = report_json["details"];  // the obstacle evaluation's own layout
  ASSERT_TRUE(json.contains("alert_count"));
  ASSERT_TRUE(json.contains("precision"));
  ASSERT_TRUE(json.contains("recall"));
  EXPECT_EQ(json["frames"].get<int>(), 51);
  // The scenario puts four of its six obstacles inside the 0.75 m clearance; each raises an alert
  // (an alert whose nearest measured point lies on it), and the two farther ones raise none.
  EXPECT_EQ(json["obstacles_within_clearance"].get<int>(), 4);
  EXPECT_EQ(json["obstacles_alerted"].get<int>(), 4);
  for (const auto& obstacle : json["obstacles"]) {
    if (obstacle["within_clearance"].get<bool>()) {
      EXPECT_GT(obstacle["alerts"].get<int>(), 0) << obstacle.dump();
    } else {
      EXPECT_EQ(obstacle["alerts"].get<int>(), 0) << obstacle.dump();
    }
  }
  // With the true poses the alerts are rarely wrong; frames right at the clearance can go either
  // way (measured distances are within a few cm), so precision and recall are high but not 1.
  EXPECT_GE(json["precision"].get<double>(), 0.8);
  EXPECT_GE(json["recall"].get<double>(), 0.7);
  const int alerts = json["alert_count"].get<int>();
  EXPECT_GT(alerts, 0);
  // alerts.csv: a header plus one row per alert.
  const std::string csv = ReadText(report + "/alerts.csv");
  EXPECT_EQ(static_cast<int>(std::count(csv.begin(), csv.end(), '\n')), alerts + 1);
  // Table 1 rows and eq. (4) in report.md.
  const std::string md = ReadText(report + "/report.md");
  for (const char* text : {"Image rectification", "Disparity mapping", "Point cloud generation",
                           "Total", "d_min = 9 px"}) {
    EXPECT_NE(md.find(text), std::string::npos) << text;
  }
  EXPECT_GT(json["timing_s"]["total"].get<double>(), 0.0);  // SI in report.json
  std::filesystem::remove_all(folder);
}

TEST(ObstaclesCommandTest, BadInputExitsWithTwo) {
  const std::string folder = testing::MakeTempDir();
  ASSERT_EQ(Simulate(folder, false).exit_code, 0);
  const std::string cli = testing::CliPath() + " obstacles --report " + folder + "/bad";
  auto result = testing::RunCommand(cli + " --dataset " + folder + "/missing");
  EXPECT_EQ(result.exit_code, 2) << result.output;
  result = testing::RunCommand(cli + " --dataset " + folder + "/data --set block_sise=15");
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_NE(result.output.find("block_sise"), std::string::npos) << result.output;
  result = testing::RunCommand(cli + " --dataset " + folder + "/data --set num_disparities=60");
  EXPECT_EQ(result.exit_code, 2) << result.output;
  result = testing::RunCommand(cli + " --dataset " + folder + "/data --pose-source nonsense");
  EXPECT_EQ(result.exit_code, 2) << result.output;
  // Without --render the dataset lists frames but has no images: the message says what to do.
  result = testing::RunCommand(cli + " --dataset " + folder + "/data");
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_NE(result.output.find("--render"), std::string::npos) << result.output;
  std::filesystem::remove_all(folder);
}

}  // namespace
}  // namespace mavloc
