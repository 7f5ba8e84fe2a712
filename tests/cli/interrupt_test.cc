// Interrupting a command (issue 17): SIGINT or SIGTERM while mavloc is generating or writing its
// output ends it with exit code 130 or 143 (128 + signal, as shells report) and leaves neither the
// output nor a staging folder "*.tmp-<pid>" nor a temporary file behind (core/interrupt.h).
#include <fcntl.h>
#include <gtest/gtest.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "tests/test_support.h"

extern char** environ;

namespace mavloc {
namespace {

namespace fs = std::filesystem;

struct Interrupted {
  bool signalled = false;  // the condition was met while the process ran, and the signal sent
  int exit_code = -1;      // -1 when the process did not exit normally
  std::string stderr_text;
};

// Starts mavloc with `args` in `dir`, waits until `ready()` holds, sends `signal_number`, and
// waits for the process to end.
Interrupted RunAndInterrupt(const std::vector<std::string>& args, const std::string& dir,
                            const std::function<bool()>& ready, int signal_number) {
  Interrupted result;
  const std::string err = dir + "/../stderr-" + std::to_string(signal_number) + ".txt";
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 2, err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  std::vector<std::string> argv_text = {testing::CliPath()};
  argv_text.insert(argv_text.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& a : argv_text) argv.push_back(a.data());
  argv.push_back(nullptr);
  std::vector<std::string> env_text = {"MAVLOC_QUIET=1", "MAVLOC_FIGURES=0"};
  for (char** e = environ; *e; ++e) env_text.push_back(*e);
  std::vector<char*> env;
  for (auto& e : env_text) env.push_back(e.data());
  env.push_back(nullptr);
  const fs::path cwd = fs::current_path();
  fs::current_path(dir);
  pid_t pid = 0;
  const int spawned = posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), env.data());
  fs::current_path(cwd);
  posix_spawn_file_actions_destroy(&actions);
  if (spawned != 0) return result;
  int status = 0;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
  bool exited = false;
  while (std::chrono::steady_clock::now() < deadline) {
    if (ready()) {
      result.signalled = ::kill(pid, signal_number) == 0;
      break;
    }
    if (::waitpid(pid, &status, WNOHANG) == pid) {
      exited = true;
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  if (!exited) {
    if (!result.signalled) ::kill(pid, SIGKILL);
    ::waitpid(pid, &status, 0);
  }
  if (WIFEXITED(status)) result.exit_code = WEXITSTATUS(status);
  std::ifstream in(err);
  std::stringstream text;
  text << in.rdbuf();
  result.stderr_text = text.str();
  return result;
}

// Paths in `dir` (recursively) whose names mark temporary output.
std::vector<std::string> TemporaryLeftovers(const std::string& dir) {
  std::vector<std::string> left;
  for (const auto& entry : fs::recursive_directory_iterator(dir)) {
    const std::string name = entry.path().filename().string();
    if (name.find(".tmp-") != std::string::npos || name.find(".old-") != std::string::npos)
      left.push_back(entry.path().string());
  }
  return left;
}

// The staging folder of `target` (any pid), or "" while there is none.
std::string StagingFolder(const std::string& dir, const std::string& target) {
  std::error_code error;
  for (const auto& entry : fs::directory_iterator(dir, error)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind(target + ".tmp-", 0) == 0) return entry.path().string();
  }
  return "";
}

// A simulation long enough to be caught while it writes: ten minutes of the default scenario
// (~1e6 feature rows: about a second of writing).
const std::vector<std::string> kLongSimulation = {
    "simulate", "--scenario", "mav-figure-eight", "--duration", "600", "--out", "dataset"};

TEST(Interrupt, SigintWhileWritingADatasetLeavesNothing) {
  const std::string dir = testing::MakeTempDir() + "/work";
  fs::create_directories(dir);
  // Ready once WriteEurocDataset has written a first file into the staging folder.
  const auto writing = [&] {
    const std::string staging = StagingFolder(dir, "dataset");
    std::error_code error;
    return !staging.empty() && fs::exists(staging + "/mav0", error);
  };
  const Interrupted r = RunAndInterrupt(kLongSimulation, dir, writing, SIGINT);
  ASSERT_TRUE(r.signalled) << "mavloc ended before it wrote anything: " << r.stderr_text;
  EXPECT_EQ(r.exit_code, 130) << r.stderr_text;
  EXPECT_NE(r.stderr_text.find("interrupted by SIGINT"), std::string::npos) << r.stderr_text;
  EXPECT_FALSE(fs::exists(dir + "/dataset"));
  EXPECT_TRUE(TemporaryLeftovers(dir).empty()) << TemporaryLeftovers(dir).front();
}

TEST(Interrupt, SigtermWhileGeneratingLeavesNothing) {
  const std::string dir = testing::MakeTempDir() + "/work";
  fs::create_directories(dir);
  const auto started = [&] { return !StagingFolder(dir, "dataset").empty(); };
  const Interrupted r = RunAndInterrupt(kLongSimulation, dir, started, SIGTERM);
  ASSERT_TRUE(r.signalled) << r.stderr_text;
  EXPECT_EQ(r.exit_code, 143) << r.stderr_text;
  EXPECT_FALSE(fs::exists(dir + "/dataset"));
  EXPECT_TRUE(TemporaryLeftovers(dir).empty()) << TemporaryLeftovers(dir).front();
}

TEST(Interrupt, SigtermDuringAReproKeepsTheOldReport) {
  const std::string dir = testing::MakeTempDir() + "/work";
  fs::create_directories(dir + "/report");
  std::ofstream(dir + "/report/report.json") << "{\"old\": true}\n";
  const auto started = [&] { return !StagingFolder(dir, "report").empty(); };
  const Interrupted r = RunAndInterrupt(
      {"repro", "laser", "--report", "report", "--runs", "50", "--set", "euroc=false"}, dir,
      started, SIGTERM);
  ASSERT_TRUE(r.signalled) << r.stderr_text;
  EXPECT_EQ(r.exit_code, 143) << r.stderr_text;
  std::ifstream json(dir + "/report/report.json");
  std::string text((std::istreambuf_iterator<char>(json)), std::istreambuf_iterator<char>());
  EXPECT_EQ(text, "{\"old\": true}\n");
  EXPECT_TRUE(TemporaryLeftovers(dir).empty()) << TemporaryLeftovers(dir).front();
}

}  // namespace
}  // namespace mavloc
