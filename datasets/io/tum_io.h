// TUM trajectory files: one pose per line, "timestamp tx ty tz qx qy qz qw", timestamp in seconds,
// '#' comments. Read by evo and the rpg tools, so mavloc's output can be compared with theirs.
// Files from other tools (repeated stamps, other formats) are read by ReadTrajectory
// (trajectory_formats/trajectory_format.h); these two functions are its strict TUM case.
#pragma once

#include <string>
#include <vector>

#include "core/pose.h"

namespace mavloc {

// ReadTrajectory with the format forced to TUM and repeated stamps refused: throws InputError
// (file:line, field) on malformed rows, NaN/inf, non-increasing timestamps or an empty file.
std::vector<StampedPose> ReadTumTrajectory(const std::string& path);
// The text of a TUM file (header comment, stamps with nanosecond precision).
std::string TumTrajectoryText(const std::vector<StampedPose>& poses);
// Atomic write (temporary file + rename) of TumTrajectoryText.
void WriteTumTrajectory(const std::vector<StampedPose>& poses, const std::string& path);

}  // namespace mavloc
