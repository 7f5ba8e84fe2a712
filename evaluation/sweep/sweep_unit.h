// One unit of a sweep (evaluation/sweep/sweep_grid.h): simulate the unit's scenario in memory with
// its seed and settings, run every estimator of the grid on that dataset and evaluate it against
// the ground truth with RunAndEvaluate (evaluation/comparison.h, the engine of `mavloc compare`).
//
// The result is JSON holding only deterministic numbers (wall-clock runtimes are left out, so that
// a rerun, a parallel run and a merge of shards give the same bytes):
//   {"index": k, "scenario": ..., "seed": s, "settings": {...},
//    "estimators": [{"name": e, "ran": true, "metrics": {metric: value}, "units": {metric: unit}}
//                  | {"name": e, "ran": false, "skipped": reason}]}
// Metrics (NaN values are left out): ate_rmse (m), ate_rotation_rmse (deg) after the grid's
// alignment, <quantity>.mean_abs and <quantity>.rmse (angles in degrees, as report.json of
// `compare`), failures (frames without a solution).
#pragma once

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

#include "evaluation/sweep/sweep_grid.h"
#include "solver/estimator.h"

namespace mavloc {

// The options of `estimator` in a sweep: `compare`'s rule (cli/option_checks.h), "name:key=value"
// for one estimator, "key=value" for every estimator that has the option, the specific one
// winning; threads=1 unless given (the sweep's parallelism is across units).
EstimatorOptions SweepEstimatorOptions(const std::string& estimator,
                                       const std::vector<std::string>& items);

// Throws InputError for bad settings or options (as `compare` would).
nlohmann::json RunSweepUnit(const SweepGrid& grid, size_t index);

}  // namespace mavloc
