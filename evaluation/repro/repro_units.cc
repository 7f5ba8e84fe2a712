#include "evaluation/repro/repro_units.h"

#include "evaluation/sweep/sweep_grid.h"
#include "evaluation/sweep/sweep_runner.h"

namespace mavloc {

std::vector<nlohmann::json> RunReproUnitsInWorkers(const std::string& repro,
                                                   const ReproOptions& options,
                                                   const std::vector<std::string>& unit_names,
                                                   int runs, const std::vector<size_t>& indices) {
  SweepGrid grid;
  grid.scenarios = unit_names;
  for (int k = 0; k < runs; ++k) grid.seeds.push_back(options.seed + static_cast<uint64_t>(k));
  grid.repro = repro;
  grid.repro_settings = options.settings;
  SweepRunOptions run_options;
  run_options.jobs = options.jobs;
  run_options.worker_argv = options.worker_argv;
  return RunSweepUnits(grid, indices, run_options);
}

}  // namespace mavloc
