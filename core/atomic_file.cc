#include "core/atomic_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "core/errors.h"
#include "core/interrupt.h"

namespace mavloc {
namespace {

namespace fs = std::filesystem;

std::string FolderOf(const std::string& path) {
  const fs::path target(path);
  return target.has_parent_path() ? target.parent_path().string() : std::string(".");
}

void RequireFolder(const std::string& folder, const std::string& named) {
  std::error_code error;
  if (!fs::is_directory(folder, error))
    throw InputError(named, 0, "", "output folder '" + folder + "' does not exist");
}

// A new file opened exclusively: an existing name, a planted link included, is never opened. The
// counter makes names unique between threads; the retry covers names taken by others. The path
// is registered with core/interrupt.h before the file exists, so an interrupt at any point leaves
// nothing behind; the caller unregisters `token`.
struct CreatedFile {
  int fd = -1;
  std::string path;
  long token = 0;
};

CreatedFile CreateExclusively(const std::string& folder, const std::string& stem,
                              const std::string& suffix, int mode) {
  static std::atomic<unsigned long> counter{0};
  for (int attempt = 0; attempt < 100; ++attempt) {
    CreatedFile file;
    file.path = (fs::path(folder) / (stem + ".tmp-" + std::to_string(::getpid()) + "-" +
                                     std::to_string(counter++) + suffix))
                    .string();
    file.token = RegisterTemporaryPath(file.path);
    file.fd = ::open(file.path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, mode);
    if (file.fd >= 0) return file;
    const int saved_errno = errno;
    UnregisterTemporaryPath(file.token);
    errno = saved_errno;
    if (errno != EEXIST) return {};
  }
  errno = EEXIST;
  return {};
}

bool WriteAll(int fd, const std::string& contents) {
  size_t done = 0;
  while (done < contents.size()) {
    const ssize_t n = ::write(fd, contents.data() + done, contents.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    done += static_cast<size_t>(n);
  }
  return true;
}

// Writes `contents` to a new temporary file beside `path` (registered, see CreateExclusively).
CreatedFile WriteTemporary(const std::string& path, const std::string& contents, int mode) {
  const std::string folder = FolderOf(path);
  RequireFolder(folder, path);
  CreatedFile file = CreateExclusively(folder, fs::path(path).filename().string(), "", mode);
  if (file.fd < 0)
    throw InputError(path, 0, "",
                     std::string("cannot create a file here: ") + std::strerror(errno));
  const bool written = WriteAll(file.fd, contents);
  const int write_errno = errno;
  const bool closed = ::close(file.fd) == 0;
  const int close_errno = errno;
  file.fd = -1;
  if (!written || !closed) {
    ::unlink(file.path.c_str());
    UnregisterTemporaryPath(file.token);
    throw InputError(
        path, 0, "",
        std::string("write failed: ") + std::strerror(!written ? write_errno : close_errno));
  }
  return file;
}

void RenameInto(const std::string& temporary, const std::string& path) {
  if (::rename(temporary.c_str(), path.c_str()) != 0) {
    const std::string reason = std::strerror(errno);
    ::unlink(temporary.c_str());
    throw InputError(path, 0, "", "cannot rename the temporary file into place: " + reason);
  }
}

}  // namespace

void WriteFileAtomically(const std::string& path, const std::string& contents,
                         const WriteOptions& options) {
  const CreatedFile file = WriteTemporary(path, contents, options.executable ? 0777 : 0666);
  try {
    RenameInto(file.path, path);
  } catch (...) {
    UnregisterTemporaryPath(file.token);
    throw;
  }
  UnregisterTemporaryPath(file.token);
}

TemporaryFile::TemporaryFile(const std::string& folder, const std::string& stem,
                             const std::string& suffix, const std::string& contents) {
  RequireFolder(folder, folder);
  const CreatedFile file = CreateExclusively(folder, stem, suffix, 0600);
  if (file.fd < 0)
    throw InputError(folder, 0, "",
                     std::string("cannot create a temporary file: ") + std::strerror(errno));
  const bool written = WriteAll(file.fd, contents);
  if (::close(file.fd) != 0 || !written) {
    ::unlink(file.path.c_str());
    UnregisterTemporaryPath(file.token);
    throw InputError(file.path, 0, "", "cannot write the temporary file");
  }
  path_ = file.path;
  token_ = file.token;
}

TemporaryFile::~TemporaryFile() {
  if (path_.empty()) return;
  ::unlink(path_.c_str());
  UnregisterTemporaryPath(token_);
  path_.clear();
}

TemporaryFolder::TemporaryFolder(const std::string& folder, const std::string& stem) {
  RequireFolder(folder, folder);
  static std::atomic<unsigned long> counter{0};
  for (int attempt = 0; attempt < 100 && path_.empty(); ++attempt) {
    const std::string path = (fs::path(folder) / (stem + ".tmp-" + std::to_string(::getpid()) +
                                                  "-" + std::to_string(counter++)))
                                 .string();
    const long token = RegisterTemporaryPath(path);
    if (::mkdir(path.c_str(), 0700) == 0) {
      path_ = path;
      token_ = token;
      return;
    }
    const int saved_errno = errno;
    UnregisterTemporaryPath(token);
    if (saved_errno != EEXIST)
      throw InputError(
          folder, 0, "",
          std::string("cannot create a temporary folder: ") + std::strerror(saved_errno));
  }
  throw InputError(folder, 0, "", "cannot create a temporary folder: every name is taken");
}

TemporaryFolder::~TemporaryFolder() {
  std::error_code ignored;
  fs::remove_all(path_, ignored);
  UnregisterTemporaryPath(token_);
}

AtomicFileSet::~AtomicFileSet() {
  for (const Pending& file : pending_) {
    ::unlink(file.temporary.c_str());
    UnregisterTemporaryPath(file.token);
  }
}

void AtomicFileSet::Add(const std::string& path, const std::string& contents) {
  const CreatedFile file = WriteTemporary(path, contents, 0666);
  pending_.push_back({file.path, path, file.token});
}

void AtomicFileSet::AddWritten(const std::string& written, const std::string& path) {
  pending_.push_back({written, path, RegisterTemporaryPath(written)});
}

void AtomicFileSet::Commit() {
  const InterruptsHeld held;  // every file renamed, or (interrupted before) none
  std::vector<Pending> files;
  files.swap(pending_);
  for (size_t i = 0; i < files.size(); ++i) {
    try {
      RenameInto(files[i].temporary, files[i].path);
    } catch (...) {
      for (size_t k = i; k < files.size(); ++k) ::unlink(files[k].temporary.c_str());
      for (const Pending& file : files) UnregisterTemporaryPath(file.token);
      throw;
    }
  }
  for (const Pending& file : files) UnregisterTemporaryPath(file.token);
}

}  // namespace mavloc
