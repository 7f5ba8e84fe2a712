// mavloc matrix on rpg_trajectory_evaluation's folder layout, with sequences cut from the real
// ground truths of ../shared/data (two windows of EuRoC V1_01_easy and TagSLAM test 21's
// optimised trajectory, exported from its bag) and estimates made from them with seeded noise:
// "good" (1 cm) and "poor" (3 cm), six runs each. The LaTeX table marks the better estimator in
// bold on every sequence, the paired test finds it lower on all three, the bootstrap intervals are
// the same for the same seed, and the report follows the one schema.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <map>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "tests/test_support.h"

namespace fs = std::filesystem;

namespace mavloc {
namespace {

using testing::CliPath;
using testing::MakeTempDir;
using testing::ReadFileBytes;
using testing::RunCommand;
using testing::SharedDataDir;

struct Row {
  double t, x, y, z, qx, qy, qz, qw;
};

std::vector<Row> ReadTum(const std::string& path) {
  std::ifstream in(path);
  std::vector<Row> rows;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    Row r;
    std::istringstream(line) >> r.t >> r.x >> r.y >> r.z >> r.qx >> r.qy >> r.qz >> r.qw;
    rows.push_back(r);
  }
  return rows;
}

void WriteTum(const std::string& path, const std::vector<Row>& rows, double noise_m,
              uint64_t seed) {
  std::mt19937_64 generator(seed);
  std::normal_distribution<double> noise(0.0, noise_m);
  std::ofstream out(path);
  out << "# timestamp tx ty tz qx qy qz qw\n" << std::setprecision(17);
  for (const Row& r : rows)
    out << r.t << " " << r.x + (noise_m > 0 ? noise(generator) : 0.0) << " "
        << r.y + (noise_m > 0 ? noise(generator) : 0.0) << " "
        << r.z + (noise_m > 0 ? noise(generator) : 0.0) << " " << r.qx << " " << r.qy << " " << r.qz
        << " " << r.qw << "\n";
}

// ROOT/<estimator>/mav_<estimator>_<sequence>/ with the ground truth and three runs.
std::string MakeLayout(const std::string& dir) {
  std::map<std::string, std::vector<Row>> sequences;
  const std::vector<Row> euroc =
      ReadTum(SharedDataDir() + "/euroc_v1_01_easy/groundtruth_full_tum.txt");
  sequences["euroc_a"] = std::vector<Row>(euroc.begin() + 2000, euroc.begin() + 5000);
  sequences["euroc_b"] = std::vector<Row>(euroc.begin() + 12000, euroc.begin() + 15000);
  const auto convert = RunCommand(CliPath() + " convert --in " + SharedDataDir() +
                                  "/tagslam/test_21/reference.bag.bz2:/tagslam/odom/body_rig "
                                  "--out " +
                                  dir + "/tagslam.tum --format tum");
  EXPECT_EQ(convert.exit_code, 0) << convert.output;
  sequences["tagslam_21"] = ReadTum(dir + "/tagslam.tum");
  const std::string root = dir + "/mav";
  uint64_t seed = 1;
  for (const auto& [estimator, noise_m] : {std::pair{"good", 0.01}, std::pair{"poor", 0.03}}) {
    for (const auto& [sequence, rows] : sequences) {
      const std::string folder = root + "/" + estimator + "/mav_" + estimator + "_" + sequence;
      fs::create_directories(folder);
      WriteTum(folder + "/stamped_groundtruth.txt", rows, 0.0, 0);
      for (int run = 0; run < 6; ++run)
        WriteTum(folder + "/stamped_traj_estimate" + std::to_string(run) + ".txt", rows, noise_m,
                 seed++);
    }
  }
  return root;
}

TEST(Matrix, EstimatorsBySequencesWithIntervalsPairedTestsAndLatex) {
  REQUIRE_SHARED_DATA();
  const std::string dir = MakeTempDir();
  const std::string root = MakeLayout(dir);
  const auto run = RunCommand("MAVLOC_FIGURES=0 " + CliPath() + " matrix " + root +
                              " --seed 7 --out " + dir + "/m");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("2 estimators x 3 sequences"), std::string::npos) << run.output;
  const auto report = nlohmann::json::parse(ReadFileBytes(dir + "/m/report.json"));
  EXPECT_EQ(report["report_kind"], "matrix");
  EXPECT_EQ(report["provenance"]["runs"], 36);
  const auto valid =
      RunCommand("/usr/bin/python3 " + testing::SourceDir() + "/scripts/validate_report.py " +
                 testing::SourceDir() + "/schemas/report.schema.json " + dir + "/m/report.json");
  if (RunCommand("/usr/bin/python3 -c 'import jsonschema'").exit_code == 0) {
    EXPECT_EQ(valid.exit_code, 0) << valid.output;
  }

  // The cells: about sqrt(3) x the noise per axis, and an interval around the mean.
  nlohmann::json cells, pairs;
  for (const auto& table : report["tables"]) {
    if (table["name"] == "ate_rmse_cells") cells = table;
    if (table["name"] == "paired_tests") pairs = table;
  }
  ASSERT_EQ(cells["rows"].size(), 6u);
  for (const auto& row : cells["rows"]) {
    const double mean = row[3], low = row[5], high = row[6];
    const double expected = std::sqrt(3.0) * (row[0] == "good" ? 0.01 : 0.03);
    EXPECT_NEAR(mean, expected, 0.2 * expected) << row.dump();
    EXPECT_LE(low, mean);
    EXPECT_GE(high, mean);
  }
  // The paired test: good is lower on all 3 sequences; exact two-sided p = 2/8.
  ASSERT_EQ(pairs["rows"].size(), 1u);
  EXPECT_EQ(pairs["rows"][0][3], 3);
  EXPECT_NEAR(pairs["rows"][0][6].get<double>(), 0.25, 1e-12);
  // LaTeX: the better estimator in bold on every sequence.
  const std::string tex = ReadFileBytes(dir + "/m/matrix.tex");
  size_t bold = 0;
  for (size_t at = tex.find("\\textbf{"); at != std::string::npos;
       at = tex.find("\\textbf{", at + 1))
    ++bold;
  EXPECT_EQ(bold, 3u) << tex;
  EXPECT_NE(tex.find("tagslam\\_21"), std::string::npos) << tex;
  // Relative errors for the grouped boxplots, at the same lengths for both estimators.
  const std::string relative = ReadFileBytes(dir + "/m/relative_errors.csv");
  EXPECT_NE(relative.find("good,euroc_a,0,"), std::string::npos);
  EXPECT_NE(relative.find("poor,euroc_a,0,"), std::string::npos);

  // The same seed gives the same intervals; another seed other ones.
  const auto again = RunCommand("MAVLOC_FIGURES=0 " + CliPath() + " matrix " + root +
                                " --seed 7 --out " + dir + "/m2");
  ASSERT_EQ(again.exit_code, 0) << again.output;
  const auto other = RunCommand("MAVLOC_FIGURES=0 " + CliPath() + " matrix " + root +
                                " --seed 8 --out " + dir + "/m3");
  ASSERT_EQ(other.exit_code, 0) << other.output;
  const auto tables = [&](const std::string& folder) {
    return nlohmann::json::parse(ReadFileBytes(folder + "/report.json"))["tables"];
  };
  EXPECT_EQ(tables(dir + "/m"), tables(dir + "/m2"));
  EXPECT_NE(tables(dir + "/m"), tables(dir + "/m3"));
}

TEST(Matrix, AFolderOutsideTheLayoutIsRefused) {
  const std::string dir = MakeTempDir();
  fs::create_directories(dir + "/root/vio/mav_vio_seq");
  const auto run = RunCommand(CliPath() + " matrix " + dir + "/root --out " + dir + "/m");
  EXPECT_EQ(run.exit_code, 2) << run.output;
  EXPECT_NE(run.output.find("stamped_groundtruth.txt"), std::string::npos) << run.output;
  EXPECT_FALSE(fs::exists(dir + "/m"));
}

}  // namespace
}  // namespace mavloc
