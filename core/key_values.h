// Typed look-ups in key=value settings (`--set key=value`, `--option key=value`). A value that
// does not parse throws InputError naming the key and what was expected.
#pragma once

#include <map>
#include <string>
#include <vector>

namespace mavloc {

using KeyValues = std::map<std::string, std::string>;

double GetDoubleSetting(const KeyValues& values, const std::string& key, double fallback);
int GetIntSetting(const KeyValues& values, const std::string& key, int fallback);
bool GetBoolSetting(const KeyValues& values, const std::string& key, bool fallback);
std::string GetStringSetting(const KeyValues& values, const std::string& key,
                             const std::string& fallback);

// "a, b,,c" -> {"a", "b", "c"}: a comma-separated list (estimator names, scenarios), items
// trimmed of blanks, empty items dropped.
std::vector<std::string> SplitList(const std::string& text);

}  // namespace mavloc
