#include "fuzz/fuzz_support.h"

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <system_error>

namespace mavloc::fuzz {
namespace fs = std::filesystem;

namespace {

void RemoveScratchFolder() {
  std::error_code ignored;
  fs::remove_all(ScratchFolder(), ignored);
}

}  // namespace

const std::string& ScratchFolder() {
  // Never destroyed: RemoveScratchFolder runs at exit, after the destructors of function statics
  // constructed later than its registration.
  static const std::string* const folder = [] {
    const char* tmpdir = std::getenv("TMPDIR");
    const fs::path root = (tmpdir != nullptr && *tmpdir != '\0') ? tmpdir : "/tmp";
    const fs::path path = root / ("mavloc-fuzz-" + std::to_string(getpid()));
    fs::remove_all(path);
    fs::create_directories(path);
    std::atexit(RemoveScratchFolder);
    return new std::string(path.string());
  }();
  return *folder;
}

std::string WriteScratchFile(const std::string& relative_path, const std::string& text) {
  return WriteScratchFile(relative_path, reinterpret_cast<const uint8_t*>(text.data()),
                          text.size());
}

std::string WriteScratchFile(const std::string& relative_path, const uint8_t* data, size_t size) {
  const fs::path path = fs::path(ScratchFolder()) / relative_path;
  fs::create_directories(path.parent_path());
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  out.close();
  if (!out) {
    std::fprintf(stderr, "fuzz: cannot write %s\n", path.c_str());
    std::abort();
  }
  return path.string();
}

void ReportUnexpectedException(const char* what) {
  std::fprintf(stderr, "fuzz finding: exception other than InputError escaped a reader: %s\n",
               what);
  std::abort();
}

}  // namespace mavloc::fuzz
