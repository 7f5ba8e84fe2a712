// `mavloc repro smoother|three-point|laser|pixhawk|apriltag --jobs N` run on the sweep machinery
// (evaluation/sweep/): N workers give the numbers of one process, because every run's result goes
// through the same JSON text either way; only the wall-clock fields differ. A reproduction that has
// no units (euroc-imu-april: one run on one real log) refuses --jobs > 1.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "tests/test_support.h"

namespace mavloc {
namespace {

using testing::CliPath;
using testing::MakeTempDir;
using testing::RunCommand;

std::string Read(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

bool IsWallTime(const std::string& key) {
  return key.find("runtime") != std::string::npos || key.find("s_per_frame") != std::string::npos ||
         key == "elapsed_s" || key == "jobs" || key == "cramer_rao_compute_s" || key == "command";
}

// The report without its wall-clock fields (run times, times per frame, the bound's compute time,
// the job count), in details and in the tables' columns.
nlohmann::json WithoutTimes(const nlohmann::json& json) {
  if (json.is_object() && json.contains("columns") && json.contains("rows")) {
    nlohmann::json table = json;
    for (size_t k = table["columns"].size(); k-- > 0;) {
      if (!IsWallTime(table["columns"][k].value("name", ""))) continue;
      table["columns"].erase(k);
      for (auto& row : table["rows"])
        if (k < row.size()) row.erase(k);
    }
    return table;
  }
  if (json.is_array()) {
    nlohmann::json out = nlohmann::json::array();
    for (const auto& item : json) out.push_back(WithoutTimes(item));
    return out;
  }
  if (!json.is_object()) return json;
  nlohmann::json out = nlohmann::json::object();
  for (const auto& [key, value] : json.items()) {
    if (IsWallTime(key)) continue;
    out[key] = WithoutTimes(value);
  }
  return out;
}

// Runs `command` (a repro without --report) with --jobs 1 and --jobs 2 into dir/serial and
// dir/parallel; returns the two report.json, after checking the exit codes and the recorded jobs.
struct TwoRuns {
  nlohmann::json serial, parallel;                // the reports' details
  nlohmann::json serial_report, parallel_report;  // the whole report.json
};

TwoRuns RunSerialAndParallel(const std::string& command, const std::string& dir) {
  TwoRuns runs;
  for (const auto& [folder, jobs] : {std::pair{"serial", 1}, std::pair{"parallel", 2}}) {
    const auto r =
        RunCommand(command + " --report " + dir + "/" + folder + " --jobs " + std::to_string(jobs));
    EXPECT_EQ(r.exit_code, 0) << r.output;
    if (r.exit_code != 0) return {};
    // The reproduction's own layout is the report's details.
    const auto report = nlohmann::json::parse(Read(dir + "/" + folder + "/report.json"));
    const nlohmann::json& details = report["details"];
    EXPECT_EQ(details.contains("jobs") ? details["jobs"] : report["provenance"]["jobs"], jobs);
    (jobs == 1 ? runs.serial : runs.parallel) = details;
    (jobs == 1 ? runs.serial_report : runs.parallel_report) = report;
  }
  return runs;
}

// The two reports (tables, details, provenance) agree on everything but wall-clock
// fields, and the files agree byte for byte.
void ExpectSameResults(const TwoRuns& runs, const std::string& dir,
                       const std::vector<std::string>& files) {
  // The prose is report.md's, compared below where it holds no wall-clock numbers.
  nlohmann::json serial = WithoutTimes(runs.serial_report);
  nlohmann::json parallel = WithoutTimes(runs.parallel_report);
  serial.erase("sections");
  parallel.erase("sections");
  const nlohmann::json difference = nlohmann::json::diff(serial, parallel);
  EXPECT_TRUE(difference.empty()) << difference.dump(1);
  // The report names its own folder where it says how to draw the figures (they are off in the
  // tests): the one difference allowed.
  const auto without_folder = [&](std::string text, const std::string& folder) {
    const std::string path = dir + "/" + folder;
    for (size_t at = text.find(path); at != std::string::npos; at = text.find(path, at))
      text.replace(at, path.size(), "REPORT");
    return text;
  };
  for (const auto& file : files) {
    const std::string left = without_folder(Read(dir + "/serial/" + file), "serial");
    EXPECT_FALSE(left.empty()) << file;
    EXPECT_TRUE(left == without_folder(Read(dir + "/parallel/" + file), "parallel"))
        << file << " differs";
  }
}

TEST(ReproJobs, SmootherGivesTheSameNumbersInTwoWorkers) {
  const std::string dir = MakeTempDir();
  const TwoRuns runs =
      RunSerialAndParallel(CliPath() +
                               " repro smoother --runs 3 --seed 5 --set scenarios=tag-arena-hover "
                               "--set duration_s=4",
                           dir);
  ASSERT_FALSE(runs.serial.is_null() || runs.parallel.is_null());
  const auto& table = runs.serial["tables"]["tag-arena-hover"];
  EXPECT_EQ(table["estimators"]["smoother"]["runs"], 3);
  EXPECT_EQ(table["estimators"]["smoother"]["per_run"].size(), 3u);
  EXPECT_EQ(table["cramer_rao_runs"], 3);
  EXPECT_GT(table["estimators"]["smoother"]["position_rmse_m"].get<double>(), 0.0);
  ExpectSameResults(runs, dir, {"crlb_tag-arena-hover.csv", "anees_tag-arena-hover.csv"});
}

// three-point: table1 plus three sensitivity rows (two heights, one biased-accelerometer row), two
// seeds each: 8 units.
TEST(ReproJobs, ThreePointGivesTheSameNumbersInTwoWorkers) {
  const std::string dir = MakeTempDir();
  const TwoRuns runs =
      RunSerialAndParallel(CliPath() +
                               " repro three-point --runs 2 --seed 3 --set noise_levels_deg=0.1 "
                               "--set heights_m=0.4,0.8",
                           dir);
  ASSERT_FALSE(runs.serial.is_null() || runs.parallel.is_null());
  const auto& three_point =
      runs.serial["tables"]["table1"]["estimators"]["three-point"]["quantities"];
  EXPECT_GT(three_point["roll"]["count"].get<long>(), 0);
  EXPECT_GT(three_point["roll"]["std_over_runs"].get<double>(), 0.0);  // two runs' means differ
  EXPECT_EQ(runs.serial["tables"]["sensitivity"]["rows"].size(), 3u);
  ExpectSameResults(runs, dir, {"report.md"});
}

// laser: two seeds of laser-plane without and with biases, and one EuRoC seed (three tables from
// one unit) when the shared data is present.
TEST(ReproJobs, LaserGivesTheSameNumbersInTwoWorkers) {
  const std::string dir = MakeTempDir();
  const bool euroc = testing::HasSharedData();
  const TwoRuns runs = RunSerialAndParallel(
      CliPath() + " repro laser --runs 2 --seed 4 --set duration_s=6 --set euroc_runs=1 --set " +
          (euroc ? "euroc=true" : "euroc=false"),
      dir);
  ASSERT_FALSE(runs.serial.is_null() || runs.parallel.is_null());
  const nlohmann::json& tables = runs.serial["tables"];
  ASSERT_EQ(tables["simulated"].size(), 2u) << tables.dump(1);
  ASSERT_EQ(tables.contains("euroc"), euroc) << tables.dump(1);
  if (euroc) {
    EXPECT_EQ(tables["euroc"].size(), 3u);
  }
  for (const auto& [group, group_tables] : tables.items()) {
    for (const auto& [name, table] : group_tables.items()) {
      EXPECT_EQ(table["seeds"].size(), group == "euroc" ? 1u : 2u) << group << " " << name;
    }
  }
  ExpectSameResults(runs, dir, {"report.md", "runs.csv"});
}

// pixhawk: the kf table (three configurations), two seeds each: 6 units. Without fig15 (whose
// ms/frame is a wall time) report.md is the same byte for byte too.
TEST(ReproJobs, PixhawkGivesTheSameNumbersInTwoWorkers) {
  const std::string dir = MakeTempDir();
  const TwoRuns runs = RunSerialAndParallel(
      CliPath() + " repro pixhawk --runs 2 --seed 6 --set tables=kf --set duration_s=6", dir);
  ASSERT_FALSE(runs.serial.is_null() || runs.parallel.is_null());
  const nlohmann::json& kf = runs.serial["tables"]["kf"]["rows"];
  ASSERT_EQ(kf.size(), 16u) << kf.dump(1);  // 5 + 5 + 6 variants
  EXPECT_EQ(kf[0]["runs"], 2);
  EXPECT_GT(kf[0]["position_rmse_m"].get<double>(), 0.0);
  EXPECT_FALSE(runs.serial["tables"].contains("fig15"));
  ExpectSameResults(runs, dir, {"kf.csv", "report.md"});
}

// apriltag: the dynamic unit and three hover units, from rendered and detected images; the
// hover's images are rendered by whichever worker runs a hover unit, and are the same in each.
TEST(ReproJobs, AprilTagGivesTheSameNumbersInTwoWorkers) {
  const std::string dir = MakeTempDir();
  const TwoRuns runs =
      RunSerialAndParallel(CliPath() +
                               " repro apriltag --runs 3 --seed 2 --set hover_duration_s=3 "
                               "--set dynamic_duration_s=8 --set supersampling=1 --set decimate=2",
                           dir);
  ASSERT_FALSE(runs.serial.is_null() || runs.parallel.is_null());
  const nlohmann::json& tables = runs.serial["tables"];
  EXPECT_EQ(tables["hover"]["runs"], 3);
  EXPECT_EQ(tables["hover"]["p0_matched"]["position"]["final_m"]["count"], 3);
  EXPECT_GT(tables["images"]["hover"]["frames"].get<int>(), 0);
  EXPECT_GT(tables["images"]["dynamic"]["detections"].get<int>(), 0);
  EXPECT_EQ(runs.serial["hover_images_seed"], 2);
  ExpectSameResults(runs, dir, {"hover_envelope.csv", "nees.csv", "dynamic_errors.csv"});
}

TEST(ReproJobs, ReproductionsWithoutUnitsRefuseJobs) {
  const std::string dir = MakeTempDir();
  const auto r = RunCommand(CliPath() + " repro euroc-imu-april --jobs 2 --report " + dir + "/r");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--jobs 2: repro euroc-imu-april runs in one process"), std::string::npos)
      << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir + "/r"));
}

}  // namespace
}  // namespace mavloc
