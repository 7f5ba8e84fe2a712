#include "core/interrupt.h"

#include <pthread.h>
#include <signal.h>
#include <unistd.h>

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <map>
#include <mutex>
#include <thread>

namespace mavloc {

namespace {

struct Registry {
  // Recursive: a thread holding InterruptsHeld registers and unregisters paths.
  std::recursive_mutex mutex;
  std::map<long, std::string> paths;
  long next_token = 1;
  bool interrupted = false;
};

Registry& TheRegistry() {
  static Registry* registry = new Registry;  // never destroyed: used until _exit
  return *registry;
}

[[noreturn]] void CleanUpAndExit(int signal_number) {
  Registry& registry = TheRegistry();
  // Held until _exit: a thread registering a new temporary path waits instead of creating it.
  registry.mutex.lock();
  registry.interrupted = true;
  // The command's thread may still be writing files into a folder being removed (remove_all then
  // fails on a folder that is not empty): remove again until every path is gone. No new folder
  // can appear (CreateOutputDirectories waits for the mutex), so this ends.
  int removed = 0;
  for (const auto& [token, path] : registry.paths) {
    bool existed = false;
    for (int attempt = 0; attempt < 1000; ++attempt) {
      std::error_code error;
      if (!std::filesystem::exists(std::filesystem::symlink_status(path, error))) break;
      existed = true;
      std::filesystem::remove_all(path, error);
    }
    removed += existed;
  }
  const char* name = signal_number == SIGINT ? "SIGINT" : "SIGTERM";
  std::fprintf(stderr, "mavloc: interrupted by %s; removed %d temporary output(s)\n", name,
               removed);
  std::fflush(stderr);
  ::_exit(128 + signal_number);
}

}  // namespace

void InstallInterruptHandler() {
  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGINT);
  sigaddset(&signals, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);
  TheRegistry();
  std::thread([signals] {
    int signal_number = 0;
    while (sigwait(&signals, &signal_number) != 0) {
    }
    CleanUpAndExit(signal_number);
  }).detach();
}

long RegisterTemporaryPath(const std::string& path) {
  Registry& registry = TheRegistry();
  std::lock_guard<std::recursive_mutex> lock(registry.mutex);
  const long token = registry.next_token++;
  registry.paths[token] = std::filesystem::absolute(path).string();
  return token;
}

bool CreateOutputDirectories(const std::filesystem::path& path, std::error_code& error) {
  std::lock_guard<std::recursive_mutex> lock(TheRegistry().mutex);
  return std::filesystem::create_directories(path, error);
}

bool CreateOutputDirectories(const std::filesystem::path& path) {
  std::lock_guard<std::recursive_mutex> lock(TheRegistry().mutex);
  return std::filesystem::create_directories(path);
}

InterruptsHeld::InterruptsHeld() { TheRegistry().mutex.lock(); }
InterruptsHeld::~InterruptsHeld() { TheRegistry().mutex.unlock(); }

void UnregisterTemporaryPath(long token) {
  Registry& registry = TheRegistry();
  std::lock_guard<std::recursive_mutex> lock(registry.mutex);
  registry.paths.erase(token);
}

}  // namespace mavloc
