#include "cli/common.h"

#include <filesystem>
#include <sstream>

#include "cli/commands.h"
#include "core/errors.h"
#include "core/progress.h"

namespace mavloc::cli {

std::string SelfPath() { return std::filesystem::read_symlink("/proc/self/exe").string(); }

std::map<std::string, std::string> ParseKeyValues(const std::vector<std::string>& items,
                                                  const std::string& flag) {
  std::map<std::string, std::string> values;
  for (const auto& item : items) {
    const auto eq = item.find('=');
    if (eq == std::string::npos || eq == 0)
      throw InputError(flag + " '" + item + "': expected key=value");
    values[item.substr(0, eq)] = item.substr(eq + 1);
  }
  return values;
}

Dataset SimulateScenario(const std::string& name, const ScenarioOptions& options) {
  const ScenarioEntry* entry = FindScenario(name);
  if (!entry) {
    std::string known;
    for (const auto& e : ScenarioRegistry()) known += (known.empty() ? "" : ", ") + e.name;
    throw InputError("unknown scenario '" + name + "' (known: " + known + ")");
  }
  ReportProgress("simulate",
                 "generating scenario " + name + " (seed " + std::to_string(options.seed) + ")");
  Dataset dataset = entry->generate(options);
  if (dataset.scenario.empty()) dataset.scenario = name;
  if (dataset.name.empty()) dataset.name = name;
  return dataset;
}

}  // namespace mavloc::cli
