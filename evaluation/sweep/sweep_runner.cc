#include "evaluation/sweep/sweep_runner.h"

#include <fcntl.h>
#include <fmt/format.h>
#include <sched.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <stdexcept>

#include "core/atomic_file.h"
#include "core/errors.h"
#include "core/interrupt.h"
#include "core/progress.h"
#include "evaluation/sweep/sweep_unit.h"

namespace fs = std::filesystem;

namespace mavloc {

namespace {

std::string ReadFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

class ProgressLine {
 public:
  explicit ProgressLine(size_t total, int jobs)
      : total_(total), jobs_(jobs), start_(std::chrono::steady_clock::now()) {}
  void UnitDone() {
    ++done_;
    const double elapsed_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    const double left_s =
        elapsed_s / static_cast<double>(done_) * static_cast<double>(total_ - done_);
    const long left = std::lround(left_s);
    ReportProgress("sweep", fmt::format("{}/{} runs done, {}:{:02d} left ({} job{})", done_, total_,
                                        left / 60, left % 60, jobs_, jobs_ == 1 ? "" : "s"));
  }

 private:
  size_t total_, done_ = 0;
  int jobs_;
  std::chrono::steady_clock::time_point start_;
};

// The worker's last "mavloc: error: ..." line (or its whole stderr tail) for the message.
std::string WorkerMessage(const std::string& stderr_text) {
  std::string text = stderr_text;
  while (!text.empty() && text.back() == '\n') text.pop_back();
  const auto newline = text.rfind('\n');
  std::string last = newline == std::string::npos ? text : text.substr(newline + 1);
  for (const char* prefix : {"mavloc: error: ", "mavloc: internal error: ", "mavloc: "})
    if (last.rfind(prefix, 0) == 0) return last.substr(std::string(prefix).size());
  return last;
}

pid_t StartWorker(const std::vector<std::string>& argv, const std::string& stderr_path) {
  std::vector<char*> args;
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  // The environment is prepared before fork: only async-signal-safe calls run in the child.
  std::vector<std::string> environment = {"MAVLOC_QUIET=1"};
  for (char** e = environ; *e; ++e)
    if (std::string(*e).rfind("MAVLOC_QUIET=", 0) != 0) environment.push_back(*e);
  std::vector<char*> envp;
  for (auto& e : environment) envp.push_back(e.data());
  envp.push_back(nullptr);
  const pid_t pid = ::fork();
  if (pid < 0) throw std::runtime_error("sweep: fork failed");
  if (pid == 0) {
    // Child: signals unblocked (core/interrupt.h blocks them in the parent's threads; the worker's
    // own main() installs its handler again), MAVLOC_QUIET=1, stdout discarded, stderr to a file
    // the parent reads on failure.
    sigset_t none;
    ::sigemptyset(&none);
    ::sigprocmask(SIG_SETMASK, &none, nullptr);
    const int null_fd = ::open("/dev/null", O_WRONLY);
    const int err_fd = ::open(stderr_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (null_fd >= 0) ::dup2(null_fd, STDOUT_FILENO);
    if (err_fd >= 0) ::dup2(err_fd, STDERR_FILENO);
    ::execve(args[0], args.data(), envp.data());
    ::_exit(127);
  }
  return pid;
}

struct TempFolder {
  std::string path;
  TempFolder() {
    std::string pattern = (fs::temp_directory_path() / "mavloc_sweep_XXXXXX").string();
    if (!::mkdtemp(pattern.data())) throw std::runtime_error("sweep: cannot create a temp folder");
    path = pattern;
  }
  ~TempFolder() {
    std::error_code ignored;
    fs::remove_all(path, ignored);
  }
};

}  // namespace

int AvailableCores() {
  cpu_set_t set;
  if (::sched_getaffinity(0, sizeof(set), &set) == 0) return std::max(1, CPU_COUNT(&set));
  const long online = ::sysconf(_SC_NPROCESSORS_ONLN);
  return online > 0 ? static_cast<int>(online) : 1;
}

std::vector<nlohmann::json> RunSweepUnits(const SweepGrid& grid, const std::vector<size_t>& indices,
                                          const SweepRunOptions& options) {
  std::vector<nlohmann::json> results(indices.size());
  const int jobs = std::max(1, std::min<int>(options.jobs, static_cast<int>(indices.size())));
  ProgressLine progress(indices.size(), jobs);
  if (jobs <= 1 || indices.size() <= 1) {
    for (size_t i = 0; i < indices.size(); ++i) {
      // Through JSON text, as a worker's result is, so that both paths give the same numbers.
      results[i] = nlohmann::json::parse(RunSweepUnit(grid, indices[i]).dump());
      progress.UnitDone();
    }
    return results;
  }
  if (options.worker_argv.empty()) throw std::logic_error("sweep: no worker command for --jobs");

  TempFolder temp;
  const TemporaryPathGuard remove_on_interrupt(temp.path);  // core/interrupt.h
  const std::string grid_path = temp.path + "/grid.json";
  WriteFileAtomically(grid_path, CanonicalGridText(grid));
  std::vector<std::string> base;
  for (std::string item : options.worker_argv) {
    if (const auto at = item.find("{grid}"); at != std::string::npos)
      item.replace(at, 6, grid_path);
    base.push_back(item);
  }
  std::map<pid_t, size_t> running;  // pid -> position in indices
  size_t next = 0;
  auto kill_all = [&] {
    for (const auto& [pid, position] : running) ::kill(pid, SIGTERM);
    for (const auto& [pid, position] : running) ::waitpid(pid, nullptr, 0);
    running.clear();
  };
  try {
    while (next < indices.size() || !running.empty()) {
      while (next < indices.size() && static_cast<int>(running.size()) < jobs) {
        std::vector<std::string> argv = base;
        const std::string stem = fmt::format("{}/unit-{}", temp.path, indices[next]);
        argv.insert(argv.end(), {"--unit", std::to_string(indices[next]), "--out", stem + ".json"});
        running[StartWorker(argv, stem + ".err")] = next;
        ++next;
      }
      int status = 0;
      const pid_t pid = ::waitpid(-1, &status, 0);
      if (pid < 0) {
        if (errno == EINTR) continue;
        throw std::runtime_error("sweep: waitpid failed");
      }
      const auto it = running.find(pid);
      if (it == running.end()) continue;  // not one of ours
      const size_t position = it->second;
      running.erase(it);
      const std::string stem = fmt::format("{}/unit-{}", temp.path, indices[position]);
      const bool ok = WIFEXITED(status) && WEXITSTATUS(status) == 0;
      if (!ok) {
        const std::string message = WorkerMessage(ReadFile(stem + ".err"));
        const int code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
        kill_all();
        const std::string text = fmt::format("sweep: unit {} failed (worker exit {}): {}",
                                             indices[position], code, message);
        if (code == 2) throw InputError(text);
        throw std::runtime_error(text);
      }
      results[position] = nlohmann::json::parse(ReadFile(stem + ".json"));
      progress.UnitDone();
    }
  } catch (...) {
    kill_all();
    throw;
  }
  return results;
}

}  // namespace mavloc
