// The one check of an estimator's options before any work, for every command that takes
// `--option` (run, compare, obstacles, sweep, the reproductions' estimator settings): the
// estimator is created once and dropped, so that the registry's keys, value ranges
// (solver/estimator_registry.cc OptionRanges: finite, in a stated range, the option named) and
// cross-checks (window_s against window_overlap_s) are made before a dataset is read.
#pragma once

#include "solver/estimator.h"

namespace mavloc {

// Throws InputError naming the option, its range and the estimator.
void CheckEstimatorOptionValues(const EstimatorEntry& entry, const EstimatorOptions& given);

}  // namespace mavloc
