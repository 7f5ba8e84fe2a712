#include "core/key_values.h"

#include <algorithm>
#include <cctype>
#include <limits>
#include <sstream>

#include "core/errors.h"
#include "core/number_text.h"

namespace mavloc {

namespace {
InputError BadSetting(const std::string& key, const std::string& value, const std::string& what) {
  return InputError("setting '" + key + "=" + value + "': expected " + what);
}
}  // namespace

double GetDoubleSetting(const KeyValues& values, const std::string& key, double fallback) {
  const auto it = values.find(key);
  if (it == values.end()) return fallback;
  const ParsedNumber<double> value = ParseDoubleText(it->second);
  if (!value.ok())
    throw BadSetting(key, it->second,
                     "a finite number (" + DescribeNumberText(it->second, value) + ")");
  return value.value;
}

int GetIntSetting(const KeyValues& values, const std::string& key, int fallback) {
  const auto it = values.find(key);
  if (it == values.end()) return fallback;
  const ParsedNumber<long long> value = ParseIntegerText(it->second);
  if (!value.ok() || value.value < std::numeric_limits<int>::min() ||
      value.value > std::numeric_limits<int>::max())
    throw BadSetting(key, it->second, "an integer");
  return static_cast<int>(value.value);
}

bool GetBoolSetting(const KeyValues& values, const std::string& key, bool fallback) {
  const auto it = values.find(key);
  if (it == values.end()) return fallback;
  std::string v = it->second;
  std::transform(v.begin(), v.end(), v.begin(), [](unsigned char c) { return std::tolower(c); });
  if (v == "1" || v == "true" || v == "yes" || v == "on") return true;
  if (v == "0" || v == "false" || v == "no" || v == "off") return false;
  throw BadSetting(key, it->second, "true or false");
}

std::string GetStringSetting(const KeyValues& values, const std::string& key,
                             const std::string& fallback) {
  const auto it = values.find(key);
  return it == values.end() ? fallback : it->second;
}

std::vector<std::string> SplitList(const std::string& text) {
  std::vector<std::string> items;
  std::stringstream stream(text);
  std::string item;
  while (std::getline(stream, item, ',')) {
    item.erase(0, item.find_first_not_of(" \t"));
    item.erase(item.find_last_not_of(" \t") + 1);
    if (!item.empty()) items.push_back(item);
  }
  return items;
}

}  // namespace mavloc
