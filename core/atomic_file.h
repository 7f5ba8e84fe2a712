// The one safe-write rule of every file mavloc writes: the bytes go to a fresh temporary file in
// the destination folder ("<name>.tmp-<pid>-<n>", created exclusively and never through a link)
// which is then renamed over the name. A rename replaces whatever the name was (a planted
// symbolic link included) without following it, so a report folder on a shared disk cannot be
// made to write elsewhere, and a reader never sees half a file. Temporary files are registered
// with core/interrupt.h, so SIGINT/SIGTERM remove them too.
#pragma once

#include <string>
#include <vector>

namespace mavloc {

struct WriteOptions {
  bool executable = false;  // mode 0777 instead of 0666 (before the umask): scripts
};

// Throws InputError when the folder does not exist or the file cannot be written.
void WriteFileAtomically(const std::string& path, const std::string& contents,
                         const WriteOptions& options = {});

// A private temporary file (mode 0600) holding `contents`, created exclusively in `folder` as
// "<stem>.tmp-<pid>-<n><suffix>" and removed by the destructor or an interrupt: a script handed to
// an interpreter. Throws InputError naming `folder`.
class TemporaryFile {
 public:
  TemporaryFile(const std::string& folder, const std::string& stem, const std::string& suffix,
                const std::string& contents);
  ~TemporaryFile();
  TemporaryFile(const TemporaryFile&) = delete;
  TemporaryFile& operator=(const TemporaryFile&) = delete;
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  long token_ = 0;
};

// A private temporary folder (mode 0700) created exclusively in `folder` as "<stem>.tmp-<pid>-<n>",
// removed with its contents by the destructor or an interrupt: where another program writes files
// that AtomicFileSet::AddWritten then renames into `folder`. Throws InputError naming `folder`.
class TemporaryFolder {
 public:
  TemporaryFolder(const std::string& folder, const std::string& stem);
  ~TemporaryFolder();
  TemporaryFolder(const TemporaryFolder&) = delete;
  TemporaryFolder& operator=(const TemporaryFolder&) = delete;
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  long token_ = 0;
};

// Several files that must appear together or not at all (figures and the page that lists them):
// Add writes each to its temporary file at once; Commit renames them all with SIGINT/SIGTERM
// held off (core/interrupt.h), so an interrupt leaves either every old file or every new one.
// Files not committed are removed by the destructor.
class AtomicFileSet {
 public:
  AtomicFileSet() = default;
  ~AtomicFileSet();
  AtomicFileSet(const AtomicFileSet&) = delete;
  AtomicFileSet& operator=(const AtomicFileSet&) = delete;

  void Add(const std::string& path, const std::string& contents);
  // A file already written (by another program) that is renamed to `path` by Commit; it must be
  // on the same file system. It is removed if never committed.
  void AddWritten(const std::string& written, const std::string& path);
  // Throws InputError naming the first file that could not be renamed (the ones before it are
  // in place).
  void Commit();

 private:
  struct Pending {
    std::string temporary, path;
    long token = 0;
  };
  std::vector<Pending> pending_;
};

}  // namespace mavloc
