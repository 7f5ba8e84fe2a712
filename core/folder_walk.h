// The one folder walk of the readers that look for files by name (matrix, sweep-merge): every
// entry with the type it has after following links, loops and unreadable entries included, so the
// caller either uses an entry, refuses it (exit 2 naming it), or lists it as skipped with a reason.
// No entry is dropped without a word, and no std::filesystem exception leaves the walk.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace mavloc {

struct FolderEntry {
  std::string name;                                                    // file name
  std::string path;                                                    // folder / name
  std::filesystem::file_type type = std::filesystem::file_type::none;  // after following links
  std::string problem;  // why it cannot be used ("is a loop of symbolic links"), else empty
  bool is_file() const { return type == std::filesystem::file_type::regular; }
  bool is_folder() const { return type == std::filesystem::file_type::directory; }
};

// The entries of `folder`, sorted by name. Throws InputError naming the folder when it is not a
// folder or cannot be listed.
std::vector<FolderEntry> ListFolder(const std::string& folder);

// An entry a walk did not use, and why: listed in the report.
struct SkippedFile {
  std::string path, reason;
};

}  // namespace mavloc
