#include "cli/output_folder.h"

#include <fcntl.h>
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
  std::error_code error;
  if (fs::exists(path)) {
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

StagedFolder::~StagedFolder() {
  std::error_code error;
  if (!committed_) fs::remove_all(staging_, error);
  UnregisterTemporaryPath(interrupt_token_);
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
  if (!fs::exists(path)) {
    fs::rename(staging_, path, error);
    if (error) throw InputError(target_, 0, "", "cannot rename the new folder: " + error.message());
    committed_ = true;
    return;
  }
  // Exchange in one step: the target is never missing nor half old, half new.
  if (::renameat2(AT_FDCWD, staging_.c_str(), AT_FDCWD, path.c_str(), RENAME_EXCHANGE) != 0) {
    if (errno != EINVAL && errno != ENOSYS)
      throw InputError(target_, 0, "",
                       std::string("cannot replace the folder: ") + std::strerror(errno));
    const fs::path old = path.string() + ".old-" + std::to_string(::getpid());
    const TemporaryPathGuard guard(old.string());
    fs::rename(path, old, error);
    if (!error) fs::rename(staging_, path, error);
    if (error) {
      std::error_code ignored;
      if (!fs::exists(path)) fs::rename(old, path, ignored);
      throw InputError(target_, 0, "", "cannot replace the folder: " + error.message());
    }
    fs::remove_all(old, error);
    committed_ = true;
    return;
  }
  // The staging path now holds the old folder.
  fs::remove_all(staging_, error);
  committed_ = true;
}

}  // namespace mavloc::cli
