// The one Monte-Carlo runner of the reproductions: a reproduction names its units (configurations
// or scenarios) and how many seeds each runs; the runner owns the units x seeds loop, --jobs (the
// sweep machinery's worker processes), the progress lines and the JSON round trip that makes
// --jobs 1 and --jobs N give the same numbers.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "evaluation/repro/repro.h"

namespace mavloc {

// The grid unit_names x seeds options.seed .. options.seed + runs - 1; a unit's index is
// name index * runs + k. indices: the units to run, in the order they run and are returned (all
// of them when empty).
struct ReproUnitGrid {
  std::vector<std::string> unit_names;
  int runs = 1;
  std::vector<size_t> indices;
};

// One unit's result: JSON that holds whatever the reproduction's summary adds up (sums, not
// means, so that runs combine exactly).
using ReproUnitFunction = std::function<nlohmann::json(const std::string& unit, uint64_t seed)>;

// options.runs (or default_runs) after checking it and options.jobs are >= 1; throws InputError
// naming the option.
int ReproRunCount(const ReproOptions& options, int default_runs);

// Runs the grid's units: in options.jobs sweep workers (the reproduction `repro`'s registered
// unit function with options.settings) when jobs > 1, otherwise here with run_unit and one progress
// line per run. Every result is returned as parsed from its JSON text, in the order of the
// indices.
std::vector<nlohmann::json> RunReproUnits(const std::string& repro, const ReproOptions& options,
                                          const ReproUnitGrid& grid,
                                          const ReproUnitFunction& run_unit);

// The results of unit name `name_index` (all its runs, in seed order) from RunReproUnits' output
// for a grid whose indices were all units in order.
std::vector<nlohmann::json> UnitRuns(const std::vector<nlohmann::json>& results, size_t name_index,
                                     int runs);

}  // namespace mavloc
