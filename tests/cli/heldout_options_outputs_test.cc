// Bad input from the independent ("held-out") catalogue, table-driven through the real CLI:
// scenario.yaml numbers the estimators read (ReadScenarioInfo), estimator option value ranges
// (solver/estimator_registry.cc), scenario count limits (datasets/scenarios/scenario.h),
// sweep/sweep-merge/--slurm output folders (staged and kind-checked like the other commands), Slurm
// option formats, and a compare --reference without overlap. Every case must exit with 2, print one
// stderr line naming the option, file or field, and leave its working folder exactly as the set-up
// left it (nothing written, no staging folder, a foreign folder untouched).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "tests/test_support.h"

namespace mavloc {
namespace {

namespace fs = std::filesystem;

struct Case {
  std::string name;
  std::string setup;                  // shell commands run in the case's folder first (may be "")
  std::string args;                   // after `mavloc`, run in the case's folder
  std::vector<std::string> expected;  // substrings of the one-line message
};

std::string ReadFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// Every file and folder under `folder` with its contents: equal snapshots mean nothing was
// written, removed or left behind.
std::map<std::string, std::string> Snapshot(const std::string& folder) {
  std::map<std::string, std::string> files;
  for (const auto& entry : fs::recursive_directory_iterator(folder)) {
    const std::string relative = fs::relative(entry.path(), folder).string();
    files[relative] = entry.is_regular_file() ? ReadFile(entry.path().string()) : "<folder>";
  }
  return files;
}

class HeldoutOptionsOutputs : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    root_ = new std::string(testing::MakeTempDir());
    for (const auto& [scenario, name] : std::vector<std::pair<std::string, std::string>>{
             {"mav-figure-eight", "fig8"}, {"tag-arena-hover", "arena"}}) {
      const auto r = testing::RunCommand(testing::CliPath() + " simulate --scenario " + scenario +
                                         " --duration 3 --out " + *root_ + "/" + name);
      ASSERT_EQ(r.exit_code, 0) << r.output;
    }
  }
  static void TearDownTestSuite() {
    std::error_code ignored;
    fs::remove_all(*root_, ignored);
    delete root_;
  }
  static std::string* root_;
};
std::string* HeldoutOptionsOutputs::root_ = nullptr;

std::vector<Case> Cases(const std::string& root) {
  const std::string fig8 = "cp -a " + root + "/fig8 d && ";
  const std::string arena = "cp -a " + root + "/arena d && ";
  // A downloaded EuRoC-like folder (not a mavloc dataset or report): never written into.
  const std::string euroc =
      "mkdir -p d/mav0/imu0 && echo '#timestamp,w_x' > d/mav0/imu0/data.csv && "
      "echo 'sensor_type: imu' > d/mav0/imu0/sensor.yaml";
  const std::string sweep =
      "sweep --scenario tag-arena-hover --duration 3 --estimators tag-pnp --seeds 1..2 --jobs 1 ";
  const std::string slurm = sweep + "--slurm --dry-run ";
  return {
      // scenario.yaml numbers the estimators read: refused with file:line and the field.
      {"pixel_noise_negative",
       fig8 + "sed -i 's/^pixel_noise_px: .*/pixel_noise_px: -1/' d/scenario.yaml",
       "compare --dataset d --estimators smoother --report r",
       {"scenario.yaml:", "pixel_noise_px", "-1"}},
      {"pixel_noise_text",
       fig8 + "sed -i 's/^pixel_noise_px: .*/pixel_noise_px: lots/' d/scenario.yaml",
       "compare --dataset d --estimators smoother --report r",
       {"scenario.yaml:", "pixel_noise_px", "lots"}},
      {"delay_nan",
       arena + "sed -i 's/^processing_delay_s: .*/processing_delay_s: .nan/' d/scenario.yaml",
       "compare --dataset d --estimators tag-ekf --report r",
       {"scenario.yaml:", "processing_delay_s"}},
      {"delay_text",
       arena + "sed -i 's/^processing_delay_s: .*/processing_delay_s: fifty ms/' d/scenario.yaml",
       "compare --dataset d --estimators tag-ekf --report r",
       {"scenario.yaml:", "processing_delay_s", "fifty"}},
      {"delay_huge",
       arena + "sed -i 's/^processing_delay_s: .*/processing_delay_s: 1e308/' d/scenario.yaml",
       "compare --dataset d --estimators tag-ekf --report r",
       {"scenario.yaml:", "processing_delay_s", "outside"}},
      // Estimator option values: a range per numeric option.
      {"dr_rate_zero",
       "",
       "run --dataset nowhere --estimator imu-dead-reckoning --option rate_hz=0 --out o.txt",
       {"--option rate_hz=0", "imu-dead-reckoning"}},
      {"dr_rate_negative",
       "",
       "run --dataset nowhere --estimator imu-dead-reckoning --option rate_hz=-50 --out o.txt",
       {"--option rate_hz=-50"}},
      {"dr_rate_huge",
       "",
       "run --dataset nowhere --estimator imu-dead-reckoning --option rate_hz=1e308 --out o.txt",
       {"--option rate_hz=1e308"}},
      {"gekf_noise_negative",
       "",
       "run --dataset nowhere --estimator gravity-ekf --option gyro_noise_density=-1 --out o.csv",
       {"gyro_noise_density", "gravity-ekf"}},
      {"smoother_loss_scale_negative",
       "",
       "compare --scenario mav-figure-eight --duration 3 --option smoother:loss_scale=-2 "
       "--estimators smoother --report r",
       {"loss_scale", "smoother"}},
      {"smoother_pixel_sigma_negative",
       "",
       "run --dataset nowhere --estimator smoother --option pixel_sigma_px=-1 --out o.txt",
       {"pixel_sigma_px"}},
      {"smoother_grow_window_negative",
       "",
       "run --dataset nowhere --estimator smoother --option grow_window_s=-1 --out o.txt",
       {"--option grow_window_s=-1", "outside [0, 1e+06] s"}},
      {"tag_ekf_rate_zero",
       "",
       "run --dataset nowhere --estimator tag-ekf --option rate_hz=0 --out o.txt",
       {"rate_hz", "tag-ekf"}},
      // Scenario counts.
      {"landmarks_1e8",
       "",
       "simulate --scenario mav-figure-eight --out sim --duration 3 --set landmarks=100000000",
       {"landmarks", "100000000"}},
      {"supersampling_huge",
       "",
       "simulate --scenario tag-arena-hover --out sim --duration 3 --set supersampling=1000",
       {"supersampling", "1000"}},
      // Sweep outputs: kind-checked before any unit runs, never written into a foreign folder.
      {"sweep_out_foreign", euroc, sweep + "--out d", {"d", "not a mavloc report"}},
      {"merge_out_foreign",
       euroc + " && " + testing::CliPath() + " " + sweep + "--shard 1/1 --out parts",
       "sweep-merge parts --out d",
       {"d", "not a mavloc report"}},
      {"slurm_out_foreign", euroc, slurm + "--out d", {"d", "not the results folder"}},
      // A Slurm results folder (partials, the merged report) is not a report to replace.
      {"report_into_slurm_results",
       testing::CliPath() + " " + slurm + "--out d",
       "compare --scenario mav-figure-eight --duration 3 --estimators imu-dead-reckoning "
       "--report d",
       {"d", "not a mavloc report"}},
      // Slurm options go into #SBATCH lines: strict formats.
      {"slurm_time_newline", "", slurm + "--time '01:00:00\ntouch pwned' --out sl", {"--time"}},
      {"slurm_time_text", "", slurm + "--time soon --out sl", {"--time", "soon"}},
      {"slurm_mem_newline", "", slurm + "--mem '4G\necho INJECTED' --out sl", {"--mem"}},
      {"slurm_partition_shell", "", slurm + "--partition 'short;reboot' --out sl", {"--partition"}},
      {"slurm_account_space", "", slurm + "--account 'my lab' --out sl", {"--account"}},
      {"slurm_setup_newline",
       "",
       slurm + "--setup 'module load gcc\nrm -rf x' --out sl",
       {"--setup"}},
      // compare --reference FILE that does not overlap the data in time.
      {"reference_no_overlap",
       fig8 + "printf '6000 0 0 1 0 0 0 1\\n6001 0 0 1 0 0 0 1\\n6002 0 0 1 0 0 0 1\\n' > far.txt",
       "compare --dataset d --reference far.txt --estimators imu-dead-reckoning --report r",
       {"far.txt", "no overlap"}},
  };
}

TEST_F(HeldoutOptionsOutputs, EveryCaseExitsTwoWithOneLineAndLeavesTheFolderAsItWas) {
  const std::string root = *root_;
  int index = 0;
  for (const Case& c : Cases(root)) {
    SCOPED_TRACE(c.name + ": mavloc " + c.args);
    const std::string work = root + "/case" + std::to_string(index);
    const std::string err = root + "/stderr" + std::to_string(index) + ".txt";
    ++index;
    fs::create_directories(work);
    if (!c.setup.empty()) {
      const auto s = testing::RunCommand("cd " + work + " && " + c.setup);
      ASSERT_EQ(s.exit_code, 0) << s.output;
    }
    const auto before = Snapshot(work);
    // The command in a script of its own: its quotes and newlines stay as written, and its
    // stderr goes to `err` whatever RunCommand adds.
    const std::string script = root + "/command" + std::to_string(index) + ".sh";
    std::ofstream(script) << "cd " << work << " && MAVLOC_FIGURES=0 " << testing::CliPath() << " "
                          << c.args << " >/dev/null 2>" << err << "\n";
    const testing::CommandResult r = testing::RunCommand("sh " + script);
    const std::string message = ReadFile(err);
    EXPECT_EQ(r.exit_code, 2) << message;
    ASSERT_FALSE(message.empty());
    EXPECT_EQ(message.find('\n'), message.size() - 1) << "not one line: " << message;
    EXPECT_EQ(message.find("internal error"), std::string::npos) << message;
    for (const auto& expected : c.expected)
      EXPECT_NE(message.find(expected), std::string::npos)
          << "'" << expected << "' not in: " << message;
    EXPECT_TRUE(Snapshot(work) == before) << "the folder changed (written, removed or left)";
  }
}

// A sweep report replaces an older report whole: no file of the older one is left beside it.
TEST_F(HeldoutOptionsOutputs, SweepReportReplacesAnOlderReportWhole) {
  const std::string work = *root_ + "/replace";
  fs::create_directories(work + "/o");
  std::ofstream(work + "/o/eval.json") << "{}\n";
  std::ofstream(work + "/o/eval.md") << "stale\n";
  const auto r = testing::RunCommand(
      "cd " + work + " && " + testing::CliPath() +
      " sweep --scenario tag-arena-hover --duration 3 --estimators tag-pnp --seeds 1 --jobs 1 "
      "--out o --force");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(fs::exists(work + "/o/report.json"));
  EXPECT_FALSE(fs::exists(work + "/o/eval.json"));
  EXPECT_FALSE(fs::exists(work + "/o/eval.md"));
  for (const auto& entry : fs::directory_iterator(work))
    EXPECT_EQ(entry.path().filename().string().find(".tmp-"), std::string::npos);
}

}  // namespace
}  // namespace mavloc
