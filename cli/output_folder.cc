#include "cli/output_folder.h"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "core/errors.h"
#include "core/interrupt.h"
#include "core/text.h"

namespace mavloc::cli {

namespace fs = std::filesystem;

namespace {

fs::path NormalizedTarget(const std::string& target) {
  fs::path path = fs::absolute(target).lexically_normal();
  if (path.has_parent_path() && path.filename().empty()) path = path.parent_path();  // "dir/"
  return path;
}

bool IsMavlocDataset(const fs::path& folder) {
  return fs::is_directory(folder / "mav0") &&
         (fs::exists(folder / "scenario.yaml") || fs::exists(folder / "import.yaml"));
}

bool IsSlurmResults(const fs::path& folder) {
  return fs::exists(folder / "slurm.json") && fs::exists(folder / "sweep.sbatch");
}

// A Slurm results folder holds the shards' partials and the merged report/: a report command
// pointed at it must not replace it.
bool IsReport(const fs::path& folder) {
  return !IsSlurmResults(folder) &&
         (fs::exists(folder / "report.json") || fs::exists(folder / "report.md") ||
          fs::exists(folder / "eval.json"));
}

// What a folder holds, for the message that refuses to replace it.
std::string Describe(const fs::path& folder) {
  if (IsSlurmResults(folder)) return "the results of a `mavloc sweep --slurm`";
  if (IsMavlocDataset(folder)) return "a mavloc dataset";
  if (IsReport(folder)) {
    const auto json =
        nlohmann::json::parse(ReadWholeFile((folder / "report.json").string()), nullptr, false);
    if (json.is_object() && json.contains("report_kind") && json["report_kind"].is_string())
      return "a `mavloc " + json["report_kind"].get<std::string>() + "` report";
    return "a mavloc report";
  }
  return "files that are not mavloc's";
}

}  // namespace

std::string StagingPathFor(const std::string& target) {
  return NormalizedTarget(target).string() + ".tmp-" + std::to_string(::getpid());
}

StagedFolder::StagedFolder(const std::string& target, FolderKind kind, bool force)
    : target_(target) {
  const fs::path path = NormalizedTarget(target);
  const fs::path parent = path.parent_path();
  if (!fs::is_directory(parent))
    throw InputError(target, 0, "", "the parent folder '" + parent.string() + "' does not exist");
  Take(path);
  std::error_code error;
  if (!created_) {
    if (!fs::is_directory(path)) throw InputError(target, 0, "", "exists and is not a folder");
    const bool empty = fs::is_empty(path, error);
    if (!empty && kind == FolderKind::kDataset && !IsMavlocDataset(path))
      throw InputError(target, 0, "",
                       "folder is not empty and is not a mavloc dataset (mav0/ with scenario.yaml "
                       "or import.yaml): not replaced; choose a new or empty folder");
    if (!empty && kind == FolderKind::kReport && !IsReport(path))
      throw InputError(target, 0, "",
                       "folder is not empty and is not a mavloc report (report.json, report.md "
                       "or eval.json): not replaced; choose a new or empty folder");
    if (!empty && kind == FolderKind::kSlurmResults && !IsSlurmResults(path))
      throw InputError(target, 0, "",
                       "folder is not empty and is not the results folder of an earlier "
                       "`mavloc sweep --slurm` (slurm.json, sweep.sbatch): not replaced; choose a "
                       "new or empty folder");
    if (!empty && !force)
      throw InputError(target, 0, "",
                       "folder exists and holds " + Describe(path) +
                           ": not replaced; add --force to replace it, or choose another folder");
  }
  staging_ = StagingPathFor(target);
  interrupt_token_ = RegisterTemporaryPath(staging_);
  fs::remove_all(staging_, error);
  CreateOutputDirectories(staging_, error);
  if (error) {
    UnregisterTemporaryPath(interrupt_token_);
    throw InputError(target, 0, "", "cannot create '" + staging_ + "': " + error.message());
  }
}

void StagedFolder::Take(const fs::path& path) {
  // mkdir is atomic: of two commands creating the same new folder, one creates it. An interrupt
  // before Commit removes the empty folder it created.
  if (!fs::exists(fs::symlink_status(path))) {
    placeholder_token_ = RegisterTemporaryPath(path.string());
    created_ = ::mkdir(path.c_str(), 0777) == 0;
    if (!created_) {
      UnregisterTemporaryPath(placeholder_token_);
      placeholder_token_ = 0;
    }
  }
  lock_fd_ = ::open(path.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (lock_fd_ < 0) return;  // not a folder: the checks that follow say so
  struct stat locked {
  }, named{};
  const bool locked_here = ::flock(lock_fd_, LOCK_EX | LOCK_NB) == 0;
  // The lock is on the folder that was opened: the name must still be that folder.
  const bool same = ::fstat(lock_fd_, &locked) == 0 && ::stat(path.c_str(), &named) == 0 &&
                    locked.st_dev == named.st_dev && locked.st_ino == named.st_ino;
  if (!locked_here || !same) {
    ::close(lock_fd_);
    lock_fd_ = -1;
    if (created_) {  // another command took it first: it is theirs now
      UnregisterTemporaryPath(placeholder_token_);
      placeholder_token_ = 0;
      created_ = false;
    }
    throw InputError(target_, 0, "",
                     "is being written by another mavloc command at this moment: not replaced; "
                     "wait for it to end, or choose another folder");
  }
}

StagedFolder::~StagedFolder() {
  std::error_code error;
  if (!committed_) fs::remove_all(staging_, error);
  // The empty folder taken for a new target, when nothing came of it (rmdir leaves a non-empty
  // one alone).
  if (!committed_ && created_) ::rmdir(NormalizedTarget(target_).c_str());
  if (placeholder_token_ != 0) UnregisterTemporaryPath(placeholder_token_);
  UnregisterTemporaryPath(interrupt_token_);
  if (lock_fd_ >= 0) ::close(lock_fd_);
}

std::string StagedFolder::ForUser(std::string text) const {
  std::string shown = target_;  // "out/" is shown as "out"
  while (shown.size() > 1 && shown.back() == '/') shown.pop_back();
  for (size_t at = text.find(staging_); at != std::string::npos;
       at = text.find(staging_, at + shown.size()))
    text.replace(at, staging_.size(), shown);
  return text;
}

void StagedFolder::Commit() {
  const fs::path path = NormalizedTarget(target_);
  std::error_code error;
  std::string old_content;  // removed after the exchange, with interrupts no longer held
  {
    // The exchange and the end of the taken folder's registration happen together: an interrupt
    // after the exchange must not remove the new folder that now has the target's name.
    const InterruptsHeld held;
    if (placeholder_token_ != 0) {
      UnregisterTemporaryPath(placeholder_token_);
      placeholder_token_ = 0;
    }
    if (!fs::exists(path)) {
      fs::rename(staging_, path, error);
      if (error)
        throw InputError(target_, 0, "", "cannot rename the new folder: " + error.message());
      committed_ = true;
      return;
    }
    // Exchange in one step: the target is never missing nor half old, half new. The staging path
    // then holds the old folder (still registered: an interrupt removes it).
    if (::renameat2(AT_FDCWD, staging_.c_str(), AT_FDCWD, path.c_str(), RENAME_EXCHANGE) == 0) {
      committed_ = true;
      old_content = staging_;
    } else if (errno != EINVAL && errno != ENOSYS) {
      throw InputError(target_, 0, "",
                       std::string("cannot replace the folder: ") + std::strerror(errno));
    }
  }
  if (committed_) {
    fs::remove_all(old_content, error);
    return;
  }
  // A file system without the exchange: rename aside and back.
  const fs::path old = path.string() + ".old-" + std::to_string(::getpid());
  const TemporaryPathGuard guard(old.string());
  fs::rename(path, old, error);
  if (!error) fs::rename(staging_, path, error);
  if (error) {
    std::error_code ignored;
    if (!fs::exists(path)) fs::rename(old, path, ignored);
    throw InputError(target_, 0, "", "cannot replace the folder: " + error.message());
  }
  committed_ = true;
  fs::remove_all(old, error);
}

}  // namespace mavloc::cli
