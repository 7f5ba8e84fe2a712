#include "evaluation/report/provenance.h"

#include <chrono>
#include <mutex>

#include "mavloc_version.h"  // generated: kMavlocVersion (CMakeLists.txt)

namespace mavloc {
namespace {

struct Invocation {
  std::mutex mutex;
  std::string text = "mavloc";
  std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now();
};

Invocation& State() {
  static Invocation state;
  return state;
}

// An argument as a user would type it: plain when it holds only safe characters, else quoted.
std::string Quoted(const std::string& argument) {
  const bool plain = !argument.empty() && argument.find_first_not_of(
                                              "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                                              "0123456789-_=.,:/+@%") == std::string::npos;
  if (plain) return argument;
  std::string quoted = "'";
  for (const char c : argument) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

}  // namespace

void RecordInvocation(int argc, const char* const* argv) {
  std::string text = "mavloc";
  for (int i = 1; i < argc; ++i) {
    text.push_back(' ');
    text.append(Quoted(argv[i]));
  }
  std::lock_guard<std::mutex> lock(State().mutex);
  State().text = text;
  State().start = std::chrono::steady_clock::now();
}

std::string InvocationText() {
  std::lock_guard<std::mutex> lock(State().mutex);
  return State().text;
}

std::string MavlocVersion() { return kMavlocVersion; }

double SecondsSinceInvocation() {
  std::lock_guard<std::mutex> lock(State().mutex);
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - State().start).count();
}

Provenance WithInvocation(Provenance provenance) {
  if (provenance.command.empty()) provenance.command = InvocationText();
  if (provenance.version.empty()) provenance.version = MavlocVersion();
  if (provenance.elapsed_s == 0.0) provenance.elapsed_s = SecondsSinceInvocation();
  return provenance;
}

}  // namespace mavloc
