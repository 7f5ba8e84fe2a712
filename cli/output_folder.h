// Output folders written whole or not at all: a command writes into a
// fresh staging folder "<target>.tmp-<pid>" beside the target and, once everything is written,
// puts it in the target's place. So a new dataset never keeps the streams of an older one (e.g. its
// tags0/), a report folder never keeps the files of an earlier report, an error leaves nothing, and
// SIGINT/SIGTERM remove the staging folder (core/interrupt.h).
#pragma once

#include <filesystem>
#include <string>

namespace mavloc::cli {

enum class FolderKind {
  kDataset,  // written by `mavloc simulate`: replaces a mavloc dataset (mav0/ + scenario.yaml or
             // import.yaml) or an empty folder
  kReport,   // compare, eval, repro, obstacles: replaces a report (report.json, report.md or
             // eval.json) or an empty folder; never a Slurm results folder
  kSlurmResults,  // sweep --slurm: replaces the results folder of an earlier --slurm (slurm.json
                  // and sweep.sbatch) or an empty folder
};

// "<target>.tmp-<pid>" for the target written with a trailing "/" removed: where StagedFolder and
// WriteEurocDatasetAtomically stage their output.
std::string StagingPathFor(const std::string& target);

class StagedFolder {
 public:
  // Checks the target before any work is done (throws InputError): its parent folder must exist,
  // and an existing target must be an empty folder, or, when the user asked for it (`force`,
  // the commands' --force), a folder of `kind`. No command replaces a folder it was not asked to:
  // the message says what the folder holds and names --force. The target is taken at once: a new
  // one is created empty (mkdir: of two commands, one creates it) and every target is locked
  // (flock) until the object ends, so a second command writing the same folder at the same time
  // is refused ("is being written by another mavloc command") instead of replacing the first's
  // output. Then creates the staging folder.
  StagedFolder(const std::string& target, FolderKind kind, bool force);
  // Removes the staging folder unless Commit() succeeded.
  ~StagedFolder();
  StagedFolder(const StagedFolder&) = delete;
  StagedFolder& operator=(const StagedFolder&) = delete;

  // Where the command writes its files.
  const std::string& path() const { return staging_; }
  // `text` with the staging path replaced by the target as the user wrote it (for messages that
  // name files written into the staging folder).
  std::string ForUser(std::string text) const;
  // Puts the staging folder in the target's place: an existing target is exchanged with it in one
  // step (renameat2 RENAME_EXCHANGE; rename-aside-and-back where the file system lacks it) and its
  // old content removed. Throws InputError when the rename fails.
  void Commit();

 private:
  // Creates a new target empty, or locks an existing one; throws when another command holds it.
  void Take(const std::filesystem::path& path);

  std::string target_;
  std::string staging_;
  long interrupt_token_ = 0;
  long placeholder_token_ = 0;  // the empty target this object created, until Commit
  bool created_ = false;        // this object created the target folder
  int lock_fd_ = -1;            // the target folder, flock'ed
  bool committed_ = false;
};

}  // namespace mavloc::cli
