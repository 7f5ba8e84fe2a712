// Interrupting a command: SIGINT or SIGTERM while mavloc is generating or writing its output ends
// it with exit code 130 or 143 (128 + signal, as shells report) and leaves neither the output nor
// a staging folder "*.tmp-<pid>" nor a temporary file behind (core/interrupt.h). Every command
// that makes temporaries in $TMPDIR or beside its output is interrupted while they exist (the
// decompressed copy of a .bag.bz2, the exported images of `log import --images`, the sweep's
// worker folder, the plotting script), with TMPDIR a fresh folder that must be empty afterwards;
// a parallel sweep's workers end with it.
#include <bzlib.h>
#include <fcntl.h>
#include <gtest/gtest.h>
#include <rosbag/bag.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
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

#include "datasets/io/rosbag/ros_messages.h"
#include "frontends/image_io.h"
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

// Starts mavloc with `args` in `dir` (`environment`, "NAME=value", ahead of this process's),
// waits until `ready()` holds, sends `signal_number`, and waits for the process to end. `started`
// receives the process id.
Interrupted RunAndInterrupt(const std::vector<std::string>& args, const std::string& dir,
                            const std::function<bool()>& ready, int signal_number,
                            const std::vector<std::string>& environment = {},
                            pid_t* started = nullptr) {
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
  std::vector<std::string> env_text = environment;
  env_text.insert(env_text.end(), {"MAVLOC_QUIET=1", "MAVLOC_FIGURES=0"});
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
  if (started != nullptr) *started = pid;
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
  const std::string base = testing::MakeTempDir();
  const std::string dir = base + "/work", tmp = base + "/tmp";
  fs::create_directories(dir + "/report");
  fs::create_directories(tmp);
  std::ofstream(dir + "/report/report.json") << "{\"old\": true}\n";
  const auto started = [&] { return !StagingFolder(dir, "report").empty(); };
  // The repro runs its units in worker processes, from a folder in TMPDIR.
  const Interrupted r = RunAndInterrupt(
      {"repro", "laser", "--report", "report", "--force", "--runs", "50", "--set", "euroc=false"},
      dir, started, SIGTERM, {"TMPDIR=" + tmp});
  ASSERT_TRUE(r.signalled) << r.stderr_text;
  EXPECT_EQ(r.exit_code, 143) << r.stderr_text;
  std::ifstream json(dir + "/report/report.json");
  std::string text((std::istreambuf_iterator<char>(json)), std::istreambuf_iterator<char>());
  EXPECT_EQ(text, "{\"old\": true}\n");
  EXPECT_TRUE(TemporaryLeftovers(dir).empty()) << TemporaryLeftovers(dir).front();
  EXPECT_TRUE(fs::is_empty(tmp)) << fs::directory_iterator(tmp)->path();
}

TEST(Interrupt, SigtermDuringFiguresLeavesNoFigureThePageDoesNotList) {
  const std::string base = testing::MakeTempDir();
  const std::string work = base + "/work";
  fs::create_directories(work);
  const auto made =
      testing::RunCommand("cd " + work + " && MAVLOC_FIGURES=0 " + testing::CliPath() +
                          " repro laser --runs 2 --set euroc=false --report report");
  ASSERT_EQ(made.exit_code, 0) << made.output;
  // A stand-in interpreter that draws one figure where it is told to (--out-dir, else the report
  // folder), announces it and then takes its time.
  testing::WriteFileBytes(work + "/python",
                          "#!/bin/sh\nout=\"$2\"\nwhile [ $# -gt 0 ]; do\n"
                          "  [ \"$1\" = --out-dir ] && out=\"$2\"\n  shift\ndone\n"
                          "printf 'PNG' > \"$out/new.png\"\nprintf 'figure\\tnew.png\\tnew\\n'\n"
                          "touch " +
                              work + "/drawn\nsleep 5\n");
  fs::permissions(work + "/python", fs::perms::owner_all);
  const Interrupted r =
      RunAndInterrupt({"figures", "report"}, work, [&] { return fs::exists(work + "/drawn"); },
                      SIGTERM, {"MAVLOC_FIGURES=1", "MAVLOC_PYTHON=" + work + "/python"});
  ASSERT_TRUE(r.signalled) << r.stderr_text;
  EXPECT_EQ(r.exit_code, 143) << r.stderr_text;
  const bool listed =
      testing::ReadFileBytes(work + "/report/report.html").find("new.png") != std::string::npos;
  EXPECT_EQ(fs::exists(work + "/report/new.png"), listed)
      << "a figure that report.html does not list (or the reverse)";
  EXPECT_TRUE(TemporaryLeftovers(work).empty()) << TemporaryLeftovers(work).front();
  fs::remove_all(base);
}

// ---- Temporaries in $TMPDIR and beside the output

// The names in `dir`, for messages.
std::string Listing(const std::string& dir) {
  std::string names;
  std::error_code error;
  for (const auto& entry : fs::directory_iterator(dir, error))
    names += entry.path().filename().string() + " ";
  return names.empty() ? "(empty)" : names;
}

// Whether `dir` holds a file whose name starts with `prefix` and that has `min_bytes` or more.
bool HasFile(const std::string& dir, const std::string& prefix, uintmax_t min_bytes) {
  std::error_code error;
  for (const auto& entry : fs::directory_iterator(dir, error)) {
    if (entry.path().filename().string().rfind(prefix, 0) != 0) continue;
    if (entry.is_regular_file(error) && entry.file_size(error) >= min_bytes) return true;
  }
  return false;
}

// A .bag.bz2 whose decompression lasts long enough to be interrupted: the real bag's bzip2 stream
// followed by 64 streams of 8 MiB of zeros (bzip2 streams may be concatenated: the reader
// decompresses them one after the other into one temporary bag of half a gigabyte).
void WriteSlowBz2Bag(const std::string& real, const std::string& out) {
  std::string bytes = testing::ReadFileBytes(real);
  ASSERT_FALSE(bytes.empty()) << real;
  std::vector<char> zeros(8 << 20, 0);
  std::vector<char> compressed(zeros.size() + zeros.size() / 100 + 600);
  unsigned int length = static_cast<unsigned int>(compressed.size());
  ASSERT_EQ(BZ2_bzBuffToBuffCompress(compressed.data(), &length, zeros.data(),
                                     static_cast<unsigned int>(zeros.size()), 9, 0, 0),
            BZ_OK);
  for (int i = 0; i < 64; ++i) bytes.append(compressed.data(), length);
  testing::WriteFileBytes(out, bytes);
}

// A bag with the real EuRoC cam0 frames, each twice, as sensor_msgs/Image (mono8) on /cam0:
// exporting them as PNGs takes a few seconds.
void WriteImageBag(const std::string& out) {
  const std::string frames = testing::SharedDataDir() + "/euroc_v1_01_easy/mav0/cam0/data";
  std::vector<std::string> paths;
  for (const auto& entry : fs::directory_iterator(frames)) paths.push_back(entry.path().string());
  std::sort(paths.begin(), paths.end());
  ASSERT_GT(paths.size(), 50u);
  rosbag::Bag bag(out, rosbag::bagmode::Write);
  uint32_t sequence = 0;
  for (int repeat = 0; repeat < 2; ++repeat) {
    for (const std::string& path : paths) {
      const cv::Mat image = LoadGrayImage(path);
      ASSERT_FALSE(image.empty()) << path;
      ros1::ImageMsg message;
      message.header.seq = sequence;
      message.header.stamp = ros::Time(1000 + sequence / 20, 50'000'000u * (sequence % 20));
      message.height = static_cast<uint32_t>(image.rows);
      message.width = static_cast<uint32_t>(image.cols);
      message.encoding = "mono8";
      message.step = static_cast<uint32_t>(image.cols);
      message.data.assign(image.data, image.data + image.total());
      bag.write("/cam0", message.header.stamp, message);
      ++sequence;
    }
  }
}

// A folder beside `dir` whose name holds `marker` and that holds a file with `extension`.
bool HasFolderWith(const std::string& dir, const std::string& marker,
                   const std::string& extension) {
  std::error_code error;
  for (const auto& entry : fs::recursive_directory_iterator(dir, error)) {
    const std::string path = entry.path().string();
    if (path.find(marker) != std::string::npos && entry.path().extension() == extension)
      return true;
  }
  return false;
}

// A command that makes temporaries, interrupted while they exist.
struct TemporaryCase {
  const char* name;
  // Writes the inputs into the work folder (the command's working directory).
  std::function<void(const std::string& work)> prepare;
  std::vector<std::string> args;
  // Whether the temporaries exist, given the work folder and TMPDIR.
  std::function<bool(const std::string& work, const std::string& tmp)> ready;
  std::vector<std::string> environment;  // besides TMPDIR
};

const std::string kRealBz2Bag = "/tagslam/test_1/tag_detections.bag.bz2";

const TemporaryCase kTemporaryCases[] = {
    // The decompressed copy of a whole-file bzip2 bag, $TMPDIR/mavloc-bag-PID-N.bag.
    {"LogInfoOfABz2Bag",
     [](const std::string& work) {
       WriteSlowBz2Bag(testing::SharedDataDir() + kRealBz2Bag, work + "/slow.bag.bz2");
     },
     {"log", "info", "slow.bag.bz2"},
     [](const std::string&, const std::string& tmp) {
       return HasFile(tmp, "mavloc-bag-", 16 << 20);
     },
     {}},
    {"ImportTagslamWithABz2Bag",
     [](const std::string& work) {
       const std::string test = testing::SharedDataDir() + "/tagslam/test_1";
       fs::create_directories(work + "/test_1");
       for (const auto& entry : fs::directory_iterator(test))
         fs::copy_file(entry.path(), work + "/test_1/" + entry.path().filename().string());
       fs::remove(work + "/test_1/tag_detections.bag.bz2");
       WriteSlowBz2Bag(test + "/tag_detections.bag.bz2", work + "/test_1/tag_detections.bag.bz2");
     },
     {"import-tagslam", "test_1", "--out", "dataset"},
     [](const std::string&, const std::string& tmp) {
       return HasFile(tmp, "mavloc-bag-", 16 << 20);
     },
     {}},
    // The PNGs exported beside the output, dataset.images-PID/cam0/*.png.
    {"LogImportImages",
     [](const std::string& work) { WriteImageBag(work + "/images.bag"); },
     {"log", "import", "images.bag", "--images", "/cam0", "--calibration",
      "cam0=" + testing::SharedDataDir() + "/euroc_v1_01_easy/mav0/cam0/sensor.yaml", "--out",
      "dataset"},
     [](const std::string& work, const std::string&) {
       return HasFolderWith(work, "dataset.images-", ".png");
     },
     {}},
    // The plotting script, $TMPDIR/mavloc_report_figures_*.py, while the interpreter (a stand-in
    // that sleeps) runs it.
    {"FiguresScript",
     [](const std::string& work) {
       const auto r =
           testing::RunCommand("cd " + work + " && MAVLOC_FIGURES=0 " + testing::CliPath() +
                               " repro laser --runs 2 --set euroc=false --report report");
       ASSERT_EQ(r.exit_code, 0) << r.output;
       testing::WriteFileBytes(work + "/python", "#!/bin/sh\nsleep 3\n");
       fs::permissions(work + "/python", fs::perms::owner_all);
     },
     {"figures", "report"},
     [](const std::string&, const std::string& tmp) {
       return HasFile(tmp, "mavloc_report_figures_", 1);
     },
     {"MAVLOC_FIGURES=1", "MAVLOC_PYTHON=python"}},
};

class InterruptTemporaries : public ::testing::TestWithParam<TemporaryCase> {};

TEST_P(InterruptTemporaries, SigintLeavesAnEmptyTmpdir) {
  REQUIRE_SHARED_DATA();
  const TemporaryCase& c = GetParam();
  const std::string base = testing::MakeTempDir();
  const std::string work = base + "/work", tmp = base + "/tmp";
  fs::create_directories(work);
  fs::create_directories(tmp);
  c.prepare(work);
  if (HasFatalFailure()) return;
  std::vector<std::string> environment = {"TMPDIR=" + tmp};
  for (std::string item : c.environment) {
    if (item == "MAVLOC_PYTHON=python") item = "MAVLOC_PYTHON=" + work + "/python";
    environment.push_back(item);
  }
  const Interrupted r = RunAndInterrupt(
      c.args, work, [&] { return c.ready(work, tmp); }, SIGINT, environment);
  ASSERT_TRUE(r.signalled) << "mavloc ended before its temporaries existed: " << r.stderr_text;
  EXPECT_EQ(r.exit_code, 130) << r.stderr_text;
  EXPECT_TRUE(fs::is_empty(tmp)) << "left in TMPDIR: " << Listing(tmp);
  for (const auto& entry : fs::directory_iterator(work)) {
    const std::string name = entry.path().filename().string();
    EXPECT_EQ(name.find("dataset"), std::string::npos) << "left beside the output: " << name;
  }
  EXPECT_TRUE(TemporaryLeftovers(work).empty()) << TemporaryLeftovers(work).front();
  fs::remove_all(base);
}

INSTANTIATE_TEST_SUITE_P(Commands, InterruptTemporaries, ::testing::ValuesIn(kTemporaryCases),
                         [](const auto& row) { return std::string(row.param.name); });

// ---- Parallel sweep workers

// Process ids (other than zombies) whose command line mentions `text`.
std::vector<pid_t> ProcessesMentioning(const std::string& text) {
  std::vector<pid_t> pids;
  std::error_code error;
  for (const auto& entry : fs::directory_iterator("/proc", error)) {
    const std::string name = entry.path().filename().string();
    if (name.empty() || name.find_first_not_of("0123456789") != std::string::npos) continue;
    // A zombie's command line is empty: only running processes are found.
    const std::string cmdline = testing::ReadFileBytes(entry.path().string() + "/cmdline");
    if (cmdline.find(text) != std::string::npos) pids.push_back(std::stoi(name));
  }
  return pids;
}

// The CPU time a process has used (user and system), 0 when it cannot be read.
double CpuSeconds(pid_t pid) {
  const std::string stat = testing::ReadFileBytes("/proc/" + std::to_string(pid) + "/stat");
  const size_t end_of_name = stat.rfind(')');  // the name, in parentheses, may hold spaces
  if (end_of_name == std::string::npos) return 0.0;
  std::istringstream fields(stat.substr(end_of_name + 2));
  std::string field;
  unsigned long long ticks = 0;
  // After the name: state (3rd field), ..., utime (14th) and stime (15th).
  for (int k = 3; k <= 15 && fields >> field; ++k)
    if (k >= 14) ticks += std::stoull(field);
  return static_cast<double>(ticks) / static_cast<double>(::sysconf(_SC_CLK_TCK));
}

TEST(Interrupt, SweepWorkersEndWithTheirParent) {
  const std::string base = testing::MakeTempDir();
  const std::string work = base + "/work", tmp = base + "/tmp";
  fs::create_directories(work);
  fs::create_directories(tmp);
  // Units of many seconds each: a worker that outlived the parent would still be computing.
  const std::vector<std::string> sweep = {
      "sweep",        "--scenario", "tag-arena-hover", "--duration", "300",   "--seeds", "1..4",
      "--estimators", "smoother",   "--jobs",          "2",          "--out", "report"};
  // Ready once both workers (their command lines name the grid in TMPDIR) are computing units: a
  // worker interrupted while it starts ends anyway, as its grid file is removed.
  const auto working = [&] {
    const std::vector<pid_t> workers = ProcessesMentioning(tmp);
    return workers.size() >= 2 && std::all_of(workers.begin(), workers.end(),
                                              [](pid_t pid) { return CpuSeconds(pid) >= 0.2; });
  };
  const Interrupted r = RunAndInterrupt(sweep, work, working, SIGINT, {"TMPDIR=" + tmp});
  ASSERT_TRUE(r.signalled) << "the sweep ended before its workers ran: " << r.stderr_text;
  EXPECT_EQ(r.exit_code, 130) << r.stderr_text;
  // The kernel kills the workers as the parent ends; they are gone once reaped.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(500);
  while (!ProcessesMentioning(tmp).empty() && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  const std::vector<pid_t> left = ProcessesMentioning(tmp);
  EXPECT_TRUE(left.empty()) << left.size() << " worker(s) outlived the parent";
  for (const pid_t pid : left) ::kill(pid, SIGKILL);
  EXPECT_TRUE(fs::is_empty(tmp)) << "left in TMPDIR: " << Listing(tmp);
  EXPECT_FALSE(fs::exists(work + "/report"));
  fs::remove_all(base);
}

}  // namespace
}  // namespace mavloc
