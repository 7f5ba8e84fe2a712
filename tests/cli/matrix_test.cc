// mavloc matrix on rpg_trajectory_evaluation's folder layout, with sequences cut from the real
// ground truths of ../shared/data (two windows of EuRoC V1_01_easy and TagSLAM test 21's
// optimised trajectory, exported from its bag) and estimates made from them with seeded noise:
// "good" (1 cm) and "poor" (3 cm), six runs each. The LaTeX table marks the better estimator in
// bold on every sequence, the paired test finds it lower on all three, the bootstrap intervals are
// the same for the same seed, and the report follows the one schema.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
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

// ---- Hostile layouts, table-driven: refused naming the path, or run with every unused file said

// A small layout without shared data: ROOT/vio/mav_vio_seq with a truth and two runs.
std::string SmallLayout(const std::string& dir, const std::string& estimator = "vio") {
  const std::string folder = dir + "/mav/" + estimator + "/mav_" + estimator + "_seq";
  fs::create_directories(folder);
  std::vector<Row> rows;
  for (int i = 0; i < 300; ++i) {
    const double s = 0.05 * i;
    rows.push_back({100.0 + 0.05 * i, std::sin(s), std::sin(2 * s), 0.1 * s, 0, 0, 0, 1});
  }
  WriteTum(folder + "/stamped_groundtruth.txt", rows, 0.0, 0);
  WriteTum(folder + "/stamped_traj_estimate0.txt", rows, 0.01, 1);
  WriteTum(folder + "/stamped_traj_estimate1.txt", rows, 0.01, 2);
  return folder;
}

struct MatrixCase {
  const char* name;
  std::function<void(const std::string& sequence_folder)> prepare;
  std::string options;                                       // after ROOT
  int exit_code;                                             // 2: refused, 0: run
  std::vector<std::string> must_contain;                     // in the output (stderr and stdout)
  std::function<void(const std::string& out)> check_report;  // for runs
};

TEST(Matrix, HostileLayoutsAreRefusedOrEveryUnusedFileIsSaid) {
  const std::vector<MatrixCase> cases = {
      {"a named pipe named like a run (blocked open() before)",
       [](const std::string& f) {
         fs::remove(f + "/stamped_traj_estimate1.txt");
         ASSERT_EQ(::mkfifo((f + "/stamped_traj_estimate1.txt").c_str(), 0644), 0);
       },
       "",
       2,
       {"stamped_traj_estimate1.txt", "named pipe"},
       nullptr},
      {"a sequence folder that is a link to itself",
       [](const std::string& f) {
         fs::create_directory_symlink("mav_vio_loop", fs::path(f).parent_path() / "mav_vio_loop");
       },
       "",
       2,
       {"mav_vio_loop", "loop of symbolic links"},
       nullptr},
      {"a run file that is a link to itself",
       [](const std::string& f) {
         fs::remove(f + "/stamped_traj_estimate1.txt");
         fs::create_symlink("stamped_traj_estimate1.txt", f + "/stamped_traj_estimate1.txt");
       },
       "",
       2,
       {"stamped_traj_estimate1.txt", "loop of symbolic links"},
       nullptr},
      {"--t-max-diff nan",
       [](const std::string&) {},
       "--t-max-diff nan",
       2,
       {"--t-max-diff", "not a finite number"},
       nullptr},
      {"--t-max-diff inf",
       [](const std::string&) {},
       "--t-max-diff inf",
       2,
       {"--t-max-diff"},
       nullptr},
      {"a run number beyond six digits",
       [](const std::string& f) {
         fs::copy_file(f + "/stamped_traj_estimate0.txt",
                       f + "/stamped_traj_estimate999999999.txt");
       },
       "",
       0,
       {"warning", "stamped_traj_estimate999999999.txt", "run number beyond 999999"},
       [](const std::string& out) {
         EXPECT_NE(ReadFileBytes(out + "/report.md").find("stamped_traj_estimate999999999.txt"),
                   std::string::npos);
       }},
      {"an unnumbered run beside numbered ones",
       [](const std::string& f) {
         fs::copy_file(f + "/stamped_traj_estimate0.txt", f + "/stamped_traj_estimate.txt");
       },
       "",
       0,
       {"warning", "stamped_traj_estimate.txt", "unnumbered run beside numbered"},
       nullptr},
      {"one run number twice (1 and 01)",
       [](const std::string& f) {
         fs::copy_file(f + "/stamped_traj_estimate1.txt", f + "/stamped_traj_estimate01.txt");
       },
       "",
       0,
       {"warning", "run 1 again"},
       nullptr},
      {"another file in a sequence folder is listed",
       [](const std::string& f) { testing::WriteFileBytes(f + "/notes.txt", "x\n"); },
       "",
       0,
       {"1 file(s) not used"},
       [](const std::string& out) {
         EXPECT_NE(ReadFileBytes(out + "/report.md").find("notes.txt"), std::string::npos);
       }},
  };
  for (const MatrixCase& c : cases) {
    SCOPED_TRACE(c.name);
    const std::string dir = MakeTempDir();
    c.prepare(SmallLayout(dir));
    if (HasFatalFailure()) return;
    const auto run = RunCommand("cd " + dir + " && MAVLOC_FIGURES=0 timeout 60 " + CliPath() +
                                " matrix mav " + c.options + " --out o");
    EXPECT_EQ(run.exit_code, c.exit_code) << run.output;
    EXPECT_EQ(run.output.find("internal error"), std::string::npos) << run.output;
    for (const auto& text : c.must_contain)
      EXPECT_NE(run.output.find(text), std::string::npos) << "'" << text << "' in " << run.output;
    EXPECT_EQ(fs::exists(dir + "/o"), c.exit_code == 0);
    for (const auto& entry : fs::directory_iterator(dir))
      EXPECT_EQ(entry.path().filename().string().find(".tmp-"), std::string::npos)
          << "left: " << entry.path();
    if (c.check_report && c.exit_code == 0) c.check_report(dir + "/o");
  }
}

TEST(Matrix, NamesThatAreCsvOrLatexSyntaxAreQuotedAndEscaped) {
  const std::string dir = MakeTempDir();
  SmallLayout(dir, "ok,vis");
  SmallLayout(dir, "a\\b~c");
  const auto run =
      RunCommand("cd " + dir + " && MAVLOC_FIGURES=0 " + CliPath() + " matrix mav --out o");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const std::string runs = ReadFileBytes(dir + "/o/runs.csv");
  EXPECT_NE(runs.find("\"ok,vis\",seq,0,"), std::string::npos) << runs;
  EXPECT_NE(ReadFileBytes(dir + "/o/relative_errors.csv").find("\"ok,vis\",seq,"),
            std::string::npos);
  const std::string tex = ReadFileBytes(dir + "/o/matrix.tex");
  EXPECT_NE(tex.find("a\\textbackslash{}b\\textasciitilde{}c"), std::string::npos) << tex;
}

}  // namespace
}  // namespace mavloc
