// The grid of a Monte-Carlo sweep (`mavloc sweep`): scenario(s) x `--set` value
// combinations x seeds, each combination one independent unit on which every listed estimator runs
// (on the same simulated dataset, as `mavloc compare` and the reproductions do).
//
// Unit order (the order of every report row): scenario (as listed) > settings combination
// (setting keys in alphabetical order, each key's values as listed, the last key fastest) > seed
// (as listed). Unit index k = ((scenario * combinations) + combination) * seeds + seed.
//
// The canonical description is the grid as JSON with sorted keys (seeds as SeedListText); its
// FNV-1a 64-bit hash together with the hash of the running mavloc executable is the fingerprint
// that partial results carry, so that partials of a different grid or of a different build are
// never merged.
#pragma once

#include <cstdint>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

namespace mavloc {

struct SweepGrid {
  std::vector<std::string> scenarios;
  std::vector<uint64_t> seeds;
  // Setting axes: key -> values (text, as `--set key=value` takes them), alphabetical by key.
  std::map<std::string, std::vector<std::string>> settings;
  std::vector<std::string> estimators;  // registry names, in report order
  // Estimator options: "estimator:key=value" or "key=value" (every estimator), as `compare`.
  std::vector<std::string> options;
  std::optional<double> duration_s;  // scenario default when unset
  std::string align = "none";        // ATE alignment (evaluation/alignment.h names)
  double max_dt_s = 0.02;            // association tolerance
  // A reproduction on the sweep machinery (`mavloc repro NAME --jobs N`): each unit is one
  // (scenario, seed) run of that reproduction (ReproEntry::unit, evaluation/repro/repro.h) with
  // its `--set` settings, instead of the estimators. Empty for `mavloc sweep`; written to the
  // grid's JSON only when set, so a sweep's grid text is unchanged.
  std::string repro;
  std::map<std::string, std::string> repro_settings;
};

// One unit of the grid.
struct SweepUnit {
  size_t index = 0;
  std::string scenario;
  std::map<std::string, std::string> settings;  // this unit's value per setting key
  uint64_t seed = 1;
};

// "1..100" (inclusive), "1,5,9", "3" or a mix "1..3,10"; throws InputError naming `flag`.
std::vector<uint64_t> ParseSeedList(const std::string& text, const std::string& flag);
// The shortest canonical text of a seed list: runs of 3 or more as "LO..HI", others listed
// ("1..100,205,207"); ParseSeedList reads it back.
std::string SeedListText(const std::vector<uint64_t>& seeds);
// A `--set` value list: "key=a,b,c", or a numeric range "key=LO..HI" (step 1) or
// "key=LO..HI:STEP"; range values carry the decimals of LO and STEP (0.1..0.3:0.1 -> 0.1, 0.2,
// 0.3).
std::pair<std::string, std::vector<std::string>> ParseSettingAxis(const std::string& item);

// Checks names (scenarios, estimators, alignment), non-empty axes and duplicates; throws
// InputError.
void ValidateSweepGrid(const SweepGrid& grid);

size_t SweepUnitCount(const SweepGrid& grid);
SweepUnit SweepUnitAt(const SweepGrid& grid, size_t index);
// The settings combination of a unit as "key=value; key=value" (empty when the grid has none).
std::string SettingsLabel(const std::map<std::string, std::string>& settings);

nlohmann::json SweepGridToJson(const SweepGrid& grid);
SweepGrid SweepGridFromJson(const nlohmann::json& json, const std::string& source);  // throws
std::string CanonicalGridText(const SweepGrid& grid);  // SweepGridToJson(grid).dump()

// FNV-1a 64 (Fowler-Noll-Vo) of bytes, as 16 lower-case hex digits.
std::string Fnv1a64Hex(const std::string& bytes);
// Hash of the running executable's bytes (/proc/self/exe); "unknown" when unreadable. Computed
// once per process.
std::string ExecutableHash();
// Fnv1a64Hex(canonical grid + executable hash).
std::string SweepFingerprint(const SweepGrid& grid);

}  // namespace mavloc
