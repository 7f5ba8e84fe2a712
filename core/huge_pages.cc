#include "core/huge_pages.h"

#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <string>

namespace mavloc {

namespace {

constexpr const char* kTunable = "glibc.malloc.hugetlb=1";

bool KernelOffersHugePagesOnRequest() {
  std::ifstream in("/sys/kernel/mm/transparent_hugepage/enabled");
  std::string modes;
  std::getline(in, modes);
  return modes.find("[madvise]") != std::string::npos;
}

}  // namespace

void ReexecWithHugePages(char** argv) {
  const char* opt_out = std::getenv("MAVLOC_HUGE_PAGES");
  if (opt_out != nullptr && std::string(opt_out) == "0") return;
  const char* tunables = std::getenv("GLIBC_TUNABLES");
  const std::string current = tunables == nullptr ? "" : tunables;
  if (current.find("glibc.malloc.hugetlb") != std::string::npos) return;  // set, by us or the user
  if (!KernelOffersHugePagesOnRequest()) return;
  const std::string wanted = current.empty() ? kTunable : current + ":" + kTunable;
  if (setenv("GLIBC_TUNABLES", wanted.c_str(), 1) != 0) return;
  execv("/proc/self/exe", argv);
  // Not re-executed (no /proc, say): go on as before, without the tunable in the environment.
  if (tunables == nullptr)
    unsetenv("GLIBC_TUNABLES");
  else
    setenv("GLIBC_TUNABLES", current.c_str(), 1);
}

}  // namespace mavloc
