// Hostile and damaged results folders and settings, table-driven: a results folder may sit on a
// shared cluster file system and be written by others, so every value read from it is checked
// before it is used, and nothing read from it reaches a shell. Each case runs the real CLI and
// expects exit code 2, one stderr line naming the file (or option) and the field, and no side
// effect (no file created by an injected command, no report written).
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/subprocess.h"
#include "tests/report_support.h"
#include "tests/test_support.h"

namespace fs = std::filesystem;

namespace mavloc {
namespace {

using testing::CliPath;
using testing::MakeTempDir;
using testing::ReadFileBytes;
using testing::RunCliIn;
using testing::WriteFileBytes;

int CountLines(const std::string& text) {
  int lines = 0;
  for (const char c : text) lines += c == '\n';
  return lines;
}

void ExpectRefused(const testing::CliRun& run, const std::vector<std::string>& must_contain,
                   const std::string& label) {
  EXPECT_EQ(run.exit_code, 2) << label << "\nstdout: " << run.out << "\nstderr: " << run.err;
  EXPECT_EQ(CountLines(run.err), 1) << label << ": " << run.err;
  EXPECT_EQ(run.err.find("internal error"), std::string::npos) << label << ": " << run.err;
  for (const auto& text : must_contain)
    EXPECT_NE(run.err.find(text), std::string::npos)
        << label << ": '" << text << "' in " << run.err;
}

// `mavloc ARGS` in `dir` with environment assignments before it, stdout and stderr apart.
testing::CliRun RunCliWith(const std::string& dir, const std::string& env,
                           const std::string& args) {
  const testing::CommandResult r = testing::RunCommand(
      "cd " + dir + " && { " + env + " " + CliPath() + " " + args + " >stdout.txt 2>stderr.txt; }");
  testing::CliRun run{r.exit_code, ReadFileBytes(dir + "/stdout.txt"),
                      ReadFileBytes(dir + "/stderr.txt")};
  fs::remove(dir + "/stdout.txt");
  fs::remove(dir + "/stderr.txt");
  return run;
}

nlohmann::json ReadJson(const std::string& path) {
  return nlohmann::json::parse(ReadFileBytes(path));
}
void WriteJson(const std::string& path, const nlohmann::json& json) {
  fs::permissions(path, fs::perms::owner_write, fs::perm_options::add);
  WriteFileBytes(path, json.dump(2) + "\n");
}

// ---- RunProgram: an argument vector, never a shell ----

TEST(RunProgram, ArgumentsReachTheProgramVerbatim) {
  const std::string dir = MakeTempDir();
  const std::string hostile = "1;touch " + dir + "/INJECTED $(touch " + dir + "/INJECTED2) `x`";
  const ProgramRun run = RunProgram({"/bin/echo", hostile});
  ASSERT_TRUE(run.started) << run.error;
  EXPECT_EQ(run.exit_code, 0);
  EXPECT_EQ(run.out, hostile + "\n");
  EXPECT_FALSE(fs::exists(dir + "/INJECTED"));
  EXPECT_FALSE(fs::exists(dir + "/INJECTED2"));
}

TEST(RunProgram, ExitCodesStandardErrorAndMissingPrograms) {
  const ProgramRun fails = RunProgram({"/bin/sh", "-c", "echo out; echo err >&2; exit 7"});
  EXPECT_EQ(fails.exit_code, 7);
  EXPECT_EQ(fails.out, "out\n");
  EXPECT_EQ(fails.err, "err\n");
  const ProgramRun merged =
      RunProgram({"/bin/sh", "-c", "echo out; echo err >&2"}, {.merge_stderr = true});
  EXPECT_NE(merged.out.find("err"), std::string::npos);
  EXPECT_TRUE(merged.err.empty());
  const ProgramRun missing = RunProgram({"/nonexistent/program"});
  EXPECT_FALSE(missing.started);
  EXPECT_NE(missing.error.find("/nonexistent/program"), std::string::npos);
  // More output than a pipe holds, on both streams at once, does not block.
  const ProgramRun large =
      RunProgram({"/bin/sh", "-c", "head -c 300000 /dev/zero; head -c 300000 /dev/zero >&2"});
  EXPECT_EQ(large.out.size(), 300000u);
  EXPECT_EQ(large.err.size(), 300000u);
}

// ---- slurm.json of a --slurm results folder ----

class HostileSlurmFolder : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = MakeTempDir();
    bin_ = dir_ + "/bin";
    fs::create_directories(bin_);
    // Stand-ins that record that they ran: a valid slurm.json reaches them, a hostile one must not.
    for (const char* tool : {"sbatch", "squeue", "sacct", "scancel"}) {
      WriteFileBytes(bin_ + "/" + tool,
                     std::string("#!/bin/sh\necho \"$@\" >> ") + bin_ + "/calls.log\necho 101\n");
      fs::permissions(bin_ + "/" + tool, fs::perms::owner_all);
    }
    const auto run = RunCliIn(dir_,
                              "sweep --scenario tag-arena-hover --duration 1 --seeds 1..4 "
                              "--estimators tag-pnp --slurm --dry-run --shards 2 --out results");
    ASSERT_EQ(run.exit_code, 0) << run.err;
    state_ = ReadJson(dir_ + "/results/slurm.json");
    state_["submissions"] =
        nlohmann::json::array({{{"array_job", "101"}, {"merge_job", "102"}, {"tasks", {1, 2}}}});
  }
  std::string Env() const {
    return "MAVLOC_SBATCH=" + bin_ + "/sbatch MAVLOC_SQUEUE=" + bin_ +
           "/squeue MAVLOC_SACCT=" + bin_ + "/sacct MAVLOC_SCANCEL=" + bin_ + "/scancel ";
  }
  std::string dir_, bin_;
  nlohmann::json state_;
};

TEST_F(HostileSlurmFolder, ValidStateReachesTheSlurmTools) {
  WriteJson(dir_ + "/results/slurm.json", state_);
  const auto run = RunCliWith(dir_, Env(), "sweep-status results");
  EXPECT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.out.find("shard 1/2"), std::string::npos) << run.out;
  EXPECT_NE(ReadFileBytes(bin_ + "/calls.log").find("-j 101"), std::string::npos);
}

TEST_F(HostileSlurmFolder, EveryDamagedOrHostileValueIsRefusedBeforeUse) {
  struct Case {
    std::string label;
    std::function<void(nlohmann::json&)> mutate;
    std::string command;  // sweep-status arguments after the folder
    std::vector<std::string> must_contain;
  };
  const std::string injected = dir_ + "/INJECTED";
  const std::vector<Case> cases = {
      {"injection in array_job",
       [&](auto& j) { j["submissions"][0]["array_job"] = "1;touch " + injected; },
       "",
       {"slurm.json", "submissions[0].array_job", "not a Slurm job id"}},
      {"injection in merge_job, resubmit",
       [&](auto& j) { j["submissions"][0]["merge_job"] = "$(touch " + injected + ")"; },
       " --resubmit",
       {"slurm.json", "submissions[0].merge_job"}},
      {"job id a number, not text",
       [](auto& j) { j["submissions"][0]["array_job"] = 101; },
       "",
       {"submissions[0].array_job"}},
      {"two billion shards",
       [](auto& j) { j["shards"] = 2000000000; },
       "",
       {"slurm.json", "shards", "from 1 to 4"}},
      {"more shards than units", [](auto& j) { j["shards"] = 5; }, "", {"shards", "from 1 to 4"}},
      {"shards as text", [](auto& j) { j["shards"] = "2"; }, "", {"shards"}},
      {"shards negative", [](auto& j) { j["shards"] = -3; }, "", {"shards"}},
      {"submissions not a list",
       [](auto& j) { j["submissions"] = "x"; },
       "",
       {"submissions", "must be a list"}},
      {"a task out of range",
       [](auto& j) {
         j["submissions"][0]["tasks"] = {1, 99};
       },
       "",
       {"submissions[0].tasks", "from 1 to 2"}},
      {"a task as text",
       [](auto& j) { j["submissions"][0]["tasks"] = {"1;id"}; },
       "",
       {"submissions[0].tasks"}},
      {"a submission without tasks",
       [](auto& j) { j["submissions"][0].erase("tasks"); },
       "",
       {"submissions[0]"}},
      {"the whole file a list",
       [](auto& j) {
         j = nlohmann::json::array({1, 2});
       },
       "",
       {"slurm.json", "not a JSON object"}},
      {"fingerprint not text", [](auto& j) { j["fingerprint"] = 3; }, "", {"fingerprint"}},
  };
  for (const Case& c : cases) {
    nlohmann::json state = state_;
    c.mutate(state);
    WriteJson(dir_ + "/results/slurm.json", state);
    fs::remove(bin_ + "/calls.log");
    const auto run = RunCliWith(dir_, Env(), "sweep-status results" + c.command);
    ExpectRefused(run, c.must_contain, c.label);
    EXPECT_FALSE(fs::exists(injected)) << c.label;
    EXPECT_FALSE(fs::exists(bin_ + "/calls.log")) << c.label << ": a Slurm tool ran";
  }
}

// ---- sweep-merge on damaged partials ----

class DamagedPartials : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new std::string(MakeTempDir());
    for (const char* shard : {"1/2", "2/2"}) {
      const auto run =
          RunCliIn(*dir_, std::string("sweep --scenario tag-arena-hover --duration 1 "
                                      "--seeds 1..2 --estimators tag-pnp --jobs 1 --shard ") +
                              shard + " --out partials");
      ASSERT_EQ(run.exit_code, 0) << run.err;
    }
  }
  static void TearDownTestSuite() { delete dir_; }
  static std::string* dir_;
};
std::string* DamagedPartials::dir_ = nullptr;

TEST_F(DamagedPartials, IntactPartialsMerge) {
  const auto run = RunCliIn(*dir_, "sweep-merge partials --out merged");
  EXPECT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(ReadJson(*dir_ + "/merged/report.json")["report_kind"], "sweep");
}

TEST_F(DamagedPartials, EveryDamagedUnitIsRefusedNamingItsField) {
  struct Case {
    std::string label;
    std::function<void(nlohmann::json&)> mutate;
    std::vector<std::string> must_contain;
  };
  auto first_metric = [](nlohmann::json& unit) -> nlohmann::json& {
    auto& metrics = unit["estimators"][0]["metrics"];
    return metrics.begin().value();
  };
  const std::vector<Case> cases = {
      {"a metric that is text",
       [&](auto& p) { first_metric(p["units"][0]) = "0.1"; },
       {"partial-1-of-2.json", "units[0].estimators[0].metrics."}},
      {"an ATE of -1e308",
       [&](auto& p) { first_metric(p["units"][0]) = -1e308; },
       {"units[0].estimators[0].metrics.", "finite number from 0"}},
      {"a metric of 1e300",
       [&](auto& p) { first_metric(p["units"][0]) = 1e300; },
       {"units[0].estimators[0].metrics."}},
      {"a unit without estimators",
       [](auto& p) { p["units"][0].erase("estimators"); },
       {"units[0].estimators", "not a list"}},
      {"an estimator without ran",
       [](auto& p) { p["units"][0]["estimators"][0].erase("ran"); },
       {"units[0].estimators[0]"}},
      {"a unit that is a number", [](auto& p) { p["units"][0] = 3; }, {"units"}},
      {"a seed that is text", [](auto& p) { p["units"][0]["seed"] = "1"; }, {"units[0].seed"}},
      {"two billion shards",
       [](auto& p) { p["shards"] = 2000000000; },
       {"partial-1-of-2.json", "shard"}},
      {"shards as a fraction", [](auto& p) { p["shards"] = 2.5; }, {"shards"}},
      // Units that are not the grid's: merged before into cells the grid does not have.
      {"an estimator that is not in the grid",
       [](auto& p) { p["units"][0]["estimators"][0]["name"] = "smoother"; },
       {"partial-1-of-2.json", "units[0].estimators[0].name", "unit 0",
        "estimator 'smoother' is not in the grid (estimators: tag-pnp)"}},
      {"an estimator of the grid twice",
       [](auto& p) { p["units"][0]["estimators"].push_back(p["units"][0]["estimators"][0]); },
       {"units[0].estimators", "unit 0 has the estimators tag-pnp, tag-pnp"}},
      {"an estimator of the grid missing",
       [](auto& p) { p["units"][0]["estimators"] = nlohmann::json::array(); },
       {"units[0].estimators", "the grid runs tag-pnp"}},
      {"the seed of another unit",
       [](auto& p) { p["units"][0]["seed"] = 7; },
       {"partial-1-of-2.json", "units[0]", "seed 7", "not a unit of this grid"}},
      {"another scenario",
       [](auto& p) { p["units"][0]["scenario"] = "tag-arena-dynamic"; },
       {"units[0]", "scenario tag-arena-dynamic", "not a unit of this grid"}},
  };
  for (const Case& c : cases) {
    const std::string work = MakeTempDir();
    fs::copy(*dir_ + "/partials", work + "/partials");
    const std::string path = work + "/partials/partial-1-of-2.json";
    nlohmann::json partial = ReadJson(path);
    c.mutate(partial);
    WriteJson(path, partial);
    const auto run = RunCliIn(work, "sweep-merge partials --out merged");
    ExpectRefused(run, c.must_contain, c.label);
    EXPECT_FALSE(fs::exists(work + "/merged")) << c.label;
  }
}

// A unit without a metric the others have is merged, and the report and the terminal name the
// short cell (its statistics are over fewer seeds than the cell ran).
TEST_F(DamagedPartials, AUnitWithoutAMetricIsMergedNamingTheShortCell) {
  const std::string work = MakeTempDir();
  fs::copy(*dir_ + "/partials", work + "/partials");
  const std::string path = work + "/partials/partial-1-of-2.json";
  nlohmann::json partial = ReadJson(path);
  partial["units"][0]["estimators"][0]["metrics"].erase("ate_rmse");
  WriteJson(path, partial);
  const auto run = RunCliIn(work, "sweep-merge partials --out merged");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const std::string warning =
      "tag-arena-hover: tag-pnp: ate_rmse has 1 value(s) for the 2 runs where it ran (missing in "
      "unit 0)";
  EXPECT_NE(run.err.find("warning: " + warning), std::string::npos) << run.err;
  EXPECT_NE(ReadFileBytes(work + "/merged/report.md").find(warning), std::string::npos);
  const nlohmann::json report = ReadJson(work + "/merged/report.json");
  EXPECT_NE(report["warnings"].dump().find("ate_rmse has 1 value(s)"), std::string::npos)
      << report["warnings"].dump();
}

// The partial folder is walked with the one folder walk: a named pipe named like a partial is
// refused naming it (it blocked the read before), any other file is named as not used.
TEST_F(DamagedPartials, TheFolderWalkRefusesAPipeAndNamesWhatItSkips) {
  const std::string work = MakeTempDir();
  fs::copy(*dir_ + "/partials", work + "/partials");
  WriteFileBytes(work + "/partials/notes.txt", "mine\n");
  auto run = RunCliIn(work, "sweep-merge partials --out merged");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.err.find("partials/notes.txt: not used: not a partial file"), std::string::npos)
      << run.err;
  fs::remove(work + "/partials/partial-2-of-2.json");
  ASSERT_EQ(::mkfifo((work + "/partials/partial-2-of-2.json").c_str(), 0644), 0);
  // A timeout: the merge blocked in open() on the pipe before.
  const testing::CommandResult piped = testing::RunCommand(
      "cd " + work + " && timeout 60 " + CliPath() + " sweep-merge partials --out merged2");
  EXPECT_EQ(piped.exit_code, 2) << piped.output;
  EXPECT_NE(piped.output.find("partial-2-of-2.json: is a named pipe"), std::string::npos)
      << piped.output;
  EXPECT_FALSE(fs::exists(work + "/merged2"));
}

// ---- figures: a report folder is one whose report.json says so ----

TEST(FiguresFolders, FoldersWithoutADeclaredReportAreRefused) {
  const std::string dir = MakeTempDir();
  fs::create_directories(dir + "/notes");
  WriteFileBytes(dir + "/notes/errors.csv", "my own file\n");
  auto run = RunCliIn(dir, "figures notes");
  ExpectRefused(run, {"notes", "no mavloc report"}, "errors.csv only");
  EXPECT_FALSE(fs::exists(dir + "/notes/report.html"));
  WriteFileBytes(dir + "/notes/report.json", "{\"report_kind\": 3}");
  run = RunCliIn(dir, "figures notes");
  ExpectRefused(run, {"no mavloc report"}, "report_kind not text");
  EXPECT_FALSE(fs::exists(dir + "/notes/report.html"));
}

TEST(FiguresFolders, AFailingPlotScriptIsOneLine) {
  const std::string dir = MakeTempDir();
  fs::create_directories(dir + "/r");
  WriteFileBytes(dir + "/r/report.json", "{\"report_kind\": \"compare\"}");
  WriteFileBytes(dir + "/r/errors.csv", "estimator,quantity\n\x01\x02,\"unterminated\n");
  // A stand-in interpreter that fails as a Python traceback does.
  const std::string python = dir + "/python3";
  WriteFileBytes(python,
                 "#!/bin/sh\necho 'Traceback (most recent call last):' >&2\n"
                 "echo '  File \"x.py\", line 1' >&2\necho 'KeyError: quantity' >&2\nexit 1\n");
  fs::permissions(python, fs::perms::owner_all);
  const auto run = RunCliWith(dir, "MAVLOC_FIGURES=1 MAVLOC_PYTHON=" + python, "figures r");
  EXPECT_EQ(run.exit_code, 1) << run.out << run.err;
  EXPECT_EQ(run.out.find("Traceback"), std::string::npos) << run.out;
  EXPECT_EQ(run.out.find("File \"x.py\""), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("the plotting script failed (exit code 1): KeyError: quantity"),
            std::string::npos)
      << run.out;
  EXPECT_TRUE(run.err.empty()) << run.err;
}

// ---- scenario settings the readers would refuse ----

TEST(ScenarioSettingRanges, ValuesNoReaderAcceptsAreRefusedBeforeAnythingRuns) {
  const std::string dir = MakeTempDir();
  struct Case {
    std::string args;
    std::vector<std::string> must_contain;
    std::string output;  // must not exist afterwards
  };
  const std::vector<Case> cases = {
      {"simulate --scenario mav-figure-eight --set pixel_noise_px=1e308 --out sim",
       {"--set pixel_noise_px=1e308", "px"},
       "sim"},
      {"compare --scenario mav-figure-eight --set pixel_noise_px=1e308 --report rep",
       {"--set pixel_noise_px=1e308"},
       "rep"},
      {"sweep --scenario mav-figure-eight --set pixel_noise_px=1,1e308 --estimators smoother "
       "--out swp",
       {"pixel_noise_px=1e308"},
       "swp"},
      {"simulate --scenario mav-figure-eight --set imu_rate_hz=1e-3 --out sim",
       {"--set imu_rate_hz=1e-3", "Hz"},
       "sim"},
      {"simulate --scenario tag-arena-hover --set corner_noise_px=-1 --out sim",
       {"--set corner_noise_px=-1"},
       "sim"},
      {"simulate --scenario tag-arena-hover --set camera_offset_s=1e9 --out sim",
       {"--set camera_offset_s=1e9"},
       "sim"},
  };
  for (const Case& c : cases) {
    const auto run = RunCliIn(dir, c.args);
    ExpectRefused(run, c.must_contain, c.args);
    EXPECT_FALSE(fs::exists(dir + "/" + c.output)) << c.args;
  }
}

// ---- IMU gaps ----

// A simulated 20 s figure-eight whose IMU stream loses the samples between 6 s and 11 s.
std::string DatasetWithImuGap(const std::string& dir) {
  const auto run =
      RunCliIn(dir, "simulate --scenario mav-figure-eight --duration 20 --seed 3 --out ds");
  EXPECT_EQ(run.exit_code, 0) << run.err;
  const std::string path = dir + "/ds/mav0/imu0/data.csv";
  const std::string text = ReadFileBytes(path);
  std::string kept;
  long long t0_ns = -1;
  size_t begin = 0;
  while (begin < text.size()) {
    const size_t end = text.find('\n', begin);
    const std::string line = text.substr(begin, end - begin + 1);
    begin = end == std::string::npos ? text.size() : end + 1;
    if (line[0] == '#') {
      kept += line;
      continue;
    }
    const long long t_ns = std::stoll(line.substr(0, line.find(',')));
    if (t0_ns < 0) t0_ns = t_ns;
    const double t_s = static_cast<double>(t_ns - t0_ns) * 1e-9;
    if (t_s < 6.0 || t_s > 11.0) kept += line;
  }
  WriteFileBytes(path, kept);
  return dir + "/ds";
}

TEST(ImuGaps, RefusedByDefaultNamingTheGapAndTheOption) {
  const std::string dir = MakeTempDir();
  DatasetWithImuGap(dir);
  const auto run = RunCliIn(dir, "compare --dataset ds --estimators imu-dead-reckoning --report r");
  ExpectRefused(run, {"ds", "imu0: 1 gap", "longest 5.01", "from t = 5.99", "imu_gaps=reset"},
                "gap, default policy");
  EXPECT_FALSE(fs::exists(dir + "/r"));
}

TEST(ImuGaps, ResetRestartsAfterTheGapAndTheReportSaysSo) {
  const std::string dir = MakeTempDir();
  DatasetWithImuGap(dir);
  const auto run = RunCliIn(dir,
                            "compare --dataset ds --estimators imu-dead-reckoning,gravity-ekf "
                            "--option imu_gaps=reset --report r");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const nlohmann::json report = ReadJson(dir + "/r/report.json");
  for (const char* name : {"imu-dead-reckoning", "gravity-ekf"}) {
    const nlohmann::json e = testing::ReportEstimator(report, name);
    ASSERT_TRUE(e.is_object()) << report.dump();
    EXPECT_EQ(e["parameters"]["imu_gap_restarts"]["value"], 1.0) << e.dump();
  }
  // Restarted from the truth after the gap, dead reckoning over 6 + 9 s stays within metres;
  // across the 5 s gap it would have integrated nothing for 5 s.
  const nlohmann::json dead_reckoning = testing::ReportEstimator(report, "imu-dead-reckoning");
  const auto& ate = dead_reckoning["metrics"]["ate_translation"]["statistics"];
  ASSERT_TRUE(ate.is_object()) << dead_reckoning.dump();
  EXPECT_LT(ate["rmse"].get<double>(), 5.0) << ate.dump();
}

// Every frame is posed or counted: the smoother restarted after the gap poses the frames of both
// segments, and the frames inside the 5 s gap are counted as frames without pose.
TEST(ImuGaps, EveryFrameIsPosedOrCounted) {
  const std::string dir = MakeTempDir();
  DatasetWithImuGap(dir);
  const auto run = RunCliIn(
      dir, "compare --dataset ds --estimators smoother --option imu_gaps=reset --report r");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const std::string frames_csv = ReadFileBytes(dir + "/ds/mav0/cam0/data.csv");
  const int frames = static_cast<int>(std::count(frames_csv.begin(), frames_csv.end(), '\n')) - 1;
  const nlohmann::json e = testing::ReportEstimator(ReadJson(dir + "/r/report.json"), "smoother");
  ASSERT_TRUE(e.is_object());
  const int posed = e["coverage"]["estimate_poses"].get<int>();
  const int counted = e["frames_without_pose"].get<int>();
  EXPECT_EQ(posed + counted, frames) << e.dump();
  EXPECT_GE(counted, 95);  // 5 s at 20 Hz inside the gap
}

TEST(ImuGaps, AnUnknownPolicyIsRefused) {
  const std::string dir = MakeTempDir();
  const auto run = RunCliIn(dir,
                            "compare --scenario mav-figure-eight --duration 2 --estimators "
                            "imu-dead-reckoning --option imu_gaps=bridge --report r");
  ExpectRefused(run, {"imu_gaps=bridge", "refuse or reset"}, "unknown policy");
}

// ---- output folders: nothing is replaced without --force ----

TEST(OutputFolders, NoCommandReplacesAFolderWithoutForce) {
  const std::string dir = MakeTempDir();
  const std::string compare =
      "compare --scenario mav-figure-eight --duration 2 --estimators "
      "imu-dead-reckoning";
  ASSERT_EQ(RunCliIn(dir, compare).exit_code, 0);  // ./mavloc_report, the default
  const std::string first = ReadFileBytes(dir + "/mavloc_report/report.json");
  ASSERT_FALSE(first.empty());
  // A second compare into the default folder is refused, naming what is there and --force.
  ExpectRefused(RunCliIn(dir, compare), {"mavloc_report", "`mavloc compare` report", "--force"},
                "second compare");
  EXPECT_EQ(ReadFileBytes(dir + "/mavloc_report/report.json"), first);
  // eval --out into that report folder is refused as well.
  ExpectRefused(RunCliIn(dir,
                         "eval --gt mavloc_report/truth.tum --est "
                         "mavloc_report/estimate_imu-dead-reckoning.tum --out mavloc_report"),
                {"mavloc_report", "--force"}, "eval into a compare report");
  // With --force the report is replaced.
  const auto forced = RunCliIn(dir, compare + " --force");
  EXPECT_EQ(forced.exit_code, 0) << forced.err;
  // A folder of someone else's files is never replaced, --force or not.
  fs::create_directories(dir + "/mine");
  WriteFileBytes(dir + "/mine/notes.txt", "mine\n");
  ExpectRefused(RunCliIn(dir, compare + " --force --report mine"), {"mine", "not a mavloc report"},
                "forced into a foreign folder");
  EXPECT_EQ(ReadFileBytes(dir + "/mine/notes.txt"), "mine\n");
  // simulate and sweep-merge follow the same rule.
  ASSERT_EQ(RunCliIn(dir, "simulate --scenario mav-figure-eight --duration 2 --out ds").exit_code,
            0);
  ExpectRefused(RunCliIn(dir, "simulate --scenario mav-figure-eight --duration 2 --out ds"),
                {"ds", "a mavloc dataset", "--force"}, "second simulate");
  EXPECT_EQ(
      RunCliIn(dir, "simulate --scenario mav-figure-eight --duration 2 --out ds --force").exit_code,
      0);
}

}  // namespace
}  // namespace mavloc
