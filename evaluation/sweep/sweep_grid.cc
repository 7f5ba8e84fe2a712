#include "evaluation/sweep/sweep_grid.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <set>

#include "core/errors.h"
#include "core/key_values.h"
#include "core/number_text.h"
#include "datasets/scenarios/scenario.h"
#include "evaluation/alignment.h"
#include "evaluation/estimator_option_ranges.h"
#include "evaluation/sweep/sweep_unit.h"
#include "evaluation/sweep/unit_kinds.h"
#include "solver/estimator.h"

namespace mavloc {

namespace {

uint64_t ParseUnsigned(const std::string& text, const std::string& flag) {
  const ParsedNumber<unsigned long long> value = ParseUnsignedText(text);
  if (!value.ok())
    throw InputError(flag + " '" + text + "': expected a non-negative integer (" +
                     DescribeNumberText(text, value, "a non-negative integer") + ")");
  if (text.find_first_not_of("0123456789") != std::string::npos)  // digits only: no '+'
    throw InputError(flag + " '" + text + "': expected a non-negative integer");
  return value.value;
}

double ParseNumber(const std::string& text, const std::string& flag) {
  const ParsedNumber<double> value = ParseDoubleText(text);
  if (!value.ok())
    throw InputError(flag + " '" + text + "': expected a finite number (" +
                     DescribeNumberText(text, value) + ")");
  return value.value;
}

}  // namespace

std::vector<uint64_t> ParseSeedList(const std::string& text, const std::string& flag) {
  std::vector<uint64_t> seeds;
  for (const auto& item : SplitList(text)) {
    const auto dots = item.find("..");
    if (dots == std::string::npos) {
      seeds.push_back(ParseUnsigned(item, flag));
      continue;
    }
    const uint64_t first = ParseUnsigned(item.substr(0, dots), flag);
    const uint64_t last = ParseUnsigned(item.substr(dots + 2), flag);
    if (last < first) throw InputError(flag + " '" + item + "': empty range (LO..HI, LO <= HI)");
    if (last - first >= 10'000'000) throw InputError(flag + " '" + item + "': range too long");
    for (uint64_t s = first; s <= last; ++s) seeds.push_back(s);
  }
  if (seeds.empty()) throw InputError(flag + " '" + text + "': no seeds");
  return seeds;
}

std::string SeedListText(const std::vector<uint64_t>& seeds) {
  std::string text;
  for (size_t i = 0; i < seeds.size();) {
    size_t j = i;
    while (j + 1 < seeds.size() && seeds[j + 1] == seeds[j] + 1) ++j;
    if (!text.empty()) text += ",";
    if (j - i >= 2) {
      text += fmt::format("{}..{}", seeds[i], seeds[j]);
    } else {
      for (size_t k = i; k <= j; ++k) text += fmt::format("{}{}", k > i ? "," : "", seeds[k]);
    }
    i = j + 1;
  }
  return text;
}

std::pair<std::string, std::vector<std::string>> ParseSettingAxis(const std::string& item) {
  const auto eq = item.find('=');
  if (eq == std::string::npos || eq == 0)
    throw InputError("--set '" + item + "': expected key=value, key=a,b,c or key=LO..HI[:STEP]");
  const std::string key = item.substr(0, eq);
  const std::string text = item.substr(eq + 1);
  std::vector<std::string> values;
  const auto dots = text.find("..");
  if (dots != std::string::npos && text.find(',') == std::string::npos) {
    const std::string flag = "--set " + key;
    const auto colon = text.find(':', dots);
    const double lo = ParseNumber(text.substr(0, dots), flag);
    const double hi = ParseNumber(
        text.substr(dots + 2, colon == std::string::npos ? std::string::npos : colon - dots - 2),
        flag);
    const double step =
        colon == std::string::npos ? 1.0 : ParseNumber(text.substr(colon + 1), flag);
    if (!(step > 0.0) || hi < lo)
      throw InputError(flag + " '" + text + "': expected LO..HI[:STEP] with LO <= HI, STEP > 0");
    const double count = std::floor((hi - lo) / step + 1e-9) + 1.0;
    if (count > 100000) throw InputError(flag + " '" + text + "': range too long");
    // lo + i * step (not repeated addition), written with as many decimals as LO and STEP have,
    // trailing zeros dropped: 0.1..0.3:0.1 gives 0.1, 0.2, 0.3.
    auto decimals = [](const std::string& number) {
      const auto point = number.find('.');
      return point == std::string::npos ? 0 : static_cast<int>(number.size() - point - 1);
    };
    const int digits =
        std::min(12, std::max(decimals(text.substr(0, dots)),
                              colon == std::string::npos ? 0 : decimals(text.substr(colon + 1))));
    for (int i = 0; i < static_cast<int>(count); ++i) {
      std::string value = fmt::format("{:.{}f}", lo + i * step, digits);
      if (value.find('.') != std::string::npos) {
        value.erase(value.find_last_not_of('0') + 1);
        if (value.back() == '.') value.pop_back();
      }
      if (value == "-0") value = "0";
      values.push_back(value);
    }
  } else {
    values = SplitList(text);
  }
  if (values.empty()) throw InputError("--set '" + item + "': no values");
  return {key, values};
}

void ValidateSweepGrid(const SweepGrid& grid) {
  if (grid.scenarios.empty()) throw InputError("sweep: no scenario (--scenario a,b)");
  if (grid.seeds.empty()) throw InputError("sweep: no seeds (--seeds 1..20)");
  if (!grid.repro.empty()) {  // the reproduction checks its own settings and scenarios
    const SweepUnitKind* kind = FindSweepUnitKind(grid.repro);
    if (!kind)
      throw InputError("sweep: '" + grid.repro + "' is not a reproduction that runs as units");
    return;
  }
  if (grid.estimators.empty()) throw InputError("sweep: no estimator (--estimators a,b)");
  auto reject_duplicates = [](const auto& items, const std::string& what) {
    std::set<typename std::decay_t<decltype(items)>::value_type> seen;
    for (const auto& item : items)
      if (!seen.insert(item).second)
        throw InputError(fmt::format("sweep: {} '{}' listed twice", what, item));
  };
  reject_duplicates(grid.scenarios, "scenario");
  reject_duplicates(grid.seeds, "seed");
  reject_duplicates(grid.estimators, "estimator");
  for (const auto& name : grid.scenarios)
    if (!FindScenario(name)) {
      std::string known;
      for (const auto& e : ScenarioRegistry()) known += (known.empty() ? "" : ", ") + e.name;
      throw InputError("unknown scenario '" + name + "' (known: " + known + ")");
    }
  for (const auto& name : grid.estimators)
    if (!FindEstimator(name))
      throw InputError("unknown estimator '" + name + "' (see `mavloc list`)");
  for (const auto& [key, values] : grid.settings) {
    if (values.empty()) throw InputError("--set " + key + ": no values");
    reject_duplicates(values, "value of --set " + key);
  }
  // Every setting value against every scenario, and every estimator option, before any unit runs
  // (the checks `compare` makes: datasets/scenarios/scenario.h, solver/estimator.h).
  for (const auto& name : grid.scenarios) {
    const ScenarioEntry& entry = *FindScenario(name);
    ScenarioOptions options;
    options.duration_s = grid.duration_s;
    CheckScenarioOptions(entry, options);
    for (const auto& [key, values] : grid.settings)
      for (const auto& value : values) {
        options.settings = {{key, value}};
        CheckScenarioOptions(entry, options);
      }
  }
  for (const auto& item : grid.options) {
    const auto colon = item.find(':');
    const auto eq = item.find('=');
    if (eq == std::string::npos || eq == 0 || (colon != std::string::npos && colon + 1 == eq))
      throw InputError("--option '" + item + "': expected [estimator:]key=value");
    if (colon != std::string::npos && colon < eq) {
      const std::string name = item.substr(0, colon);
      const EstimatorEntry* entry = FindEstimator(name);
      if (!entry ||
          std::find(grid.estimators.begin(), grid.estimators.end(), name) == grid.estimators.end())
        throw InputError("--option " + item + ": '" + name + "' is not an estimator of this sweep");
      EstimatorOptions one;
      one.Set(item.substr(colon + 1, eq - colon - 1), item.substr(eq + 1));
      CheckEstimatorOptions(*entry, one);
    } else {
      const std::string key = item.substr(0, eq);
      bool used = false;
      for (const auto& name : grid.estimators) used = used || FindEstimator(name)->HasOption(key);
      if (!used)
        throw InputError("--option " + item + ": no estimator of this sweep has option '" + key +
                         "'");
    }
  }
  for (const auto& name : grid.estimators)
    CheckEstimatorOptionValues(*FindEstimator(name), SweepEstimatorOptions(name, grid.options));
  if (!ParseAlignmentMode(grid.align))
    throw InputError("--align '" + grid.align + "': expected none, se3, sim3 or posyaw");
  if (!(grid.max_dt_s > 0.0)) throw InputError("--max-dt: must be positive");
  if (grid.duration_s && !(*grid.duration_s > 0.0))
    throw InputError("--duration: must be positive");
}

size_t SweepUnitCount(const SweepGrid& grid) {
  size_t combinations = 1;
  for (const auto& [key, values] : grid.settings) combinations *= values.size();
  return grid.scenarios.size() * combinations * grid.seeds.size();
}

SweepUnit SweepUnitAt(const SweepGrid& grid, size_t index) {
  SweepUnit unit;
  unit.index = index;
  size_t rest = index;
  unit.seed = grid.seeds[rest % grid.seeds.size()];
  rest /= grid.seeds.size();
  // The last key varies fastest: peel keys from the back.
  for (auto it = grid.settings.rbegin(); it != grid.settings.rend(); ++it) {
    unit.settings[it->first] = it->second[rest % it->second.size()];
    rest /= it->second.size();
  }
  unit.scenario = grid.scenarios.at(rest);
  return unit;
}

std::string SettingsLabel(const std::map<std::string, std::string>& settings) {
  std::string label;
  for (const auto& [key, value] : settings)
    label += (label.empty() ? "" : "; ") + key + "=" + value;
  return label;
}

nlohmann::json SweepGridToJson(const SweepGrid& grid) {
  nlohmann::json j;
  j["scenarios"] = grid.scenarios;
  j["seeds"] = SeedListText(grid.seeds);
  j["settings"] = grid.settings;
  j["estimators"] = grid.estimators;
  j["options"] = grid.options;
  j["duration_s"] = grid.duration_s ? nlohmann::json(*grid.duration_s) : nlohmann::json(nullptr);
  j["align"] = grid.align;
  j["max_dt_s"] = grid.max_dt_s;
  if (!grid.repro.empty()) {
    j["repro"] = grid.repro;
    j["repro_settings"] = grid.repro_settings;
  }
  return j;
}

SweepGrid SweepGridFromJson(const nlohmann::json& j, const std::string& source) {
  SweepGrid grid;
  try {
    grid.scenarios = j.at("scenarios").get<std::vector<std::string>>();
    grid.seeds = ParseSeedList(j.at("seeds").get<std::string>(), source + ": seeds");
    grid.settings = j.at("settings").get<std::map<std::string, std::vector<std::string>>>();
    grid.estimators = j.at("estimators").get<std::vector<std::string>>();
    grid.options = j.at("options").get<std::vector<std::string>>();
    if (!j.at("duration_s").is_null()) grid.duration_s = j.at("duration_s").get<double>();
    grid.align = j.at("align").get<std::string>();
    grid.max_dt_s = j.at("max_dt_s").get<double>();
    if (j.contains("repro")) {
      grid.repro = j.at("repro").get<std::string>();
      grid.repro_settings = j.at("repro_settings").get<std::map<std::string, std::string>>();
    }
  } catch (const nlohmann::json::exception& e) {
    throw InputError(source, 0, "grid", std::string("not a sweep grid: ") + e.what());
  }
  ValidateSweepGrid(grid);
  return grid;
}

std::string CanonicalGridText(const SweepGrid& grid) { return SweepGridToJson(grid).dump(); }

std::string Fnv1a64Hex(const std::string& bytes) {
  uint64_t hash = 0xcbf29ce484222325ULL;  // FNV-1a 64 offset basis
  for (const unsigned char byte : bytes) {
    hash ^= byte;
    hash *= 0x100000001b3ULL;  // FNV 64 prime
  }
  return fmt::format("{:016x}", hash);
}

std::string ExecutableHash() {
  static const std::string hash = [] {
    std::ifstream in("/proc/self/exe", std::ios::binary);
    if (!in) return std::string("unknown");
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    return Fnv1a64Hex(bytes);
  }();
  return hash;
}

std::string SweepFingerprint(const SweepGrid& grid) {
  return Fnv1a64Hex(CanonicalGridText(grid) + "\nmavloc executable " + ExecutableHash());
}

}  // namespace mavloc
