#include "evaluation/repro/repro_units.h"

#include <fmt/format.h>

#include <map>

#include "core/errors.h"
#include "core/progress.h"
#include "evaluation/sweep/sweep_grid.h"
#include "evaluation/sweep/sweep_runner.h"

namespace mavloc {

int ReproRunCount(const ReproOptions& options, int default_runs) {
  const int runs = options.runs.value_or(default_runs);
  if (runs < 1) throw InputError("", 0, "--runs", "must be >= 1");
  if (options.jobs < 1) throw InputError("", 0, "--jobs", "must be >= 1");
  return runs;
}

std::vector<nlohmann::json> RunReproUnits(const std::string& repro, const ReproOptions& options,
                                          const ReproUnitGrid& grid,
                                          const ReproUnitFunction& run_unit) {
  const auto runs = static_cast<size_t>(grid.runs);
  std::vector<size_t> indices = grid.indices;
  if (indices.empty()) {
    for (size_t i = 0; i < grid.unit_names.size() * runs; ++i) indices.push_back(i);
  }
  if (options.jobs > 1) {
    SweepGrid sweep;
    sweep.scenarios = grid.unit_names;
    for (size_t k = 0; k < runs; ++k) sweep.seeds.push_back(options.seed + k);
    sweep.repro = repro;
    sweep.repro_settings = options.settings;
    SweepRunOptions run_options;
    run_options.jobs = options.jobs;
    run_options.worker_argv = options.worker_argv;
    return RunSweepUnits(sweep, indices, run_options);
  }
  std::map<size_t, size_t> runs_of_name;  // for "run k/n" in the progress lines
  for (const size_t index : indices) ++runs_of_name[index / runs];
  std::vector<nlohmann::json> results;
  for (const size_t index : indices) {
    const std::string& unit = grid.unit_names.at(index / runs);
    const size_t k = index % runs;
    const uint64_t seed = options.seed + k;
    ReportProgress("repro " + repro, fmt::format("{} run {}/{} (seed {})", unit, k + 1,
                                                 runs_of_name[index / runs], seed));
    results.push_back(nlohmann::json::parse(run_unit(unit, seed).dump()));
  }
  return results;
}

std::vector<nlohmann::json> UnitRuns(const std::vector<nlohmann::json>& results, size_t name_index,
                                     int runs) {
  const auto first = static_cast<long>(name_index * static_cast<size_t>(runs));
  return {results.begin() + first, results.begin() + first + runs};
}

}  // namespace mavloc
