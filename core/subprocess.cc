#include "core/subprocess.h"

#include <fcntl.h>
#include <poll.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstdio>
#include <cstring>

extern char** environ;

namespace mavloc {
namespace {

struct Pipe {
  int read_end = -1, write_end = -1;
  bool Open() {
    int fds[2];
    if (::pipe2(fds, O_CLOEXEC) != 0) return false;
    read_end = fds[0];
    write_end = fds[1];
    return true;
  }
  void CloseWrite() {
    if (write_end >= 0) ::close(write_end);
    write_end = -1;
  }
  void CloseRead() {
    if (read_end >= 0) ::close(read_end);
    read_end = -1;
  }
  ~Pipe() {
    CloseWrite();
    CloseRead();
  }
};

// Reads both pipes until both reach end of file (poll, so that neither pipe fills up and blocks
// the child while the other is read).
void ReadUntilClosed(Pipe& out, Pipe& err, ProgramRun* run) {
  std::array<char, 4096> buffer;
  while (out.read_end >= 0 || err.read_end >= 0) {
    std::array<pollfd, 2> fds{{{out.read_end, POLLIN, 0}, {err.read_end, POLLIN, 0}}};
    if (::poll(fds.data(), fds.size(), -1) < 0) {
      if (errno == EINTR) continue;
      break;
    }
    for (int k = 0; k < 2; ++k) {
      Pipe& pipe = k == 0 ? out : err;
      if (pipe.read_end < 0 || fds[static_cast<size_t>(k)].revents == 0) continue;
      const ssize_t n = ::read(pipe.read_end, buffer.data(), buffer.size());
      if (n > 0) {
        (k == 0 ? run->out : run->err).append(buffer.data(), static_cast<size_t>(n));
      } else if (n == 0 || errno != EINTR) {
        pipe.CloseRead();
      }
    }
  }
}

}  // namespace

ProgramRun RunProgram(const std::vector<std::string>& argv, const ProgramOptions& options) {
  ProgramRun run;
  if (argv.empty() || argv[0].empty()) {
    run.error = "no program to run";
    return run;
  }
  std::vector<char*> args;
  for (const auto& arg : argv) args.push_back(const_cast<char*>(arg.c_str()));
  args.push_back(nullptr);
  Pipe out, err;
  if (!out.Open() || !err.Open()) {
    run.error = std::string("cannot create a pipe: ") + std::strerror(errno);
    return run;
  }
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_adddup2(&actions, out.write_end, 1);
  posix_spawn_file_actions_adddup2(&actions, options.merge_stderr ? out.write_end : err.write_end,
                                   2);
  std::fflush(nullptr);
  pid_t pid = -1;
  const int spawn_error = ::posix_spawnp(&pid, args[0], &actions, nullptr, args.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  out.CloseWrite();
  err.CloseWrite();
  if (spawn_error != 0) {
    run.error = "cannot start " + argv[0] + ": " + std::strerror(spawn_error);
    return run;
  }
  run.started = true;
  ReadUntilClosed(out, err, &run);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  run.exit_code = WIFEXITED(status)     ? WEXITSTATUS(status)
                  : WIFSIGNALED(status) ? 128 + WTERMSIG(status)
                                        : -1;
  return run;
}

}  // namespace mavloc
