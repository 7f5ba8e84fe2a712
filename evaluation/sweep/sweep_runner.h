// Runs units of a sweep on the local cores (issue 16, "All cores of one machine").
//
// jobs == 1 runs the units one after another in this process. jobs > 1 starts one worker process
// per unit (fork + exec of the mavloc executable, at most `jobs` at a time): the estimators use
// Ceres thread pools and static state, so separate processes are the safe way to run them side by
// side. Each worker writes its unit's JSON to a file in a private temporary folder; results are
// returned by unit index, so parallel and serial runs give the same bytes (every result goes
// through the same JSON text either way).
//
// Progress: one line per finished unit on stderr ("[sweep] 12/40 runs done, 0:35 left"), silent
// with MAVLOC_QUIET (core/progress.h). Workers run with MAVLOC_QUIET=1.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "evaluation/sweep/sweep_grid.h"

namespace mavloc {

struct SweepRunOptions {
  int jobs = 1;
  // Worker command without the unit: argv of an executable that, given "--unit K --out FILE"
  // appended, writes RunSweepUnit(grid, K) as JSON to FILE (`mavloc sweep-worker --grid G`).
  // Required when jobs > 1; "{grid}" in an item is replaced by the grid file the runner writes.
  std::vector<std::string> worker_argv;
};

// Results of `indices` in the order given. A failing unit stops the run (remaining workers are
// terminated) and throws InputError with the worker's message.
std::vector<nlohmann::json> RunSweepUnits(const SweepGrid& grid, const std::vector<size_t>& indices,
                                          const SweepRunOptions& options);

// The number of cores available to this process (sched_getaffinity; at least 1).
int AvailableCores();

}  // namespace mavloc
