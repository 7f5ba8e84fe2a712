#include "datasets/io/rosbag/bzip2_file.h"

#include <bzlib.h>
#include <fcntl.h>
#include <fmt/format.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <vector>

#include "core/errors.h"
#include "core/input_file.h"
#include "core/progress.h"

namespace mavloc::ros1 {

namespace {

struct FileCloser {
  void operator()(std::FILE* file) const { std::fclose(file); }
};
using FilePtr = std::unique_ptr<std::FILE, FileCloser>;

// Reads decompressed bytes from `file` through BZ2_bzRead, reopening after each stream end so that
// concatenated streams are read whole. `sink(data, size)` returns false to stop early.
template <class Sink>
void ReadBzip2(std::FILE* file, const std::string& path, Sink&& sink) {
  std::vector<char> unused;
  std::vector<char> buffer(1 << 20);
  uint64_t decompressed = 0;
  while (true) {
    int error = BZ_OK;
    BZFILE* bz = BZ2_bzReadOpen(&error, file, 0, 0, unused.data(), static_cast<int>(unused.size()));
    if (error != BZ_OK) {
      BZ2_bzReadClose(&error, bz);
      throw InputError(path, 0, "", "cannot start bzip2 decompression");
    }
    while (error == BZ_OK) {
      const int n = BZ2_bzRead(&error, bz, buffer.data(), static_cast<int>(buffer.size()));
      if (error != BZ_OK && error != BZ_STREAM_END) break;
      if (n > 0) {
        decompressed += static_cast<uint64_t>(n);
        if (!sink(buffer.data(), static_cast<std::size_t>(n))) {
          BZ2_bzReadClose(&error, bz);
          return;
        }
      }
    }
    if (error != BZ_STREAM_END) {
      int ignored = BZ_OK;
      BZ2_bzReadClose(&ignored, bz);
      const char* what = error == BZ_UNEXPECTED_EOF ? "truncated" : "corrupt";
      throw InputError(
          path, 0, "",
          fmt::format("bzip2 stream is {} after {} decompressed bytes (bzlib error {})", what,
                      decompressed, error));
    }
    void* unused_data = nullptr;
    int unused_size = 0;
    BZ2_bzReadGetUnused(&error, bz, &unused_data, &unused_size);
    unused.assign(static_cast<char*>(unused_data), static_cast<char*>(unused_data) + unused_size);
    BZ2_bzReadClose(&error, bz);
    if (unused.empty()) {  // another stream follows only when more bytes remain
      const int next = std::fgetc(file);
      if (next == EOF) return;
      std::ungetc(next, file);
    }
  }
}

}  // namespace

bool IsBzip2File(const std::string& path) {
  if (!NotARegularFile(path).empty()) return false;  // a pipe would block the open
  std::ifstream in(path, std::ios::binary);
  char magic[3] = {};
  return in.read(magic, 3) && magic[0] == 'B' && magic[1] == 'Z' && magic[2] == 'h';
}

std::string ReadBzip2Prefix(const std::string& path, std::size_t max_bytes) {
  if (!IsBzip2File(path)) return {};
  FilePtr file(std::fopen(path.c_str(), "rb"));
  if (!file) return {};
  std::string prefix;
  try {
    ReadBzip2(file.get(), path, [&](const char* data, std::size_t size) {
      prefix.append(data, std::min(size, max_bytes - prefix.size()));
      return prefix.size() < max_bytes;
    });
  } catch (const InputError&) {
    // a prefix is all that is asked for: a stream that breaks later still has one
  }
  return prefix;
}

void DecompressBzip2File(const std::string& bz2_path, const std::string& out_path) {
  FilePtr in(std::fopen(bz2_path.c_str(), "rb"));
  if (!in) throw InputError(bz2_path, 0, "", "cannot open the file");
  // Created exclusively: a name planted in the shared temporary folder (a link) is never opened.
  const int out_fd =
      ::open(out_path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0600);
  FilePtr out(out_fd >= 0 ? ::fdopen(out_fd, "wb") : nullptr);
  if (!out && out_fd >= 0) ::close(out_fd);
  if (!out) throw InputError(out_path, 0, "", "cannot create the temporary decompressed bag");
  uint64_t written = 0;
  uint64_t next_report = 256ull << 20;
  try {
    ReadBzip2(in.get(), bz2_path, [&](const char* data, std::size_t size) {
      if (std::fwrite(data, 1, size, out.get()) != size) {
        throw InputError(out_path, 0, "", "cannot write the decompressed bag (disk full?)");
      }
      written += size;
      if (written >= next_report) {
        ReportProgress("bag", fmt::format("{}: {} MB decompressed", bz2_path, written >> 20));
        next_report += 256ull << 20;
      }
      return true;
    });
    if (std::fflush(out.get()) != 0) {
      throw InputError(out_path, 0, "", "cannot write the decompressed bag (disk full?)");
    }
  } catch (...) {
    out.reset();
    std::error_code ignored;
    std::filesystem::remove(out_path, ignored);
    throw;
  }
}

}  // namespace mavloc::ros1
