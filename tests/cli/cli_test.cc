// The mavloc executable end to end: simulate -> run -> eval -> compare, and every bad-input case
// of a dataset folder: one clear line on stderr, exit code 2, no partial output file left behind.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "tests/report_support.h"
#include "tests/test_support.h"

namespace fs = std::filesystem;

namespace mavloc {
namespace {

using testing::CliPath;
using testing::MakeTempDir;
using testing::RunCommand;

std::string Cli(const std::string& args) { return CliPath() + " " + args; }

void ExpectCleanFailure(const testing::CommandResult& r, const std::string& must_contain) {
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find(must_contain), std::string::npos) << r.output;
  // One line on stderr (the output is stderr only for failures before any work was printed).
  EXPECT_LE(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
}

void ExpectNoFilesUnder(const std::string& dir) {
  if (!fs::exists(dir)) return;
  for (const auto& entry : fs::recursive_directory_iterator(dir)) {
    EXPECT_FALSE(entry.is_regular_file()) << "left behind: " << entry.path();
  }
}

class CliPipeline : public ::testing::Test {
 protected:
  // One dataset per process (ctest runs every test in its own process, in parallel).
  static void SetUpTestSuite() {
    dir_ = new std::string(fs::temp_directory_path() /
                           ("mavloc_cli_pipeline_" + std::to_string(::getpid())));
    fs::remove_all(*dir_);
    fs::create_directories(*dir_);
    simulate_ = new testing::CommandResult(RunCommand(Cli(
        "simulate --scenario mav-figure-eight --duration 6 --seed 3 --out " + *dir_ + "/data")));
  }
  static void TearDownTestSuite() { fs::remove_all(*dir_); }
  // A failed set-up fails every test (rather than skipping it).
  void SetUp() override { ASSERT_EQ(simulate_->exit_code, 0) << simulate_->output; }
  static std::string* dir_;
  static testing::CommandResult* simulate_;
};
std::string* CliPipeline::dir_ = nullptr;
testing::CommandResult* CliPipeline::simulate_ = nullptr;

TEST_F(CliPipeline, SimulateWritesAnEurocFolder) {
  for (const char* f :
       {"/data/mav0/imu0/data.csv", "/data/mav0/imu0/sensor.yaml", "/data/mav0/cam0/sensor.yaml",
        "/data/mav0/state_groundtruth_estimate0/data.csv", "/data/mav0/features0/data.csv",
        "/data/map.yaml", "/data/scenario.yaml"})
    EXPECT_TRUE(fs::exists(*dir_ + f)) << f;
  // Same seed, same bytes.
  const auto r = RunCommand(
      Cli("simulate --scenario mav-figure-eight --duration 6 --seed 3 --out " + *dir_ + "/again"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (const char* f : {"/mav0/imu0/data.csv", "/mav0/features0/data.csv",
                        "/mav0/state_groundtruth_estimate0/data.csv"}) {
    std::ifstream a(*dir_ + "/data" + f), b(*dir_ + "/again" + f);
    EXPECT_TRUE(
        std::equal(std::istreambuf_iterator<char>(a), {}, std::istreambuf_iterator<char>(b), {}))
        << f;
  }
}

TEST_F(CliPipeline, RunThenEval) {
  const std::string est = *dir_ + "/dr.txt";
  auto r = RunCommand(
      Cli("run --dataset " + *dir_ + "/data --estimator imu-dead-reckoning --out " + est));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = RunCommand(Cli("eval --gt " + *dir_ +
                     "/data/mav0/state_groundtruth_estimate0/data.csv --est " + est +
                     " --align se3 --json " + *dir_ + "/eval.json"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("ATE translation"), std::string::npos);
  std::ifstream in(*dir_ + "/eval.json");
  const auto j = nlohmann::json::parse(in)["details"];  // eval's own layout
  EXPECT_GT(j["pairs"].get<int>(), 100);
  EXPECT_GE(j["ate"]["rmse"].get<double>(), 0.0);
  // Quantities as CSV.
  r = RunCommand(Cli("run --dataset " + *dir_ + "/data --estimator imu-dead-reckoning --out " +
                     *dir_ + "/dr.csv"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::ifstream csv(*dir_ + "/dr.csv");
  std::string header;
  std::getline(csv, header);
  EXPECT_NE(header.find("roll [rad]"), std::string::npos) << header;
}

TEST_F(CliPipeline, CompareWritesTheReportContract) {
  const std::string report = *dir_ + "/report";
  const auto r = RunCommand(Cli("compare --dataset " + *dir_ +
                                "/data --estimators imu-dead-reckoning --report " + report));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("| imu-dead-reckoning |"), std::string::npos) << r.output;
  std::ifstream in(report + "/report.json");
  const auto j = nlohmann::json::parse(in);
  const auto e = testing::ReportEstimator(j, "imu-dead-reckoning");
  for (const char* q : {"x", "y", "z", "roll", "pitch", "yaw"}) {
    const auto stats = testing::MetricStatistics(e, q);
    ASSERT_TRUE(stats.is_object()) << q;
    EXPECT_TRUE(stats.contains("mean"));
    EXPECT_TRUE(stats.contains("rmse"));
  }
  EXPECT_EQ(e["metrics"]["x"]["unit"], "m");
  EXPECT_EQ(e["metrics"]["yaw"]["unit"], "rad");  // SI in JSON; degrees only in the tables
  EXPECT_TRUE(testing::MetricStatistics(e, "ate_translation").contains("rmse"));
  EXPECT_EQ(j["protocol"]["alignment"], "none");
  EXPECT_TRUE(e.contains("runtime_s"));
  EXPECT_EQ(j["report_kind"], "compare");
  EXPECT_TRUE(j["provenance"]["input"].get<std::string>().find("data") != std::string::npos);
  EXPECT_TRUE(fs::exists(report + "/report.md"));
  EXPECT_TRUE(fs::exists(report + "/errors.csv"));
}

TEST(CliHelp, EveryCommandHasHelp) {
  for (const char* command : {"", "list", "simulate", "run", "eval", "compare", "repro",
                              "import-aprilgrid", "detect-tags"}) {
    const auto r = RunCommand(Cli(std::string(command) + " --help"));
    EXPECT_EQ(r.exit_code, 0) << command << r.output;
    EXPECT_NE(r.output.find("Usage"), std::string::npos) << command;
  }
}

// ---- bad input ----

TEST(CliBadInput, UnknownOptionAndCommand) {
  ExpectCleanFailure(RunCommand(Cli("compare --frobnicate")), "frobnicate");
  ExpectCleanFailure(RunCommand(Cli("fly")), "fly");
}

TEST(CliBadInput, UnknownScenarioAndEstimator) {
  const std::string dir = MakeTempDir();
  ExpectCleanFailure(RunCommand(Cli("simulate --scenario nowhere --out " + dir + "/x")),
                     "unknown scenario 'nowhere'");
  ExpectNoFilesUnder(dir);
  ExpectCleanFailure(
      RunCommand(Cli("compare --estimators imu-dead-reckoning,nobody --report " + dir + "/r")),
      "unknown estimator 'nobody'");
  ExpectNoFilesUnder(dir);
}

TEST(CliBadInput, MissingFileAndFolder) {
  const std::string dir = MakeTempDir();
  ExpectCleanFailure(RunCommand(Cli("eval --gt /nonexistent/gt.txt --est /nonexistent/est.txt")),
                     "/nonexistent/gt.txt: file does not exist");
  ExpectCleanFailure(
      RunCommand(Cli("run --dataset /nonexistent/ds --estimator imu-dead-reckoning --out " + dir +
                     "/o.txt")),
      "dataset folder does not exist");
  ExpectNoFilesUnder(dir);
}

class CliBadFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = MakeTempDir();
    Write("gt.txt", "1.0 0 0 0 0 0 0 1\n2.0 1 0 0 0 0 0 1\n3.0 2 0 0 0 0 0 1\n4.0 3 1 0 0 0 0 1\n");
  }
  void Write(const std::string& name, const std::string& body) {
    std::ofstream(dir_ + "/" + name) << body;
  }
  testing::CommandResult Eval(const std::string& est) {
    return RunCommand(Cli("eval --gt " + dir_ + "/gt.txt --est " + dir_ + "/" + est + " --json " +
                          dir_ + "/out/e.json"));
  }
  std::string dir_;
};

TEST_F(CliBadFiles, MalformedRow) {
  Write("est.txt", "1.0 0 0 0 0 0 0 1\n2.0 1 0 zero 0 0 0 1\n");
  ExpectCleanFailure(Eval("est.txt"), "est.txt:2: field 'tz': 'zero' is not a number");
}

TEST_F(CliBadFiles, NonMonotonicAndDuplicateTimestamps) {
  Write("est.txt", "2.0 0 0 0 0 0 0 1\n1.0 1 0 0 0 0 0 1\n");
  ExpectCleanFailure(Eval("est.txt"), "est.txt:2: field 'timestamp'");
  // A repeated stamp keeps the first row and is reported, as evo and TUM's tools do.
  Write("dup.txt",
        "1.0 0 0 0 0 0 0 1\n1.0 1 0 0 0 0 0 1\n2.0 1 0 0 0 0 0 1\n3.0 2 0 0 0 0 0 1\n4.0 3 1 0 0 0 "
        "0 1\n");
  const auto dup =
      RunCommand(Cli("eval --align none --gt " + dir_ + "/gt.txt --est " + dir_ + "/dup.txt"));
  EXPECT_EQ(dup.exit_code, 0) << dup.output;
  EXPECT_NE(dup.output.find("dup.txt: 1 row with a repeated timestamp dropped"), std::string::npos)
      << dup.output;
}

TEST_F(CliBadFiles, NanInfAndEmpty) {
  Write("nan.txt", "1.0 nan 0 0 0 0 0 1\n");
  ExpectCleanFailure(Eval("nan.txt"), "nan.txt:1: field 'tx'");
  Write("inf.txt", "1.0 0 0 0 0 0 0 1\n2.0 inf 0 0 0 0 0 1\n");
  ExpectCleanFailure(Eval("inf.txt"), "not finite");
  Write("empty.txt", "");
  ExpectCleanFailure(Eval("empty.txt"), "empty.txt: file has no data rows");
}

TEST_F(CliBadFiles, GroundTruthThatDoesNotOverlap) {
  Write("late.txt", "100.0 0 0 0 0 0 0 1\n101.0 1 0 0 0 0 0 1\n");
  ExpectCleanFailure(Eval("late.txt"), "no estimate stamp overlaps the ground truth");
}

TEST_F(CliBadFiles, NoPartialOutputOnFailure) {
  Write("est.txt", "1.0 0 0 0 0 0 0 1\n2.0 1 0 0 0 0 0 1\n3.0 2 0 0 0 0 0 1\n4.0 3 1 0 0 0 0 1\n");
  // The --json folder does not exist: the error names it, and nothing is left behind.
  const auto r = Eval("est.txt");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("out/e.json"), std::string::npos) << r.output;
  for (const auto& entry : fs::directory_iterator(dir_))
    EXPECT_EQ(entry.path().filename().string().find(".tmp-"), std::string::npos) << entry.path();
}

TEST_F(CliBadFiles, BadSettingValue) {
  ExpectCleanFailure(
      RunCommand(
          Cli("simulate --scenario mav-figure-eight --set landmarks=many --out " + dir_ + "/s")),
      "setting 'landmarks=many': expected an integer");
  EXPECT_FALSE(fs::exists(dir_ + "/s"));
}

TEST_F(CliBadFiles, MalformedReferenceTrajectory) {
  // compare --reference FILE reads the file with the trajectory readers' checks.
  Write("ref.txt", "1.0 0 0 0 0 0 0 1\n2.0 1 0 zero 0 0 0 1\n");
  ExpectCleanFailure(RunCommand(Cli("compare --scenario mav-figure-eight --duration 4 "
                                    "--estimators imu-dead-reckoning --reference " +
                                    dir_ + "/ref.txt --report " + dir_ + "/r")),
                     "ref.txt:2: field 'tz': 'zero' is not a number");
  EXPECT_FALSE(fs::exists(dir_ + "/r"));
}

TEST_F(CliBadFiles, BadIssue12Options) {
  ExpectCleanFailure(RunCommand(Cli("repro euroc-imu-april --set nope=1 --report " + dir_ + "/r")),
                     "unknown setting 'nope'");
  ExpectCleanFailure(
      RunCommand(Cli("repro euroc-imu-april --set initial=guess --report " + dir_ + "/r")),
      "initial must be coarse or official");
  ExpectCleanFailure(RunCommand(Cli("repro euroc-imu-april --set estimators=tag-ekf:gate "
                                    "--report " +
                                    dir_ + "/r")),
                     "must read name:key=value");
  EXPECT_FALSE(fs::exists(dir_ + "/r"));
  Write("img.png", "not an image");
  ExpectCleanFailure(RunCommand(Cli("detect-tags --family tag99h99 --images " + dir_ +
                                    "/img.png --out " + dir_ + "/t.csv")),
                     "tag99h99");
  EXPECT_FALSE(fs::exists(dir_ + "/t.csv"));
}

}  // namespace
}  // namespace mavloc
