#include "evaluation/sweep/sweep_runner.h"

#include <fcntl.h>
#include <fmt/format.h>
#include <poll.h>
#include <sched.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <memory>
#include <stdexcept>

#include "core/atomic_file.h"
#include "core/errors.h"
#include "core/interrupt.h"
#include "core/progress.h"
#include "core/text.h"
#include "evaluation/sweep/sweep_unit.h"

namespace fs = std::filesystem;

namespace mavloc {

namespace {

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

struct Worker {
  pid_t pid = -1;
  int channel = -1;         // the parent's end of the worker's socket pair
  std::string stderr_path;  // read when the worker fails
  std::string pending;      // bytes received that do not yet form a line
  long position = -1;       // the unit (position in `indices`) it runs, -1 when idle
};

// Starts one long-lived worker: argv plus "--serve" (core of the protocol: sweep_runner.h), with a
// socket pair as its channel on fd 3 (a socket, not a pipe: send(MSG_NOSIGNAL) to a worker that
// died returns an error instead of killing this process with SIGPIPE).
Worker StartWorker(const std::vector<std::string>& argv, const std::string& stderr_path) {
  int fds[2];
  if (::socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, fds) != 0)
    throw std::runtime_error("sweep: socketpair failed");
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
  const pid_t parent = ::getpid();
  const pid_t pid = ::fork();
  if (pid < 0) {
    ::close(fds[0]);
    ::close(fds[1]);
    throw std::runtime_error("sweep: fork failed");
  }
  if (pid == 0) {
    // Child: killed when this process ends, however it ends (an interrupt ends it with _exit,
    // core/interrupt.h, without waiting for the workers). The signal follows the forking thread,
    // which waits for its workers before it returns. A parent that ended before the request took
    // effect is caught by the getppid check (the orphan was adopted by another process).
    if (::prctl(PR_SET_PDEATHSIG, SIGKILL) != 0 || ::getppid() != parent) ::_exit(127);
    // Signals unblocked (core/interrupt.h blocks them in the parent's threads; the worker's
    // own main() installs its handler again), MAVLOC_QUIET=1, stdout discarded, stderr to a file
    // the parent reads on failure, the channel on fd 3 (dup2 clears its close-on-exec flag).
    sigset_t none;
    ::sigemptyset(&none);
    ::sigprocmask(SIG_SETMASK, &none, nullptr);
    const int null_fd = ::open("/dev/null", O_WRONLY);
    const int err_fd = ::open(stderr_path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW, 0600);
    if (null_fd >= 0) ::dup2(null_fd, STDOUT_FILENO);
    if (err_fd >= 0) ::dup2(err_fd, STDERR_FILENO);
    if (::dup2(fds[1], kSweepWorkerChannelFd) < 0) ::_exit(127);
    ::execve(args[0], args.data(), envp.data());
    ::_exit(127);
  }
  ::close(fds[1]);
  Worker worker;
  worker.pid = pid;
  worker.channel = fds[0];
  worker.stderr_path = stderr_path;
  return worker;
}

bool SendLine(int fd, const std::string& line) {
  const std::string text = line + "\n";
  size_t sent = 0;
  while (sent < text.size()) {
    const ssize_t n = ::send(fd, text.data() + sent, text.size() - sent, MSG_NOSIGNAL);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    sent += static_cast<size_t>(n);
  }
  return true;
}

// A fresh folder in the system's temporary folder, removed with its contents when destroyed. It is
// registered with the interrupt cleanup (core/interrupt.h) before it is created, and created with
// CreateOutputDirectories, which waits once an interrupt is being handled: an interrupt at any
// moment leaves no folder.
class TempFolder {
 public:
  TempFolder() {
    for (int attempt = 0; attempt < 100 && path_.empty(); ++attempt) {
      const std::string candidate = (fs::temp_directory_path() / CandidateName()).string();
      auto guard = std::make_unique<TemporaryPathGuard>(candidate);
      std::error_code error;
      if (!CreateOutputDirectories(candidate, error)) {
        if (error) throw std::runtime_error("sweep: cannot create a temp folder: " + candidate);
        continue;  // the name is taken
      }
      fs::permissions(candidate, fs::perms::owner_all, error);
      path_ = candidate;
      guard_ = std::move(guard);
    }
    if (path_.empty()) throw std::runtime_error("sweep: cannot create a temp folder");
  }
  ~TempFolder() {
    std::error_code ignored;
    fs::remove_all(path_, ignored);
  }
  TempFolder(const TempFolder&) = delete;
  TempFolder& operator=(const TempFolder&) = delete;

  const std::string& path() const { return path_; }

 private:
  // "mavloc_sweep_<pid>_<number>": unique among this process's folders, unlikely among others'.
  static std::string CandidateName() {
    static std::atomic<unsigned> counter{0};
    const auto now = std::chrono::steady_clock::now().time_since_epoch().count();
    return fmt::format("mavloc_sweep_{}_{}_{:x}", static_cast<long>(::getpid()), counter++,
                       static_cast<unsigned long long>(now) & 0xffffff);
  }

  std::string path_;
  std::unique_ptr<TemporaryPathGuard> guard_;
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

  const TempFolder temp;
  const std::string grid_path = temp.path() + "/grid.json";
  WriteFileAtomically(grid_path, CanonicalGridText(grid));
  std::vector<std::string> argv;
  for (std::string item : options.worker_argv) {
    if (const auto at = item.find("{grid}"); at != std::string::npos)
      item.replace(at, 6, grid_path);
    argv.push_back(item);
  }
  argv.insert(argv.end(), {"--serve", temp.path()});

  std::vector<Worker> workers;
  auto stop_all = [&] {
    for (Worker& w : workers) {
      if (w.channel >= 0) ::close(w.channel);
      w.channel = -1;
      if (w.pid > 0) ::kill(w.pid, SIGTERM);
    }
    for (Worker& w : workers) {
      if (w.pid > 0) ::waitpid(w.pid, nullptr, 0);
      w.pid = -1;
    }
  };
  // The failure of worker w: its exit status and the last line of its stderr.
  auto fail = [&](Worker& w, const std::string& what) {
    int status = 0;
    if (w.channel >= 0) ::close(w.channel);
    w.channel = -1;
    ::waitpid(w.pid, &status, 0);
    w.pid = -1;
    const int code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    const std::string unit =
        w.position >= 0 ? std::to_string(indices[static_cast<size_t>(w.position)]) : "-";
    const std::string text = fmt::format("sweep: unit {} failed (worker exit {}{}): {}", unit, code,
                                         what, WorkerMessage(ReadWholeFile(w.stderr_path)));
    stop_all();
    if (code == 2) throw InputError(text);
    throw std::runtime_error(text);
  };
  size_t next = 0, done = 0;
  // Hands worker w the next unit, or closes its channel (the worker then exits) when none is left.
  auto assign = [&](Worker& w) {
    if (next >= indices.size()) {
      ::close(w.channel);
      w.channel = -1;
      w.position = -1;
      return;
    }
    w.position = static_cast<long>(next);
    if (!SendLine(w.channel, std::to_string(indices[next]))) fail(w, ", channel closed");
    ++next;
  };
  try {
    for (int k = 0; k < jobs; ++k) {
      workers.push_back(StartWorker(argv, fmt::format("{}/worker-{}.err", temp.path(), k)));
    }
    for (Worker& w : workers) assign(w);
    while (done < indices.size()) {
      std::vector<pollfd> polls;
      std::vector<Worker*> polled;
      for (Worker& w : workers) {
        if (w.channel < 0) continue;
        polls.push_back({w.channel, POLLIN, 0});
        polled.push_back(&w);
      }
      if (polls.empty()) throw std::logic_error("sweep: units left but no worker");
      if (::poll(polls.data(), polls.size(), -1) < 0) {
        if (errno == EINTR) continue;
        throw std::runtime_error("sweep: poll failed");
      }
      for (size_t p = 0; p < polls.size(); ++p) {
        if (polls[p].revents == 0) continue;
        Worker& w = *polled[p];
        char buffer[256];
        const ssize_t n = ::recv(w.channel, buffer, sizeof(buffer), 0);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) {
          fail(w, "");  // the worker ended with a unit outstanding; throws
          continue;
        }
        w.pending.append(buffer, static_cast<size_t>(n));
        size_t newline;
        while ((newline = w.pending.find('\n')) != std::string::npos) {
          const std::string line = w.pending.substr(0, newline);
          w.pending.erase(0, newline + 1);
          const size_t position = static_cast<size_t>(w.position);
          if (w.position < 0 || line != std::to_string(indices[position]))
            fail(w, ", unexpected reply '" + line + "'");
          results[position] = nlohmann::json::parse(
              ReadWholeFile(fmt::format("{}/unit-{}.json", temp.path(), indices[position])));
          ++done;
          progress.UnitDone();
          assign(w);
        }
      }
    }
    // Every channel is closed now: each worker sees the end of its input and exits 0.
    for (Worker& w : workers) {
      int status = 0;
      ::waitpid(w.pid, &status, 0);
      w.pid = -1;
      if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
        throw std::runtime_error("sweep: a worker did not exit cleanly after its last unit");
    }
  } catch (...) {
    stop_all();
    throw;
  }
  return results;
}

}  // namespace mavloc
