#include "core/atomic_file.h"

#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

#include "core/errors.h"
#include "core/interrupt.h"

namespace mavloc {

void WriteFileAtomically(const std::string& path, const std::string& contents) {
  const std::filesystem::path target(path);
  const auto folder = target.has_parent_path() ? target.parent_path() : std::filesystem::path(".");
  if (!std::filesystem::is_directory(folder))
    throw InputError(path, 0, "", "output folder '" + folder.string() + "' does not exist");
  const std::string temporary = path + ".tmp-" + std::to_string(::getpid());
  const TemporaryPathGuard guard(temporary);  // removed if the process is interrupted
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    if (!out) {
      std::remove(temporary.c_str());
      throw InputError(path, 0, "", "cannot open for writing");
    }
    out << contents;
    out.flush();
    if (!out) {
      std::remove(temporary.c_str());
      throw InputError(path, 0, "", "write failed");
    }
  }
  std::error_code error;
  std::filesystem::rename(temporary, target, error);
  if (error) {
    std::remove(temporary.c_str());
    throw InputError(path, 0, "", "cannot rename temporary file: " + error.message());
  }
}

}  // namespace mavloc
