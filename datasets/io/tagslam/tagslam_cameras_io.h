// TagSLAM's cameras.yaml and camera_poses.yaml (berndpfrommer/tagslam: src/camera2.cpp,
// src/camera_intrinsics2.cpp, src/yaml.cpp; the Kalibr camchain layout) -> mavloc camera sensors.
//
// cameras.yaml: per camera camN (N = 0..99, TagSLAM's order) `camera_model: pinhole`,
// `intrinsics: [fu, fv, cu, cv]`, `distortion_model`, `distortion_coeffs`,
// `resolution: [width, height]`, `rostopic` (images), `tagtopic` (the AprilTag detections),
// `rig_body`. Distortion models (core/camera_model.h):
//   - `equidistant` (Kalibr's equi, TagSLAM's Cal3FS2: theta = atan(r),
//     theta_d = theta (1 + k1 theta^2 + k2 theta^4 + k3 theta^6 + k4 theta^8), x_d = theta_d x / r;
//     identical to mavloc's kEquidistant) with 4 coefficients;
//   - `radtan` / `plumb_bob` (k1, k2, p1, p2[, k3]) -> kRadialTangential; mavloc's model has no k3,
//     so a camera with a non-zero fifth coefficient is unsupported (said why), not approximated.
// camera_poses.yaml: per camera `pose: {position, rotation}` (rotation vector) = T_rig_cam, the
// camera frame in the rig body (TagSLAM's convert_transforms.py inverts Kalibr's T_cn_cnm1 to get
// it; test 11's right camera sits at +0.20 m along the left camera's x), so CameraSensor::T_B_C
// with B = the rig body. A camera without an entry has no known pose: TagSLAM estimates it, mavloc
// cannot use it.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "core/camera_model.h"
#include "core/pose.h"

namespace mavloc {

struct TagslamCamera {
  std::string name;  // TagSLAM's camN
  std::string image_topic;
  std::string tag_topic;  // empty when cameras.yaml has none
  std::string rig_body;
  std::optional<CameraModel> model;  // nullopt: unsupported model (see unsupported)
  std::string unsupported;           // why there is no model
  std::optional<Pose> T_B_C;         // camera_poses.yaml; nullopt when the camera has no entry
};

// Reads both files (camera_poses_path may be empty: no poses). Cameras in TagSLAM's order.
// InputError names the file, line and field for a missing or malformed item.
std::vector<TagslamCamera> ReadTagslamCameras(const std::string& cameras_path,
                                              const std::string& camera_poses_path);

}  // namespace mavloc
