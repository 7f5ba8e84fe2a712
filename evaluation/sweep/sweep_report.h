// The Monte-Carlo report of a sweep, from the unit results (evaluation/sweep/sweep_unit.h) in unit
// order. The same function builds the report of a single-process run and of a merge of shards, so
// both are the same bytes:
//   runs.csv    one row per unit x estimator x metric (long format: unit, scenario, settings,
//               seed, estimator, ran, metric, unit, value; values in shortest round-trip text)
//   report.json the one report schema (evaluation/report/report.h): provenance (seeds, runs, the
//               grid's fingerprint), protocol (alignment, tolerance), one table per scenario,
//               settings combination and unit (a row per estimator and metric: n, mean, sample
//               standard deviation, min, median, max over the seeds), and details {"sweep": {grid,
//               fingerprint, units}, "cells": [...], "runs": [unit results]}; values in SI
//   report.md   the grid, then those tables (angles in degrees); an estimator that did not run in
//               some seeds is a warning, and so is a short cell: a metric with fewer values than
//               the runs where the estimator ran (a unit without it)
// A cell is (scenario, settings combination, estimator); its statistics are over the seeds where
// the estimator ran (a metric missing in a run, e.g. NaN, is left out of that metric's n).
// Figures are drawn afterwards from the folder (`mavloc figures`), outside the merged bytes.
#pragma once

#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "evaluation/sweep/sweep_grid.h"

namespace mavloc {

// File name -> contents. `units` must hold every unit of the grid, ordered by index.
// `warnings` (optional) receives the report's warnings, for the terminal.
std::map<std::string, std::string> BuildSweepReport(const SweepGrid& grid,
                                                    const std::string& fingerprint,
                                                    const std::vector<nlohmann::json>& units,
                                                    std::vector<std::string>* warnings = nullptr);

// Creates the folder and writes every file atomically (core/atomic_file.h).
void WriteSweepReport(const std::string& folder, const std::map<std::string, std::string>& files);

}  // namespace mavloc
