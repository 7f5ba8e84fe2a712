// yaml-cpp helpers: loading files that start with OpenCV's "%YAML:1.0" line (EuRoC/Kimera), and
// typed field access whose errors name the file, the line and the field (a node of the
// wrong type is an InputError, never yaml-cpp's exception escaping as "internal error").
#pragma once

#include <yaml-cpp/yaml.h>

#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/pose.h"

namespace mavloc {

// Loads a YAML file, dropping a leading "%YAML:1.0" directive that yaml-cpp rejects and a UTF-8
// byte order mark. Throws InputError when the file is missing, is a folder or is not valid YAML
// (with the parser's line).
YAML::Node LoadYamlFile(const std::string& path);
// The same, for files whose top level must be a map of keys: an empty file gives an empty map; a
// scalar or a list at the top is an InputError.
YAML::Node LoadYamlMap(const std::string& path);

// 1-based line of a node for messages (0 when yaml-cpp has none).
long YamlLine(const YAML::Node& node);

// The child `field` of a map node, required to be a map / a list. `node` itself must be a map.
YAML::Node YamlMapField(const YAML::Node& node, const std::string& field, const std::string& path);
YAML::Node YamlListField(const YAML::Node& node, const std::string& field, const std::string& path);

// Scalar fields. Numbers must be finite; YamlDoubleIn also within [lo, hi] (the sanity ranges of
// core/physical_limits.h). Integers are written as integers ("3", not "3.0" or "1e3") within
// [lo, hi]: ids are never read through a double.
double YamlDouble(const YAML::Node& node, const std::string& field, const std::string& path);
double YamlDoubleIn(const YAML::Node& node, const std::string& field, const std::string& path,
                    double lo, double hi, const std::string& unit);
long long YamlInteger(const YAML::Node& node, const std::string& field, const std::string& path,
                      long long lo, long long hi);
std::string YamlString(const YAML::Node& node, const std::string& field, const std::string& path);
// The text of a map key; a key that is not a single value (YAML's `? [a, b]` or `? {a: 1}`
// complex keys) is refused with its line. `within` names the map for the message ("" = the top).
std::string YamlKey(const YAML::Node& key, const std::string& path, const std::string& within = "");
std::vector<double> YamlDoubles(const YAML::Node& node, const std::string& field,
                                const std::string& path, size_t expected_size = 0);
// A 4x4 transform written as {cols: 4, rows: 4, data: [16 values]} (EuRoC T_BS, yac, OpenCV), a
// flat list of 16, or 4 lists of 4 (Kalibr).
Eigen::Matrix4d YamlTransform(const YAML::Node& node, const std::string& field,
                              const std::string& path);
// YamlTransform checked to be rigid: last row (0, 0, 0, 1), R orthonormal with det +1 within
// limits::kRotationMatrixTolerance (then made exactly orthonormal), translation within
// limits::kMaxPosition_m. An all-zero or scaled matrix is refused.
Pose YamlRigidTransform(const YAML::Node& node, const std::string& field, const std::string& path);

}  // namespace mavloc
