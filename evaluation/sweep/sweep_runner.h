// Runs units of a sweep on the local cores.
//
// jobs == 1 runs the units one after another in this process. jobs > 1 starts `jobs` long-lived
// worker processes (fork + exec of the mavloc executable): the estimators use Ceres thread pools
// and static state, so separate processes are the safe way to run them side by side, and starting
// each worker once (not once per unit) keeps the start-up cost out of the runs. The protocol, on a
// socket pair that is the worker's fd 3: the runner sends a unit index per line; the worker runs
// it, writes its JSON to <folder>/unit-K.json (atomically) and answers the same line; the runner
// then sends the next unit to whichever worker is free (so slow units do not hold up a static
// share), and closes the channel when none is left, which ends the worker. Results are returned by
// unit index, so parallel and serial runs give the same bytes (every result goes through the same
// JSON text either way).
//
// Progress: one line per finished unit on stderr ("[sweep] 12/40 runs done, 0:35 left"), silent
// with MAVLOC_QUIET (core/progress.h). Workers run with MAVLOC_QUIET=1.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "evaluation/sweep/sweep_grid.h"

namespace mavloc {

// The worker's end of its channel to the runner.
constexpr int kSweepWorkerChannelFd = 3;

struct SweepRunOptions {
  int jobs = 1;
  // Worker command: argv of an executable that, given "--serve FOLDER" appended, serves units on
  // fd 3 as described above (`mavloc sweep-worker --grid G`). Required when jobs > 1; "{grid}" in
  // an item is replaced by the grid file the runner writes.
  std::vector<std::string> worker_argv;
};

// Results of `indices` in the order given. A failing unit stops the run (remaining workers are
// terminated) and throws InputError with the worker's message.
std::vector<nlohmann::json> RunSweepUnits(const SweepGrid& grid, const std::vector<size_t>& indices,
                                          const SweepRunOptions& options);

// The number of cores available to this process (sched_getaffinity; at least 1).
int AvailableCores();

}  // namespace mavloc
