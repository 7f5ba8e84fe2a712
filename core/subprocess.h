// Runs another program with an argument vector (posix_spawnp): no shell ever sees the arguments,
// so a value read from a file (a job id, a path) is one argument whatever characters it holds.
#pragma once

#include <string>
#include <vector>

namespace mavloc {

struct ProgramRun {
  bool started = false;  // false: the program could not be started (see `error`)
  int exit_code = -1;    // exit status, or 128 + signal when the program was killed
  std::string out;       // standard output (with standard error when merge_stderr)
  std::string err;       // standard error (empty when merge_stderr)
  std::string error;     // why the program could not be started
};

struct ProgramOptions {
  bool merge_stderr = false;  // standard error into `out`, as a shell's 2>&1
};

// Runs argv[0] (looked up on PATH when it holds no '/') with argv, standard input from /dev/null,
// and waits for it. Standard output and error are read in full.
ProgramRun RunProgram(const std::vector<std::string>& argv, const ProgramOptions& options = {});

}  // namespace mavloc
