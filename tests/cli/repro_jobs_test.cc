// `mavloc repro smoother|three-point|laser --jobs N` run on the sweep machinery (issue 16): N
// workers give the numbers of one process, because every run's result goes through the same JSON
// text either way; only the wall-clock fields differ. A reproduction that has no units refuses
// --jobs > 1.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>

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

// The report without its wall-clock fields (run times, the bound's compute time, the job count).
nlohmann::json WithoutTimes(const nlohmann::json& json) {
  if (json.is_array()) {
    nlohmann::json out = nlohmann::json::array();
    for (const auto& item : json) out.push_back(WithoutTimes(item));
    return out;
  }
  if (!json.is_object()) return json;
  nlohmann::json out = nlohmann::json::object();
  for (const auto& [key, value] : json.items()) {
    if (key.find("runtime") != std::string::npos || key == "elapsed_s" || key == "jobs" ||
        key == "cramer_rao_compute_s")
      continue;
    out[key] = WithoutTimes(value);
  }
  return out;
}

TEST(ReproJobs, SmootherGivesTheSameNumbersInTwoWorkers) {
  const std::string dir = MakeTempDir();
  const std::string command = CliPath() +
                              " repro smoother --runs 3 --seed 5 --set scenarios=tag-arena-hover "
                              "--set duration_s=4 --report " +
                              dir;
  const auto serial = RunCommand(command + "/serial --jobs 1");
  ASSERT_EQ(serial.exit_code, 0) << serial.output;
  const auto parallel = RunCommand(command + "/parallel --jobs 2");
  ASSERT_EQ(parallel.exit_code, 0) << parallel.output;

  const auto a = nlohmann::json::parse(Read(dir + "/serial/report.json"));
  const auto b = nlohmann::json::parse(Read(dir + "/parallel/report.json"));
  EXPECT_EQ(a["jobs"], 1);
  EXPECT_EQ(b["jobs"], 2);
  const auto& table = a["tables"]["tag-arena-hover"];
  EXPECT_EQ(table["estimators"]["smoother"]["runs"], 3);
  EXPECT_EQ(table["estimators"]["smoother"]["per_run"].size(), 3u);
  EXPECT_EQ(table["cramer_rao_runs"], 3);
  EXPECT_GT(table["estimators"]["smoother"]["position_rmse_m"].get<double>(), 0.0);
  const nlohmann::json difference = nlohmann::json::diff(WithoutTimes(a), WithoutTimes(b));
  EXPECT_TRUE(difference.empty()) << difference.dump(1);
  for (const char* csv : {"crlb_tag-arena-hover.csv", "anees_tag-arena-hover.csv"}) {
    const std::string left = Read(dir + "/serial/" + csv);
    EXPECT_FALSE(left.empty()) << csv;
    EXPECT_TRUE(left == Read(dir + "/parallel/" + csv)) << csv << " differs";
  }
}

// three-point: table1 plus three sensitivity rows (two heights, one biased-accelerometer row), two
// seeds each: 8 units.
TEST(ReproJobs, ThreePointGivesTheSameNumbersInTwoWorkers) {
  const std::string dir = MakeTempDir();
  const std::string command = CliPath() +
                              " repro three-point --runs 2 --seed 3 --set noise_levels_deg=0.1 "
                              "--set heights_m=0.4,0.8 --report " +
                              dir;
  const auto serial = RunCommand(command + "/serial --jobs 1");
  ASSERT_EQ(serial.exit_code, 0) << serial.output;
  const auto parallel = RunCommand(command + "/parallel --jobs 2");
  ASSERT_EQ(parallel.exit_code, 0) << parallel.output;

  const auto a = nlohmann::json::parse(Read(dir + "/serial/report.json"));
  const auto b = nlohmann::json::parse(Read(dir + "/parallel/report.json"));
  EXPECT_EQ(a["jobs"], 1);
  EXPECT_EQ(b["jobs"], 2);
  const auto& three_point = a["tables"]["table1"]["estimators"]["three-point"]["quantities"];
  EXPECT_GT(three_point["roll"]["count"].get<long>(), 0);
  EXPECT_GT(three_point["roll"]["std_over_runs"].get<double>(), 0.0);  // two runs' means differ
  EXPECT_EQ(a["tables"]["sensitivity"]["rows"].size(), 3u);
  const nlohmann::json difference = nlohmann::json::diff(WithoutTimes(a), WithoutTimes(b));
  EXPECT_TRUE(difference.empty()) << difference.dump(1);
  const std::string markdown = Read(dir + "/serial/report.md");
  EXPECT_FALSE(markdown.empty());
  EXPECT_TRUE(markdown == Read(dir + "/parallel/report.md")) << "report.md differs";
}

// laser: two seeds of laser-plane without and with biases, and one EuRoC seed (three tables from
// one unit) when the shared data is present.
TEST(ReproJobs, LaserGivesTheSameNumbersInTwoWorkers) {
  const std::string dir = MakeTempDir();
  const bool euroc = testing::HasSharedData();
  const std::string command =
      CliPath() + " repro laser --runs 2 --seed 4 --set duration_s=6 --set euroc_runs=1 --set " +
      (euroc ? "euroc=true" : "euroc=false") + " --report " + dir;
  const auto serial = RunCommand(command + "/serial --jobs 1");
  ASSERT_EQ(serial.exit_code, 0) << serial.output;
  const auto parallel = RunCommand(command + "/parallel --jobs 2");
  ASSERT_EQ(parallel.exit_code, 0) << parallel.output;

  const auto a = nlohmann::json::parse(Read(dir + "/serial/report.json"));
  const auto b = nlohmann::json::parse(Read(dir + "/parallel/report.json"));
  EXPECT_EQ(b["jobs"], 2);
  ASSERT_EQ(a["tables"]["simulated"].size(), 2u) << a["tables"].dump(1);
  ASSERT_EQ(a["tables"].contains("euroc"), euroc) << a["tables"].dump(1);
  if (euroc) {
    EXPECT_EQ(a["tables"]["euroc"].size(), 3u);
  }
  for (const auto& [group, tables] : a["tables"].items()) {
    for (const auto& [name, table] : tables.items()) {
      EXPECT_EQ(table["seeds"].size(), group == "euroc" ? 1u : 2u) << group << " " << name;
    }
  }
  const nlohmann::json difference = nlohmann::json::diff(WithoutTimes(a), WithoutTimes(b));
  EXPECT_TRUE(difference.empty()) << difference.dump(1);
  for (const char* file : {"report.md", "runs.csv"}) {
    const std::string left = Read(dir + "/serial/" + file);
    EXPECT_FALSE(left.empty()) << file;
    EXPECT_TRUE(left == Read(dir + "/parallel/" + file)) << file << " differs";
  }
}

TEST(ReproJobs, ReproductionsWithoutUnitsRefuseJobs) {
  const std::string dir = MakeTempDir();
  const auto r = RunCommand(CliPath() + " repro pixhawk --jobs 2 --report " + dir + "/r");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--jobs 2: repro pixhawk runs in one process"), std::string::npos)
      << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir + "/r"));
}

}  // namespace
}  // namespace mavloc
