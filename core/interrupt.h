// Interrupting a command (SIGINT, SIGTERM) leaves no partial output. Every temporary
// file or folder that will be renamed into place (core/atomic_file.h, cli/output_folder.h) is
// registered here while it exists. InstallInterruptHandler blocks SIGINT and SIGTERM in the
// calling thread (and so in every thread started afterwards) and starts one thread that waits for
// them with sigwait(2): cleanup then runs in an ordinary thread, not in a signal handler, so it may
// remove whole folders. It removes every registered path, prints one line and ends the process
// with _exit(128 + signal): 130 for SIGINT, 143 for SIGTERM, as shells report a process killed by
// the signal.
#pragma once

#include <filesystem>
#include <string>
#include <system_error>

namespace mavloc {

// Call once, first thing in main(), before any other thread starts.
void InstallInterruptHandler();

// Registers a path that is temporary: removed (recursively) if the process is interrupted. Returns
// a token for UnregisterTemporaryPath. Once an interrupt is being handled this call blocks until
// the process ends, so that no temporary file is created after the cleanup has run.
long RegisterTemporaryPath(const std::string& path);
void UnregisterTemporaryPath(long token);

// std::filesystem::create_directories for every folder mavloc writes output into. Once an
// interrupt is being handled it blocks until the process ends: the cleanup removes the temporary
// folders while the command's own thread may still be writing, and a folder created after the
// removal (writing `staging/mav0/imu0` recreates `staging`) would outlive the process.
bool CreateOutputDirectories(const std::filesystem::path& path);
bool CreateOutputDirectories(const std::filesystem::path& path, std::error_code& error);

// While an InterruptsHeld exists, an interrupt waits: its cleanup runs once the holder is gone.
// For a few renames that must happen together (core/atomic_file.h: AtomicFileSet). The holder
// may register and unregister paths; it must not wait for anything slow.
class InterruptsHeld {
 public:
  InterruptsHeld();
  ~InterruptsHeld();
  InterruptsHeld(const InterruptsHeld&) = delete;
  InterruptsHeld& operator=(const InterruptsHeld&) = delete;
};

// RAII registration of one temporary path.
class TemporaryPathGuard {
 public:
  explicit TemporaryPathGuard(const std::string& path) : token_(RegisterTemporaryPath(path)) {}
  ~TemporaryPathGuard() { UnregisterTemporaryPath(token_); }
  TemporaryPathGuard(const TemporaryPathGuard&) = delete;
  TemporaryPathGuard& operator=(const TemporaryPathGuard&) = delete;

 private:
  long token_;
};

}  // namespace mavloc
