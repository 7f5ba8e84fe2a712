#include "core/input_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "core/errors.h"

#include <system_error>

namespace mavloc {
namespace {

std::string TypeProblem(mode_t mode) {
  if (S_ISREG(mode)) return "";
  if (S_ISDIR(mode)) return "is a folder, not a file";
  if (S_ISFIFO(mode)) return "is a named pipe (FIFO), not a file (save the stream to a file first)";
  if (S_ISCHR(mode) || S_ISBLK(mode)) return "is a device, not a file";
  if (S_ISSOCK(mode)) return "is a socket, not a file";
  return "is not a regular file";
}

std::string OpenProblem(int error) {
  switch (error) {
    case ENOENT:
      return "file does not exist";
    case ELOOP:
      return "is a loop of symbolic links (or too many links in a row)";
    case EACCES:
      return "cannot be read: permission denied";
    case ENOTDIR:
      return "a part of the path is not a folder";
    default:
      return std::string("cannot be opened: ") + std::strerror(error);
  }
}

}  // namespace

std::string NotARegularFile(const std::string& path) {
  struct stat info {};
  if (::stat(path.c_str(), &info) != 0) return OpenProblem(errno);
  return TypeProblem(info.st_mode);
}

std::string NotAFolder(const std::string& path) {
  struct stat info {};
  if (::stat(path.c_str(), &info) != 0) return OpenProblem(errno);
  return S_ISDIR(info.st_mode) ? "" : "is not a folder";
}

void RequireFolder(const std::string& path) {
  const std::string problem = NotAFolder(path);
  if (!problem.empty()) throw InputError(path, 0, "", problem);
}

std::string DescribeFilesystemError(const std::filesystem::filesystem_error& error) {
  const std::string path = !error.path1().empty() ? error.path1().string() : error.path2().string();
  const int code = error.code().value();
  std::string problem = error.code().category() == std::system_category() ||
                                error.code().category() == std::generic_category()
                            ? OpenProblem(code)
                            : error.code().message();
  return path.empty() ? problem : path + ": " + problem;
}

void RequireRegularFile(const std::string& path) {
  const std::string problem = NotARegularFile(path);
  if (!problem.empty()) throw InputError(path, 0, "", problem);
}

int OpenRegularFile(const std::string& path) {
  // Type checked before the open (a FIFO's open blocks until a writer comes) and again on the
  // descriptor (the name may have been replaced in between; O_NONBLOCK keeps that open from
  // blocking).
  RequireRegularFile(path);
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) throw InputError(path, 0, "", OpenProblem(errno));
  struct stat info {};
  const std::string problem =
      ::fstat(fd, &info) != 0 ? OpenProblem(errno) : TypeProblem(info.st_mode);
  if (!problem.empty()) {
    ::close(fd);
    throw InputError(path, 0, "", problem);
  }
  ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) & ~O_NONBLOCK);
  return fd;
}

std::FILE* OpenRegularFileStream(const std::string& path) {
  const int fd = OpenRegularFile(path);
  std::FILE* file = ::fdopen(fd, "rb");
  if (!file) {
    const int error = errno;
    ::close(fd);
    throw InputError(path, 0, "", OpenProblem(error));
  }
  return file;
}

std::string ReadRegularFile(const std::string& path) {
  const int fd = OpenRegularFile(path);
  std::string bytes;
  char buffer[1 << 16];
  for (;;) {
    const ssize_t n = ::read(fd, buffer, sizeof buffer);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      const int error = errno;
      ::close(fd);
      throw InputError(path, 0, "", std::string("read failed: ") + std::strerror(error));
    }
    if (n == 0) break;
    bytes.append(buffer, static_cast<size_t>(n));
  }
  ::close(fd);
  return bytes;
}

}  // namespace mavloc
