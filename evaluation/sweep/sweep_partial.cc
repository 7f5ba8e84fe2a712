#include "evaluation/sweep/sweep_partial.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <regex>

#include "core/atomic_file.h"
#include "core/errors.h"
#include "core/folder_walk.h"
#include "core/input_file.h"
#include "core/interrupt.h"

namespace fs = std::filesystem;

namespace mavloc {

namespace {

constexpr const char* kFormat = "mavloc-sweep-partial 1";
const std::regex kPartialName(R"(partial-([0-9]+)-of-([0-9]+)\.json)");

// The whole partial; a named pipe, a folder or a loop of links is refused naming it (it would
// block the read or end it in a filesystem error).
std::string ReadAll(const std::string& path) { return ReadRegularFile(path); }

// Every sweep metric is an RMSE, a mean absolute error or a count: finite, not negative, and far
// below this bound, which keeps sums of squares over any grid finite.
constexpr double kMaxMetricValue = 1e100;

// The result of one unit of a plain sweep grid (evaluation/sweep/sweep_unit.cc writes it), checked
// field by field so that a damaged partial is refused naming the unit and the field.
void CheckUnitResult(const nlohmann::json& unit, const std::string& path, size_t k) {
  const std::string at = fmt::format("units[{}]", k);
  auto refuse = [&](const std::string& field, const std::string& what) {
    throw InputError(path, 0, at + field, "damaged unit result: " + what);
  };
  if (!unit.is_object()) refuse("", "not an object");
  if (!unit.contains("scenario") || !unit["scenario"].is_string()) refuse(".scenario", "not text");
  if (!unit.contains("seed") || !unit["seed"].is_number_unsigned()) refuse(".seed", "not a seed");
  if (!unit.contains("settings") || !unit["settings"].is_object())
    refuse(".settings", "not an object");
  for (const auto& [key, value] : unit["settings"].items())
    if (!value.is_string()) refuse(".settings." + key, "not text");
  if (!unit.contains("estimators") || !unit["estimators"].is_array())
    refuse(".estimators", "not a list");
  for (size_t e = 0; e < unit["estimators"].size(); ++e) {
    const auto& row = unit["estimators"][e];
    const std::string field = fmt::format(".estimators[{}]", e);
    if (!row.is_object() || !row.contains("name") || !row["name"].is_string() ||
        !row.contains("ran") || !row["ran"].is_boolean())
      refuse(field, "needs a name and ran");
    if (!row["ran"].get<bool>()) {
      if (row.contains("skipped") && !row["skipped"].is_string())
        refuse(field + ".skipped", "not text");
      continue;
    }
    if (!row.contains("metrics") || !row["metrics"].is_object() || !row.contains("units") ||
        !row["units"].is_object())
      refuse(field, "a run without metrics and units");
    for (const auto& [metric, value] : row["metrics"].items()) {
      if (!value.is_number() || !std::isfinite(value.get<double>()) || value.get<double>() < 0.0 ||
          value.get<double>() > kMaxMetricValue)
        refuse(field + ".metrics." + metric,
               "must be a finite number from 0 to 1e100 (an RMSE, a mean absolute error or a "
               "count), not " +
                   value.dump().substr(0, 40));
      if (!row["units"].contains(metric) || !row["units"][metric].is_string())
        refuse(field + ".units." + metric, "no unit for the metric");
    }
  }
}

std::string JoinedNames(const std::vector<std::string>& names) {
  return names.empty() ? std::string("none") : fmt::format("{}", fmt::join(names, ", "));
}

// A unit of a plain sweep against its grid: the scenario, seed and settings of the grid's unit of
// that index, and one row per estimator of the grid, in the grid's order. A unit of another grid
// (an edited partial) would otherwise be merged into the cells of this one.
void CheckUnitAgainstGrid(const nlohmann::json& unit, const SweepGrid& grid,
                          const std::string& path, size_t k) {
  const size_t index = unit["index"].get<size_t>();
  const std::string at = fmt::format("units[{}]", k);
  const SweepUnit expected = SweepUnitAt(grid, index);
  const auto settings = unit["settings"].get<std::map<std::string, std::string>>();
  if (unit["scenario"].get<std::string>() != expected.scenario ||
      unit["seed"].get<uint64_t>() != expected.seed || settings != expected.settings)
    throw InputError(
        path, 0, at,
        fmt::format("unit {} is scenario {}, seed {}{}; the grid's unit {} is "
                    "scenario {}, seed {}{}: not a unit of this grid",
                    index, unit["scenario"].get<std::string>(), unit["seed"].get<uint64_t>(),
                    settings.empty() ? "" : ", " + SettingsLabel(settings), index,
                    expected.scenario, expected.seed,
                    expected.settings.empty() ? "" : ", " + SettingsLabel(expected.settings)));
  std::vector<std::string> names;
  for (const auto& row : unit["estimators"]) names.push_back(row["name"].get<std::string>());
  for (size_t e = 0; e < names.size(); ++e)
    if (std::find(grid.estimators.begin(), grid.estimators.end(), names[e]) ==
        grid.estimators.end())
      throw InputError(
          path, 0, fmt::format("{}.estimators[{}].name", at, e),
          fmt::format("unit {}: estimator '{}' is not in the grid (estimators: {})", index,
                      PrintableMessage(names[e], 60), JoinedNames(grid.estimators)));
  if (names != grid.estimators)
    throw InputError(path, 0, at + ".estimators",
                     fmt::format("unit {} has the estimators {}; the grid runs {} on every unit",
                                 index, JoinedNames(names), JoinedNames(grid.estimators)));
}

struct Partial {
  std::string path;
  nlohmann::json json;
  ShardSpec spec;
};

// Parses and checks one partial on its own (format, complete marker, fingerprint, unit set).
Partial ReadPartial(const std::string& path) {
  Partial p;
  p.path = path;
  try {
    p.json = nlohmann::json::parse(ReadAll(path));
  } catch (const nlohmann::json::exception&) {
    throw InputError(path, 0, "",
                     "incomplete partial: not valid JSON (cut short by an interrupted copy or "
                     "shard?); rerun this shard");
  }
  if (!p.json.is_object() || p.json.value("format", "") != kFormat)
    throw InputError(path, 0, "format",
                     std::string("not a mavloc sweep partial (expected \"") + kFormat + "\")");
  if (!p.json.contains("complete") || p.json["complete"] != true)
    throw InputError(path, 0, "complete",
                     "incomplete partial: no \"complete\": true marker; rerun this shard");
  try {
    for (const char* field : {"shard", "shards"}) {
      const auto& value = p.json.at(field);
      if (!value.is_number_integer() || value.get<int64_t>() < 1 ||
          value.get<int64_t>() > 1000000000)
        throw InputError(path, 0, field, "not a shard number: " + value.dump().substr(0, 40));
    }
    p.spec.shard = p.json.at("shard").get<int>();
    p.spec.shards = p.json.at("shards").get<int>();
    const SweepGrid grid = SweepGridFromJson(p.json.at("grid"), path);
    const std::string fingerprint = p.json.at("fingerprint").get<std::string>();
    const std::string expected = Fnv1a64Hex(CanonicalGridText(grid) + "\nmavloc executable " +
                                            p.json.at("executable").get<std::string>());
    if (fingerprint != expected)
      throw InputError(path, 0, "fingerprint",
                       "fingerprint " + fingerprint + " does not match its own grid (" + expected +
                           "): the file was edited or damaged");
    if (p.spec.shards < 1 || p.spec.shard < 1 || p.spec.shard > p.spec.shards ||
        static_cast<size_t>(p.spec.shards) > std::max<size_t>(1, SweepUnitCount(grid)))
      throw InputError(path, 0, "shard",
                       fmt::format("bad shard {}/{}", p.spec.shard, p.spec.shards));
    const auto expected_units = ShardUnitIndices(SweepUnitCount(grid), p.spec);
    const auto& units = p.json.at("units");
    bool same = units.is_array() && units.size() == expected_units.size();
    for (size_t i = 0; same && i < units.size(); ++i)
      same = units[i].is_object() && units[i].contains("index") &&
             units[i]["index"].is_number_unsigned() &&
             units[i]["index"].get<size_t>() == expected_units[i];
    if (!same)
      throw InputError(
          path, 0, "units",
          fmt::format("incomplete partial: shard {}/{} must hold {} units, it holds {}",
                      p.spec.shard, p.spec.shards, expected_units.size(),
                      units.is_array() ? units.size() : 0));
    if (grid.repro.empty())
      for (size_t i = 0; i < units.size(); ++i) {
        CheckUnitResult(units[i], path, i);
        CheckUnitAgainstGrid(units[i], grid, path, i);
      }
  } catch (const nlohmann::json::exception& e) {
    throw InputError(path, 0, "", std::string("malformed partial: ") + e.what());
  }
  return p;
}

}  // namespace

ShardSpec ParseShardSpec(const std::string& text) {
  const std::regex pattern(R"(([0-9]{1,9})/([0-9]{1,9}))");
  std::smatch match;
  if (!std::regex_match(text, match, pattern))
    throw InputError("--shard '" + text + "': expected I/N (e.g. 3/10)");
  ShardSpec spec{std::stoi(match[1].str()), std::stoi(match[2].str())};
  if (spec.shards < 1 || spec.shard < 1 || spec.shard > spec.shards)
    throw InputError("--shard '" + text + "': expected 1 <= I <= N");
  return spec;
}

std::vector<size_t> ShardUnitIndices(size_t unit_count, const ShardSpec& spec) {
  std::vector<size_t> indices;
  for (size_t k = static_cast<size_t>(spec.shard - 1); k < unit_count;
       k += static_cast<size_t>(spec.shards))
    indices.push_back(k);
  return indices;
}

std::string PartialFileName(const ShardSpec& spec) {
  return fmt::format("partial-{}-of-{}.json", spec.shard, spec.shards);
}

std::string WritePartial(const std::string& folder, const SweepGrid& grid, const ShardSpec& spec,
                         const std::vector<nlohmann::json>& units) {
  std::error_code error;
  CreateOutputDirectories(folder, error);
  if (error)
    throw InputError(folder, 0, "", "cannot create the partial folder: " + error.message());
  nlohmann::json j;
  j["format"] = kFormat;
  j["grid"] = SweepGridToJson(grid);
  j["grid_hash"] = Fnv1a64Hex(CanonicalGridText(grid));
  j["executable"] = ExecutableHash();
  j["fingerprint"] = SweepFingerprint(grid);
  j["shard"] = spec.shard;
  j["shards"] = spec.shards;
  j["units"] = units;
  j["complete"] = true;
  const std::string path = (fs::path(folder) / PartialFileName(spec)).string();
  WriteFileAtomically(path, j.dump() + "\n");
  return path;
}

MergedSweep MergePartials(const std::vector<std::string>& inputs) {
  std::vector<std::string> files;
  std::vector<std::string> leftovers;       // temporary files of interrupted shards
  std::vector<SkippedFile> merged_skipped;  // other entries of the folders, with the reason
  for (const auto& input : inputs) {
    if (NotAFolder(input).empty()) {
      std::vector<std::string> found;
      for (const FolderEntry& entry : ListFolder(input)) {
        if (std::regex_match(entry.name, kPartialName)) {
          if (!entry.problem.empty()) throw InputError(entry.path, 0, "", entry.problem);
          found.push_back(entry.path);
        } else if (entry.name.rfind("partial-", 0) == 0 &&
                   entry.name.find(".json.tmp-") != std::string::npos) {
          leftovers.push_back(entry.path);
        } else {
          merged_skipped.push_back({entry.path, "not a partial file (partial-I-of-N.json)"});
        }
      }
      std::sort(found.begin(), found.end());
      if (found.empty())
        throw InputError(input, 0, "", "no partial files (partial-I-of-N.json) in this folder");
      files.insert(files.end(), found.begin(), found.end());
    } else if (fs::exists(input)) {
      files.push_back(input);
    } else {
      throw InputError(input, 0, "", "no such partial file or folder");
    }
  }
  if (files.empty()) throw InputError("sweep-merge: no partial files given");

  std::map<int, Partial> by_shard;
  std::string fingerprint, first_path;
  int shards = 0;
  for (const auto& path : files) {
    Partial p = ReadPartial(path);
    const std::string fp = p.json["fingerprint"].get<std::string>();
    if (first_path.empty()) {
      fingerprint = fp;
      shards = p.spec.shards;
      first_path = path;
    } else if (fp != fingerprint) {
      throw InputError(path, 0, "fingerprint",
                       "mismatched fingerprint " + fp + " (" + first_path + " has " + fingerprint +
                           "): a partial of a different grid or mavloc build");
    } else if (p.spec.shards != shards) {
      throw InputError(path, 0, "shards",
                       fmt::format("shard {}/{} but {} is of {} shards", p.spec.shard,
                                   p.spec.shards, first_path, shards));
    }
    const int shard = p.spec.shard;
    if (by_shard.count(shard))
      throw InputError(
          path, 0, "shard",
          fmt::format("duplicate shard {}/{} (also in {})", shard, shards, by_shard[shard].path));
    by_shard.emplace(shard, std::move(p));
  }
  std::vector<int> missing;
  for (int i = 1; i <= shards; ++i)
    if (!by_shard.count(i)) missing.push_back(i);
  if (!missing.empty()) {
    std::string message = fmt::format("sweep-merge: missing shard(s) {} of {} (have {})",
                                      fmt::join(missing, ", "), shards, by_shard.size());
    if (!leftovers.empty())
      message += "; interrupted shard files: " + fmt::format("{}", fmt::join(leftovers, ", "));
    throw InputError(message);
  }

  MergedSweep merged;
  merged.skipped = std::move(merged_skipped);
  merged.grid = SweepGridFromJson(by_shard.begin()->second.json["grid"], first_path);
  merged.fingerprint = fingerprint;
  const size_t count = SweepUnitCount(merged.grid);
  merged.units.resize(count);
  for (auto& [shard, partial] : by_shard)
    for (auto& unit : partial.json["units"]) {
      const size_t index = unit["index"].get<size_t>();
      merged.units[index] = std::move(unit);
    }
  return merged;
}

std::vector<bool> CompleteShards(const std::string& folder, int shards,
                                 const std::string& fingerprint) {
  std::vector<bool> complete(static_cast<size_t>(shards) + 1, false);
  for (int i = 1; i <= shards; ++i) {
    const std::string path = (fs::path(folder) / PartialFileName({i, shards})).string();
    if (!fs::exists(path)) continue;
    try {
      const Partial partial = ReadPartial(path);
      complete[static_cast<size_t>(i)] = partial.json["fingerprint"] == fingerprint &&
                                         partial.spec.shard == i && partial.spec.shards == shards;
    } catch (const InputError&) {
    }
  }
  return complete;
}

}  // namespace mavloc
