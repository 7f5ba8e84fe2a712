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

#include "evaluation/sweep/sweep_grid.h"

namespace mavloc {

// Throws InputError for bad settings or options (as `compare` would).
nlohmann::json RunSweepUnit(const SweepGrid& grid, size_t index);

}  // namespace mavloc
