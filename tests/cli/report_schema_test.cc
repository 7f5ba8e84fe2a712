// Every report any command writes follows the one JSON Schema (schemas/report.schema.json),
// validated by Debian's python3-jsonschema (scripts/validate_report.py): compare on a simulated
// scenario and on a real log against a reference, eval on one estimate, several, and a folder of
// runs, sweep and sweep-merge, and every reproduction on small settings (obstacles: its own
// end-to-end suite, tests/cli/obstacles_test.cc, which renders the images, validates its report). A
// report written by one command is read without knowing which command wrote it: the same keys hold
// the ATE of compare and eval, and on the same estimate, truth and protocol they agree to 1e-9.
#include <gtest/gtest.h>

#include <filesystem>
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

bool HasJsonSchema() {
  static const bool has = RunCommand("/usr/bin/python3 -c 'import jsonschema'").exit_code == 0;
  return has;
}

// The cells of a Markdown table row: '|' separators that are not escaped as '\|'.
size_t CellCount(const std::string& line) {
  size_t bars = 0;
  for (size_t i = 0; i < line.size(); ++i)
    if (line[i] == '|' && (i == 0 || line[i - 1] != '\\')) ++bars;
  return bars > 0 ? bars - 1 : 0;
}

// Every table of a Markdown report has as many cells in each row as in its header.
void ExpectWellFormedTables(const std::string& markdown, const std::string& label) {
  std::istringstream lines(markdown);
  std::string line;
  size_t header_cells = 0;
  int line_number = 0;
  while (std::getline(lines, line)) {
    ++line_number;
    if (line.empty() || line[0] != '|') {
      header_cells = 0;
      continue;
    }
    if (header_cells == 0) {
      header_cells = CellCount(line);
      continue;
    }
    EXPECT_EQ(CellCount(line), header_cells)
        << label << " report.md line " << line_number << ": " << line;
  }
}

// True when one of the '_'-separated words of `key` is a display unit (yaw_deg, deg_per_m,
// render_ms_per_frame, position_rmse_cm).
bool NamesDisplayUnit(const std::string& key) {
  size_t begin = 0;
  while (begin <= key.size()) {
    const size_t end = std::min(key.find('_', begin), key.size());
    const std::string word = key.substr(begin, end - begin);
    if (word == "deg" || word == "mm" || word == "cm" || word == "ms") return true;
    begin = end + 1;
  }
  return false;
}

// Values in report.json are SI: no number under a key that names a display unit, no "unit" that
// is one, anywhere in the report (details included). Echoed settings are text and may keep their
// names ("bearing_noise_deg": "0.5").
void ExpectSiOnly(const nlohmann::json& j, const std::string& path, const std::string& label) {
  if (!j.is_object() && !j.is_array()) return;
  for (const auto& [key, value] : j.items()) {
    if (j.is_object() && NamesDisplayUnit(key))
      EXPECT_FALSE(value.is_number() || value.is_array() || value.is_object())
          << label << ": " << path << "/" << key;
    if (j.is_object() && key == "unit" && value.is_string())
      for (const char* display : {"deg", "mm", "cm", "ms", "deg/s"})
        EXPECT_NE(value.get<std::string>(), display) << label << ": " << path;
    ExpectSiOnly(value, path + "/" + key, label);
  }
}

// Runs `mavloc ARGS` (figures off), validates DIR/report.json (schema, SI only) and the tables of
// DIR/report.md.
nlohmann::json RunAndValidate(const std::string& args, const std::string& report_dir) {
  const auto run = RunCommand("MAVLOC_FIGURES=0 " + CliPath() + " " + args);
  EXPECT_EQ(run.exit_code, 0) << args << "\n" << run.output;
  const std::string path = report_dir + "/report.json";
  EXPECT_TRUE(fs::exists(path)) << args;
  if (!fs::exists(path)) return {};
  const std::string schema = testing::SourceDir() + "/schemas/report.schema.json";
  const auto valid = RunCommand("/usr/bin/python3 " + testing::SourceDir() +
                                "/scripts/validate_report.py " + schema + " " + path);
  EXPECT_EQ(valid.exit_code, 0) << args << "\n" << valid.output;
  ExpectWellFormedTables(ReadFileBytes(report_dir + "/report.md"), args);
  nlohmann::json report = nlohmann::json::parse(ReadFileBytes(path));
  ExpectSiOnly(report, "", args);
  return report;
}

#define REQUIRE_JSONSCHEMA() \
  if (!HasJsonSchema()) GTEST_SKIP() << "python3-jsonschema is not installed (scripts/setup)"

TEST(ReportSchema, CompareAndEvalAgreeOnTheSameProtocol) {
  REQUIRE_JSONSCHEMA();
  const std::string dir = MakeTempDir();
  const nlohmann::json compare = RunAndValidate(
      "compare --scenario mav-figure-eight --duration 6 --estimators smoother,imu-dead-reckoning "
      "--report " +
          dir + "/c",
      dir + "/c");
  ASSERT_FALSE(compare.is_null());
  EXPECT_EQ(compare["report_kind"], "compare");
  const nlohmann::json smoother = testing::ReportEstimator(compare, "smoother");
  ASSERT_TRUE(smoother.is_object()) << compare.dump(1);
  const double compare_ate = smoother["metrics"]["ate_translation"]["statistics"]["rmse"];
  EXPECT_GT(smoother["coverage"]["pairs"].get<int>(), 100);
  // eval on the files compare wrote, with compare's protocol (no alignment, truth interpolated
  // within 0.02 s).
  const nlohmann::json eval =
      RunAndValidate("eval --gt " + dir + "/c/truth.tum --est " + dir +
                         "/c/estimate_smoother.tum --label smoother --align none --t-max-diff "
                         "0.02 --out " +
                         dir + "/e",
                     dir + "/e");
  ASSERT_FALSE(eval.is_null());
  EXPECT_EQ(eval["report_kind"], "eval");
  const nlohmann::json evaluated = testing::ReportEstimator(eval, "smoother");
  ASSERT_TRUE(evaluated.is_object()) << eval.dump(1);
  EXPECT_NEAR(evaluated["metrics"]["ate_translation"]["statistics"]["rmse"].get<double>(),
              compare_ate, 1e-9);
  EXPECT_EQ(eval["protocol"]["alignment"], compare["protocol"]["alignment"]);
  EXPECT_EQ(eval["protocol"]["association"], compare["protocol"]["association"]);
}

TEST(ReportSchema, EvalOnSeveralEstimatesAndAFolderOfRuns) {
  REQUIRE_JSONSCHEMA();
  const std::string dir = MakeTempDir();
  const auto simulated =
      RunCommand("MAVLOC_FIGURES=0 " + CliPath() +
                 " compare --scenario mav-figure-eight --duration 4 --estimators "
                 "smoother,imu-dead-reckoning --report " +
                 dir + "/c");
  ASSERT_EQ(simulated.exit_code, 0) << simulated.output;
  fs::create_directories(dir + "/runs");
  fs::copy_file(dir + "/c/estimate_smoother.tum", dir + "/runs/run1.tum");
  fs::copy_file(dir + "/c/estimate_imu-dead-reckoning.tum", dir + "/runs/run2.tum");
  const nlohmann::json several = RunAndValidate(
      "eval --gt " + dir + "/c/truth.tum --est " + dir + "/c/estimate_smoother.tum --est " + dir +
          "/c/estimate_imu-dead-reckoning.tum --out " + dir + "/e2",
      dir + "/e2");
  EXPECT_EQ(several["estimators"].size(), 2u);
  const nlohmann::json folder = RunAndValidate(
      "eval --gt " + dir + "/c/truth.tum --est " + dir + "/runs --out " + dir + "/e3", dir + "/e3");
  EXPECT_EQ(folder["estimators"].size(), 2u);
  EXPECT_EQ(folder["provenance"]["runs"], 2);
}

TEST(ReportSchema, CompareOnARealLogAgainstAReference) {
  REQUIRE_JSONSCHEMA();
  REQUIRE_SHARED_DATA();
  const std::string dir = MakeTempDir();
  const std::string euroc = SharedDataDir() + "/euroc_v1_01_easy";
  const nlohmann::json report = RunAndValidate(
      "compare --dataset " + euroc + " --estimators imu-dead-reckoning --reference " + euroc +
          "/groundtruth_full_tum.txt --report " + dir + "/r",
      dir + "/r");
  ASSERT_FALSE(report.is_null());
  EXPECT_EQ(report["protocol"]["reference"], "estimate");
}

// imu-noise on the static part of PX4's sample log: the noise in SI units, measured or bounded.
TEST(ReportSchema, ImuNoise) {
  REQUIRE_JSONSCHEMA();
  REQUIRE_SHARED_DATA();
  const std::string dir = MakeTempDir();
  const nlohmann::json report = RunAndValidate(
      "imu-noise " + SharedDataDir() + "/px4_ulog/sample.ulg --from 8 --out " + dir + "/n",
      dir + "/n");
  ASSERT_FALSE(report.is_null());
  EXPECT_EQ(report["report_kind"], "imu-noise");
  ASSERT_EQ(report["tables"].size(), 2u);
  const auto& gyro = report["tables"][0];
  EXPECT_EQ(gyro["columns"][1]["unit"], "rad/s/sqrt(Hz)") << gyro.dump();
  // The white noise of the static gyroscope is measured, at the MEMS level (1e-5..1e-3).
  const auto& yaml_row = gyro["rows"][3];
  EXPECT_EQ(yaml_row[2], "measured") << yaml_row.dump();
  EXPECT_GT(yaml_row[1].get<double>(), 1e-5);
  EXPECT_LT(yaml_row[1].get<double>(), 1e-3);
}

TEST(ReportSchema, SweepAndSweepMerge) {
  REQUIRE_JSONSCHEMA();
  const std::string dir = MakeTempDir();
  const std::string grid =
      "sweep --scenario tag-arena-hover --duration 1 --seeds 1..2 --estimators tag-pnp --jobs 1 ";
  RunAndValidate(grid + "--out " + dir + "/s", dir + "/s");
  for (const char* shard : {"1/2", "2/2"})
    ASSERT_EQ(
        RunCommand(CliPath() + " " + grid + "--shard " + shard + " --out " + dir + "/p").exit_code,
        0);
  const nlohmann::json merged =
      RunAndValidate("sweep-merge " + dir + "/p --out " + dir + "/m", dir + "/m");
  EXPECT_EQ(merged["report_kind"], "sweep");
}

TEST(ReportSchema, EveryReproduction) {
  REQUIRE_JSONSCHEMA();
  const std::string dir = MakeTempDir();
  const std::vector<std::pair<std::string, std::string>> repros = {
      {"smoother", "--runs 1 --seed 5 --set scenarios=tag-arena-hover --set duration_s=3"},
      {"three-point", "--runs 1 --seed 3 --set noise_levels_deg=0.1 --set heights_m=0.4"},
      {"laser", "--runs 1 --seed 4 --set duration_s=4 --set euroc=false"},
      {"pixhawk", "--runs 1 --seed 6 --set tables=kf --set duration_s=4"},
      {"apriltag",
       "--runs 1 --seed 2 --set hover_duration_s=3 --set dynamic_duration_s=8 "
       "--set supersampling=1 --set decimate=2"},
  };
  for (const auto& [name, settings] : repros) {
    const std::string out = dir + "/" + name;
    const nlohmann::json report =
        RunAndValidate("repro " + name + " " + settings + " --report " + out, out);
    EXPECT_EQ(report["report_kind"], "repro") << name;
  }
  if (testing::HasSharedData()) {
    const std::string out = dir + "/euroc-imu-april";
    RunAndValidate("repro euroc-imu-april --set data=" + SharedDataDir() +
                       "/euroc_imu_april --set official=" + SharedDataDir() +
                       "/euroc_v1_01_easy/mav0 --set duration_s=8 --set estimators=tag-pnp "
                       "--report " +
                       out,
                   out);
  }
}

}  // namespace
}  // namespace mavloc
