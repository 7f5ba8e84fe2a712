#include "solver/pose/tags_camera.h"

namespace mavloc {

const CameraSensor* TagsCamera(const Dataset& dataset, const std::string& camera_name) {
  if (camera_name.empty()) return dataset.cameras.empty() ? nullptr : &dataset.cameras.front();
  return dataset.Camera(camera_name);
}

std::string TagsCameraMissing(const Dataset& dataset, const std::string& camera_name) {
  if (TagsCamera(dataset, camera_name) != nullptr) return "";
  return "needs the calibration of " + (camera_name.empty() ? std::string("cam0") : camera_name);
}

}  // namespace mavloc
