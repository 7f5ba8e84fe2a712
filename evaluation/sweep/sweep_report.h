// The Monte-Carlo report of a sweep, from the unit results (evaluation/sweep/sweep_unit.h) in unit
// order. The same function builds the report of a single-process run and of a merge of shards, so
// both are the same bytes:
//   runs.csv    one row per unit x estimator x metric (long format: unit, scenario, settings,
//               seed, estimator, ran, metric, unit, value; values in shortest round-trip text)
//   report.json {"sweep": {grid, fingerprint, units}, "cells": [...], "runs": [unit results]}
//   report.md   the grid, then per scenario and settings combination one table: estimator x
//               metric with n, mean, sample standard deviation, min, median, max over the seeds
// A cell is (scenario, settings combination, estimator); its statistics are over the seeds where
// the estimator ran (a metric missing in a run, e.g. NaN, is left out of that metric's n).
// No figures: the repro figure script (evaluation/report_figures.h) reads the reproductions'
// "tables" layout, not this one, and PNG bytes would break the byte-identical merge.
#pragma once

#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "evaluation/sweep/sweep_grid.h"

namespace mavloc {

// File name -> contents. `units` must hold every unit of the grid, ordered by index.
std::map<std::string, std::string> BuildSweepReport(const SweepGrid& grid,
                                                    const std::string& fingerprint,
                                                    const std::vector<nlohmann::json>& units);

// Creates the folder and writes every file atomically (core/atomic_file.h).
void WriteSweepReport(const std::string& folder, const std::map<std::string, std::string>& files);

}  // namespace mavloc
