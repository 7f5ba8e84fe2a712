// Checks that a dataset's ground truth can judge its estimators: a ground truth that does not
// overlap the data, or one with a single row, is refused instead of giving an empty table or a
// meaningless evaluation.
#pragma once

#include <string>

#include "core/dataset.h"

namespace mavloc {

// The file the ground truth of a dataset was read from (for messages), or "ground truth" for an
// in-memory simulation.
std::string GroundTruthSource(const Dataset& dataset);

// Throws InputError naming the ground-truth file when it has fewer than 2 rows, or when its time
// span does not overlap the span of the sensor streams (imu0, cameras, features0, laser0, tags).
// A dataset without ground truth passes (there is nothing to judge with; callers say so).
void RequireUsableGroundTruth(const Dataset& dataset);

}  // namespace mavloc
