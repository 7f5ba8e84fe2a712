// mavloc sweep end to end: a parallel run gives the bytes of a serial run, shards merged
// in any order give the bytes of the single run, every merge problem (missing or duplicate shard,
// mismatched fingerprint, incomplete partial) exits with 2 and names the problem, and --slurm
// writes and submits the job array and the merge job (through a stand-in sbatch that records its
// arguments; tests/integration/slurm_sweep_test.cc runs a real Slurm).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>

#include "tests/test_support.h"

namespace fs = std::filesystem;

namespace mavloc {
namespace {

using testing::CliPath;
using testing::MakeTempDir;
using testing::RunCommand;

// A small grid: 2 corner-noise settings x 3 seeds on a 3 s hover, two estimators (one of them the
// Ceres smoother, whose thread pool is the reason workers are processes).
const std::string kGrid =
    "--scenario tag-arena-hover --duration 3 --seeds 1..3 --set corner_noise_px=0.3,1 "
    "--estimators tag-pnp,smoother";

std::string Read(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// The same bytes in report.md (up to its figure section, which names the folder) and runs.csv,
// and the same report.json but its provenance (the command line and the elapsed time differ
// between a serial run and a merge of shards).
std::string BeforeFigures(const std::string& markdown) {
  return markdown.substr(0, markdown.find("<!-- mavloc:figures -->"));
}

void ExpectSameReport(const std::string& a, const std::string& b) {
  for (const char* name : {"report.md", "runs.csv"}) {
    const std::string left = BeforeFigures(Read(a + "/" + name));
    const std::string right = BeforeFigures(Read(b + "/" + name));
    EXPECT_FALSE(left.empty()) << a << "/" << name;
    EXPECT_TRUE(left == right) << name << " differs between " << a << " and " << b;
  }
  nlohmann::json left = nlohmann::json::parse(Read(a + "/report.json"));
  nlohmann::json right = nlohmann::json::parse(Read(b + "/report.json"));
  left.erase("provenance");
  right.erase("provenance");
  EXPECT_TRUE(left == right) << "report.json differs between " << a << " and " << b << ":\n"
                             << nlohmann::json::diff(left, right).dump(1);
}

void ExpectExit2(const testing::CommandResult& r, const std::string& must_contain) {
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find(must_contain), std::string::npos) << r.output;
}

class SweepCli : public ::testing::Test {
 protected:
  // The serial run and the shards, once per process (each test of this file reads them).
  static void SetUpTestSuite() {
    dir_ = new std::string(MakeTempDir());
    serial_ = new testing::CommandResult(
        RunCommand(CliPath() + " sweep " + kGrid + " --jobs 1 --out " + *dir_ + "/serial"));
    shards_ok_ = true;
    for (int i = 1; i <= 3; ++i) {
      const auto r = RunCommand(CliPath() + " sweep " + kGrid + " --jobs 1 --shard " +
                                std::to_string(i) + "/3 --out " + *dir_ + "/partials");
      shards_ok_ = shards_ok_ && r.exit_code == 0;
      if (r.exit_code != 0) ADD_FAILURE() << r.output;
    }
  }
  static void TearDownTestSuite() { fs::remove_all(*dir_); }
  void SetUp() override {
    ASSERT_EQ(serial_->exit_code, 0) << serial_->output;
    ASSERT_TRUE(shards_ok_);
  }
  static std::string P(const std::string& rel) { return *dir_ + "/" + rel; }
  static std::string* dir_;
  static testing::CommandResult* serial_;
  static bool shards_ok_;
};
std::string* SweepCli::dir_ = nullptr;
testing::CommandResult* SweepCli::serial_ = nullptr;
bool SweepCli::shards_ok_ = false;

TEST_F(SweepCli, ReportHoldsEveryRunAndCellStatistics) {
  const auto report = nlohmann::json::parse(Read(P("serial/report.json")))["details"];
  EXPECT_EQ(report["sweep"]["units"], 6);
  ASSERT_EQ(report["runs"].size(), 6u);
  // Unit order: settings combination, then seed (the last axis fastest).
  EXPECT_EQ(report["runs"][0]["settings"]["corner_noise_px"], "0.3");
  EXPECT_EQ(report["runs"][0]["seed"], 1);
  EXPECT_EQ(report["runs"][4]["settings"]["corner_noise_px"], "1");
  EXPECT_EQ(report["runs"][4]["seed"], 2);
  // 2 settings x 2 estimators = 4 cells of 3 seeds each, and the smoother ran.
  ASSERT_EQ(report["cells"].size(), 4u);
  for (const auto& cell : report["cells"]) {
    EXPECT_EQ(cell["runs"], 3);
    EXPECT_EQ(cell["ran"], 3) << cell.dump();
    EXPECT_EQ(cell["metrics"]["ate_rmse"]["n"], 3);
    EXPECT_GT(cell["metrics"]["ate_rmse"]["mean"].get<double>(), 0.0);
    EXPECT_LT(cell["metrics"]["ate_rmse"]["mean"].get<double>(), 0.1);  // metres, not a failure
  }
  // The cell mean is the mean of the per-run rows.
  double sum = 0.0;
  for (int k = 0; k < 3; ++k)
    sum += report["runs"][k]["estimators"][1]["metrics"]["ate_rmse"].get<double>();
  EXPECT_EQ(report["cells"][1]["estimator"], "smoother");
  EXPECT_DOUBLE_EQ(report["cells"][1]["metrics"]["ate_rmse"]["mean"].get<double>(), sum / 3.0);
  const std::string csv = Read(P("serial/runs.csv"));
  EXPECT_EQ(csv.rfind("unit,scenario,settings,seed,estimator,ran,metric,unit,value\n", 0), 0u);
  EXPECT_NE(csv.find("\n5,tag-arena-hover,corner_noise_px=1,3,smoother,1,ate_rmse,m,"),
            std::string::npos);
  // report.md: one table per scenario, settings and unit; angles shown in degrees.
  const std::string md = Read(P("serial/report.md"));
  EXPECT_NE(md.find("### tag-arena-hover (corner_noise_px=1): metrics in m,"), std::string::npos);
  EXPECT_NE(md.find("### tag-arena-hover (corner_noise_px=1): angles,"), std::string::npos);
  EXPECT_NE(md.find("| mean [mm] |"), std::string::npos);
  EXPECT_NE(md.find("| mean [deg] |"), std::string::npos);
  // report.json: the rotation metric in radians, its table's columns in rad.
  EXPECT_EQ(report["cells"][0]["metrics"]["ate_rotation_rmse"]["unit"], "rad");
  EXPECT_EQ(report["runs"][0]["estimators"][0]["units"]["ate_rotation_rmse"], "rad");
}

TEST_F(SweepCli, TwoJobsGiveTheSerialBytes) {
  const auto r = RunCommand(CliPath() + " sweep " + kGrid + " --jobs 2 --out " + P("parallel"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  ExpectSameReport(P("serial"), P("parallel"));
}

TEST_F(SweepCli, ShardsMergedInAnyOrderGiveTheSingleRunBytes) {
  // Files in scrambled order, and the folder itself.
  auto r = RunCommand(CliPath() + " sweep-merge " + P("partials/partial-3-of-3.json") + " " +
                      P("partials/partial-1-of-3.json") + " " + P("partials/partial-2-of-3.json") +
                      " --out " + P("merged_files"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  ExpectSameReport(P("serial"), P("merged_files"));
  r = RunCommand(CliPath() + " sweep-merge " + P("partials") + " --out " + P("merged_dir"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  ExpectSameReport(P("serial"), P("merged_dir"));
}

TEST_F(SweepCli, MissingShardIsNamed) {
  fs::create_directories(P("two"));
  fs::copy_file(P("partials/partial-1-of-3.json"), P("two/partial-1-of-3.json"));
  fs::copy_file(P("partials/partial-3-of-3.json"), P("two/partial-3-of-3.json"));
  // An interrupted shard leaves only its temporary file, which is never taken for a partial.
  std::ofstream(P("two/partial-2-of-3.json.tmp-12345")) << "{\"format\": \"mavloc-sweep-part";
  const auto r = RunCommand(CliPath() + " sweep-merge " + P("two") + " --out " + P("m_missing"));
  ExpectExit2(r, "missing shard(s) 2 of 3");
  EXPECT_NE(r.output.find("interrupted shard files"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(P("m_missing/report.md")));
}

TEST_F(SweepCli, DuplicateShardIsNamed) {
  fs::create_directories(P("dup"));
  fs::copy_file(P("partials/partial-2-of-3.json"), P("dup/partial-2-of-3.json"));
  const auto r = RunCommand(CliPath() + " sweep-merge " + P("partials") + " " + P("dup") +
                            " --out " + P("m_dup"));
  ExpectExit2(r, "duplicate shard 2/3");
  EXPECT_FALSE(fs::exists(P("m_dup/report.md")));
}

TEST_F(SweepCli, MismatchedFingerprintIsNamed) {
  // Shard 2 of the same layout but another grid (seeds 4..6).
  const std::string other =
      "--scenario tag-arena-hover --duration 3 --seeds 4..6 --set corner_noise_px=0.3,1 "
      "--estimators tag-pnp";
  auto r = RunCommand(CliPath() + " sweep " + other + " --jobs 1 --shard 2/3 --out " + P("other"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = RunCommand(CliPath() + " sweep-merge " + P("partials/partial-1-of-3.json") + " " +
                 P("other/partial-2-of-3.json") + " " + P("partials/partial-3-of-3.json") +
                 " --out " + P("m_fp"));
  ExpectExit2(r, "mismatched fingerprint");
  EXPECT_FALSE(fs::exists(P("m_fp/report.md")));
}

TEST_F(SweepCli, IncompletePartialIsNamed) {
  fs::create_directories(P("incomplete"));
  for (int i : {1, 3})
    fs::copy_file(P("partials/partial-" + std::to_string(i) + "-of-3.json"),
                  P("incomplete/partial-" + std::to_string(i) + "-of-3.json"));
  // Without the complete marker.
  auto json = nlohmann::json::parse(Read(P("partials/partial-2-of-3.json")));
  json["complete"] = false;
  std::ofstream(P("incomplete/partial-2-of-3.json")) << json.dump();
  auto r = RunCommand(CliPath() + " sweep-merge " + P("incomplete") + " --out " + P("m_inc"));
  ExpectExit2(r, "incomplete partial: no \"complete\": true marker");
  // Cut short (e.g. an interrupted copy).
  const std::string text = Read(P("partials/partial-2-of-3.json"));
  std::ofstream(P("incomplete/partial-2-of-3.json"), std::ios::trunc)
      << text.substr(0, text.size() / 2);
  r = RunCommand(CliPath() + " sweep-merge " + P("incomplete") + " --out " + P("m_inc"));
  ExpectExit2(r, "incomplete partial: not valid JSON");
  // A unit removed.
  json = nlohmann::json::parse(text);
  json["units"].erase(json["units"].size() - 1);
  std::ofstream(P("incomplete/partial-2-of-3.json"), std::ios::trunc) << json.dump();
  r = RunCommand(CliPath() + " sweep-merge " + P("incomplete") + " --out " + P("m_inc"));
  ExpectExit2(r, "incomplete partial: shard 2/3 must hold 2 units, it holds 1");
  EXPECT_FALSE(fs::exists(P("m_inc/report.md")));
}

TEST_F(SweepCli, BadGridsExitWith2) {
  ExpectExit2(
      RunCommand(CliPath() + " sweep --scenario nowhere --estimators tag-pnp --out " + P("bad")),
      "unknown scenario 'nowhere'");
  ExpectExit2(RunCommand(CliPath() +
                         " sweep --scenario tag-arena-hover --estimators nobody "
                         "--out " +
                         P("bad")),
              "unknown estimator 'nobody'");
  ExpectExit2(RunCommand(CliPath() +
                         " sweep --scenario tag-arena-hover --estimators tag-pnp "
                         "--seeds 5..2 --out " +
                         P("bad")),
              "empty range");
  ExpectExit2(RunCommand(CliPath() +
                         " sweep --scenario tag-arena-hover --estimators tag-pnp "
                         "--shard 4/3 --out " +
                         P("bad")),
              "--shard '4/3'");
  // Unknown setting keys are refused before any unit runs.
  ExpectExit2(RunCommand(CliPath() +
                         " sweep --scenario tag-arena-hover --duration 1 --estimators "
                         "tag-pnp --set no_such_key=1 --out " +
                         P("bad")),
              "no_such_key");
  // A number that does not parse is refused before any unit runs, naming the setting.
  ExpectExit2(RunCommand(CliPath() +
                         " sweep --scenario tag-arena-hover --duration 1 --estimators tag-pnp "
                         "--seeds 1..2 --set corner_noise_px=abc --jobs 2 --out " +
                         P("bad")),
              "corner_noise_px");
  // A value only the scenario itself can judge fails inside a worker: the parallel runner stops
  // and reports the worker's message with exit code 2.
  const auto r = RunCommand(CliPath() +
                            " sweep --scenario marker-board-flight --duration 1 --estimators pnp "
                            "--seeds 1..2 --set image_stamping=bogus --jobs 2 --out " +
                            P("bad"));
  ExpectExit2(r, "failed (worker exit 2)");
  EXPECT_NE(r.output.find("image_stamping"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(P("bad/report.md")));
}

// --slurm with a stand-in sbatch (records its arguments, prints job ids) and squeue/sacct that
// report shard 2 FAILED: the scripts, the afterok dependency, sweep-status and --resubmit.
TEST_F(SweepCli, SlurmScriptsSubmissionStatusAndResubmit) {
  const std::string bin = P("fakebin");
  fs::create_directories(bin);
  auto tool = [&](const std::string& name, const std::string& body) {
    std::ofstream(bin + "/" + name) << "#!/bin/sh\n" << body;
    fs::permissions(bin + "/" + name, fs::perms::owner_all);
  };
  tool("sbatch", "echo \"$@\" >> " + bin +
                     "/sbatch.log\n"
                     "n=$(wc -l < " +
                     bin + "/sbatch.log)\necho $((100 + n))\n");
  tool("squeue", "exit 0\n");
  tool("sacct", "echo '101_1|COMPLETED'\necho '101_2|FAILED'\necho '101_3|COMPLETED'\n");
  tool("scancel", "echo \"$@\" >> " + bin + "/scancel.log\n");
  const std::string env = "MAVLOC_SBATCH=" + bin + "/sbatch MAVLOC_SQUEUE=" + bin +
                          "/squeue MAVLOC_SACCT=" + bin + "/sacct MAVLOC_SCANCEL=" + bin +
                          "/scancel ";
  const std::string results = P("slurm_results");
  // Dry run: scripts only.
  auto r = RunCommand(CliPath() + " sweep " + kGrid +
                      " --slurm --dry-run --shards 3 --time 00:10:00 "
                      "--mem 2G --cpus-per-task 2 --partition short --account lab "
                      "--setup 'module load mavloc' --out " +
                      results);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_FALSE(fs::exists(bin + "/sbatch.log"));
  const std::string script = Read(results + "/sweep.sbatch");
  for (const char* line :
       {"#SBATCH --array=1-3\n", "#SBATCH --time=00:10:00\n", "#SBATCH --mem=2G\n",
        "#SBATCH --cpus-per-task=2\n", "#SBATCH --partition=short\n", "#SBATCH --account=lab\n",
        "module load mavloc\n", "--shard \"${SLURM_ARRAY_TASK_ID}/3\""})
    EXPECT_NE(script.find(line), std::string::npos) << line << "\n" << script;
  EXPECT_NE(Read(results + "/merge.sbatch").find("sweep-merge"), std::string::npos);
  // Submission: the array (id 101), then the merge after it (id 102).
  r = RunCommand(env + CliPath() + " sweep " + kGrid + " --slurm --shards 3 --force --out " +
                 results);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("submitted array job 101 (3 tasks) and merge job 102 (afterok:101)"),
            std::string::npos)
      << r.output;
  const std::string log = Read(bin + "/sbatch.log");
  EXPECT_NE(log.find("--parsable " + results + "/sweep.sbatch"), std::string::npos) << log;
  EXPECT_NE(log.find("--parsable --dependency=afterok:101 " + results + "/merge.sbatch"),
            std::string::npos)
      << log;
  // Shards 1 and 3 finished (their partials exist), shard 2 failed.
  for (int i : {1, 3})
    fs::copy_file(P("partials/partial-" + std::to_string(i) + "-of-3.json"),
                  results + "/partials/partial-" + std::to_string(i) + "-of-3.json");
  r = RunCommand(env + CliPath() + " sweep-status " + results);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("shard 2/3: no complete partial (slurm job 101_2: FAILED)"),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("failed or never run: shards 2"), std::string::npos) << r.output;
  r = RunCommand(env + CliPath() + " sweep-status " + results + " --resubmit");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("resubmitted 1 shard(s) as array job 103; merge job 104 (afterok:103)"),
            std::string::npos)
      << r.output;
  EXPECT_NE(Read(bin + "/sbatch.log").find("--parsable --array=2 " + results + "/sweep.sbatch"),
            std::string::npos);
  EXPECT_EQ(Read(bin + "/scancel.log"), "102\n");  // the merge job that waited on the failure
}

}  // namespace
}  // namespace mavloc
