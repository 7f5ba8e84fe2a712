// The one file-type check of every reader: a path where a file is expected must name a regular
// file. A named pipe would block open() or be read once only, a device never ends, a folder or a
// loop of symbolic links cannot be read at all: each is refused with an InputError naming the path
// (exit code 2), before anything is read. Files are opened with O_NONBLOCK and checked with fstat
// on the open descriptor, so a file swapped for a pipe between a check and the open cannot block.
#pragma once

#include <cstdio>
#include <filesystem>
#include <string>

namespace mavloc {

// Why `path` is not a readable regular file ("does not exist", "is a named pipe (FIFO), not a
// file", "is a folder, not a file", "is a loop of symbolic links", ...), or empty when it is one.
std::string NotARegularFile(const std::string& path);

// The same for a folder: empty when `path` is one (following links).
std::string NotAFolder(const std::string& path);
void RequireFolder(const std::string& path);

// "PATH: why" for a std::filesystem exception (a loop of links, a folder that vanished during a
// walk), the way the readers say it: what cli/main.cc prints for one, with exit code 2.
std::string DescribeFilesystemError(const std::filesystem::filesystem_error& error);

// Throws InputError(path, ..., NotARegularFile(path)) unless path is a regular file.
void RequireRegularFile(const std::string& path);

// A descriptor open for reading on the regular file `path` (O_CLOEXEC, blocking reads); throws
// InputError naming the path otherwise.
int OpenRegularFile(const std::string& path);

// The same as a stdio stream ("rb").
std::FILE* OpenRegularFileStream(const std::string& path);

// The whole regular file; throws InputError naming the path (not a regular file, read error).
std::string ReadRegularFile(const std::string& path);

}  // namespace mavloc
