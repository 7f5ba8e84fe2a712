// Typed access to TagSLAM's YAML files (tagslam.yaml, cameras.yaml, camera_poses.yaml), with
// errors naming the file, the line and the field (core/errors.h InputError); the generic typed
// helpers (YamlLine, YamlString, YamlDouble) are those of datasets/io/yaml_util.h.
#pragma once

#include <yaml-cpp/yaml.h>

#include <string>
#include <vector>

#include "core/pose.h"
#include "core/time.h"
#include "datasets/io/yaml_util.h"  // YamlLine, YamlString, YamlDouble

namespace mavloc {

int YamlInt(const YAML::Node& node, const std::string& field, const std::string& path);
// A list of integers; an absent field is an empty list.
std::vector<int> YamlInts(const YAML::Node& node, const std::string& field,
                          const std::string& path);
bool YamlBool(const YAML::Node& node, const std::string& field, const std::string& path);
// A ROS time "seconds.nanoseconds" (tag_id_remap start_time/end_time) -> ns, exactly.
TimeNs YamlRosTime(const YAML::Node& node, const std::string& field, const std::string& path);

// TagSLAM's pose {position: {x, y, z}, rotation: {x, y, z}} (src/yaml.cpp, make_transform):
// rotation is a rotation vector (axis * angle [rad]); the result maps child into parent
// coordinates. Noise entries (position_noise, rotation_noise, R) are ignored.
Pose ReadTagslamPose(const YAML::Node& node, const std::string& field, const std::string& path);

}  // namespace mavloc
