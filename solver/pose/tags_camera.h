// The camera whose pixels the tags0 corners are in: Dataset::cameras[0] (core/dataset.h:
// TagObservation::camera = 0 is cameras[0], whatever its name; a real EuRoC cam0 has a non-trivial
// T_B_C and radial-tangential distortion, which every tag estimator takes from here).
#pragma once

#include <string>

#include "core/dataset.h"

namespace mavloc {

// cameras[0] when camera_name is empty, else the camera of that name; nullptr when absent.
const CameraSensor* TagsCamera(const Dataset& dataset, const std::string& camera_name = "");

// "needs the calibration of cam0" style reason, or empty when TagsCamera finds the camera.
std::string TagsCameraMissing(const Dataset& dataset, const std::string& camera_name = "");

}  // namespace mavloc
