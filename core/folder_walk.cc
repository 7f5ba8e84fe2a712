#include "core/folder_walk.h"

#include <algorithm>
#include <system_error>

#include "core/errors.h"
#include "core/input_file.h"

namespace mavloc {

namespace fs = std::filesystem;

std::vector<FolderEntry> ListFolder(const std::string& folder) {
  RequireFolder(folder);
  std::vector<FolderEntry> entries;
  std::error_code error;
  fs::directory_iterator it(folder, error);
  if (error) throw InputError(folder, 0, "", "cannot be listed: " + error.message());
  for (; it != fs::directory_iterator(); it.increment(error)) {
    if (error) break;
    FolderEntry entry;
    entry.name = it->path().filename().string();
    entry.path = it->path().string();
    std::error_code status_error;
    entry.type = fs::status(it->path(), status_error).type();
    if (status_error) {
      entry.type = fs::file_type::none;
      entry.problem = NotARegularFile(entry.path);
      if (entry.problem.empty()) entry.problem = "cannot be read: " + status_error.message();
    }
    if (entry.problem.empty() && entry.type == fs::file_type::not_found)
      entry.problem = "is a symbolic link to nothing";
    entries.push_back(std::move(entry));
  }
  if (error) throw InputError(folder, 0, "", "cannot be listed: " + error.message());
  std::sort(entries.begin(), entries.end(),
            [](const FolderEntry& a, const FolderEntry& b) { return a.name < b.name; });
  return entries;
}

}  // namespace mavloc
