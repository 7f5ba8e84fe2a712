#include "datasets/io/tagslam/tagslam_yaml.h"

#include <Eigen/Core>

#include "core/errors.h"
#include "core/rotation.h"
#include "datasets/io/tagslam/tagslam_map_io.h"
#include "datasets/io/yaml_util.h"

namespace mavloc {
namespace {

YAML::Node Required(const YAML::Node& node, const std::string& field, const std::string& path) {
  if (!node.IsMap()) throw InputError(path, YamlLine(node), field, "parent is not a map");
  const YAML::Node value = node[field];
  if (!value) throw InputError(path, YamlLine(node), field, "missing");
  return value;
}

Eigen::Vector3d ReadXyz(const YAML::Node& node, const std::string& field, const std::string& path) {
  const YAML::Node value = Required(node, field, path);
  if (!value.IsMap()) throw InputError(path, YamlLine(value), field, "not an {x, y, z} map");
  return {YamlDouble(value, "x", path), YamlDouble(value, "y", path), YamlDouble(value, "z", path)};
}

}  // namespace

int YamlInt(const YAML::Node& node, const std::string& field, const std::string& path) {
  const YAML::Node value = Required(node, field, path);
  try {
    return value.as<int>();
  } catch (const YAML::Exception&) {
    throw InputError(path, YamlLine(value), field, "not an integer");
  }
}

std::vector<int> YamlInts(const YAML::Node& node, const std::string& field,
                          const std::string& path) {
  const YAML::Node value = node[field];
  if (!value || value.IsNull()) return {};
  if (!value.IsSequence()) throw InputError(path, YamlLine(value), field, "not a list");
  std::vector<int> out;
  for (const YAML::Node& item : value) {
    try {
      out.push_back(item.as<int>());
    } catch (const YAML::Exception&) {
      throw InputError(path, YamlLine(item), field, "list holds a value that is not an integer");
    }
  }
  return out;
}

bool YamlBool(const YAML::Node& node, const std::string& field, const std::string& path) {
  const YAML::Node value = Required(node, field, path);
  try {
    return value.as<bool>();
  } catch (const YAML::Exception&) {
    throw InputError(path, YamlLine(value), field, "not true/false");
  }
}

TimeNs YamlRosTime(const YAML::Node& node, const std::string& field, const std::string& path) {
  const std::string text = YamlString(node, field, path);
  const std::optional<TimeNs> t_ns = ParseRosTimeText(text);
  if (!t_ns)
    throw InputError(path, YamlLine(node[field]), field,
                     "not a ROS time 'seconds.nanoseconds': '" + text + "'");
  return *t_ns;
}

Pose ReadTagslamPose(const YAML::Node& node, const std::string& field, const std::string& path) {
  const YAML::Node pose = Required(node, field, path);
  if (!pose.IsMap()) throw InputError(path, YamlLine(pose), field, "not a map");
  const Eigen::Vector3d position = ReadXyz(pose, "position", path);
  const Eigen::Vector3d rotation_vector = ReadXyz(pose, "rotation", path);
  return Pose(ExpSO3(rotation_vector), position);
}

}  // namespace mavloc
