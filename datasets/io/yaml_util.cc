#include "datasets/io/yaml_util.h"

#include <fmt/format.h>
#include <yaml-cpp/depthguard.h>

#include <Eigen/Geometry>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string_view>

#include "core/errors.h"
#include "core/input_file.h"
#include "core/input_limits.h"
#include "core/number_text.h"
#include "core/physical_limits.h"

namespace mavloc {

namespace {

const char* KindName(const YAML::Node& node) {
  switch (node.Type()) {
    case YAML::NodeType::Map:
      return "a map";
    case YAML::NodeType::Sequence:
      return "a list";
    case YAML::NodeType::Scalar:
      return "a scalar";
    case YAML::NodeType::Null:
      return "empty";
    default:
      return "undefined";
  }
}

// The node of `field` in the map `node`; throws when `node` is not a map or the field is missing.
YAML::Node Field(const YAML::Node& node, const std::string& field, const std::string& path) {
  if (!node.IsMap())
    throw InputError(path, YamlLine(node), field,
                     std::string("expected a map holding this field, found ") + KindName(node));
  const YAML::Node value = node[field];
  if (!value) throw InputError(path, YamlLine(node), field, "missing");
  return value;
}

YAML::Node Scalar(const YAML::Node& node, const std::string& field, const std::string& path) {
  const YAML::Node value = Field(node, field, path);
  if (!value.IsScalar())
    throw InputError(path, YamlLine(value), field,
                     std::string("expected a single value, found ") + KindName(value));
  return value;
}

// A YAML scalar as a number: YAML's own spellings of infinity and NaN (".inf", "-.Inf", ".nan",
// ...) are not finite; everything else is read whole by the strict parser (core/number_text.h).
ParsedNumber<double> ParseYamlNumber(const std::string& text) {
  std::string_view body = text;
  if (!body.empty() && (body.front() == '+' || body.front() == '-')) body.remove_prefix(1);
  for (const char* special : {".inf", ".Inf", ".INF", ".nan", ".NaN", ".NAN"})
    if (body == special) return {0.0, NumberTextStatus::kNotFinite};
  return ParseDoubleText(text);
}

}  // namespace

namespace {

std::string TooDeep() {
  return fmt::format("YAML nests deeper than {} levels (limit input_limits::kMaxYamlNesting)",
                     input_limits::kMaxYamlNesting);
}

// Refuses a document nested deeper than input_limits::kMaxYamlNesting or with more than
// kMaxYamlNodes nodes, counting a node once per alias that repeats it: yaml-cpp shares an aliased
// node, so a few lines of aliases of aliases describe billions of nodes for a reader that walks
// them. The walk stops at the first node beyond a limit.
void CheckYamlShape(const YAML::Node& node, const std::string& path, int depth, uint64_t* nodes) {
  if (++*nodes > input_limits::kMaxYamlNodes) {
    throw InputError(path, YamlLine(node), "",
                     fmt::format("YAML document has more than {} nodes, counting each repetition "
                                 "by an alias (limit input_limits::kMaxYamlNodes)",
                                 input_limits::kMaxYamlNodes));
  }
  if (depth > input_limits::kMaxYamlNesting) throw InputError(path, YamlLine(node), "", TooDeep());
  if (node.IsSequence()) {
    for (const YAML::Node& child : node) CheckYamlShape(child, path, depth + 1, nodes);
  } else if (node.IsMap()) {
    for (const auto& item : node) {
      CheckYamlShape(item.first, path, depth + 1, nodes);
      CheckYamlShape(item.second, path, depth + 1, nodes);
    }
  }
}

}  // namespace

long YamlLine(const YAML::Node& node) {
  if (!node.IsDefined()) return 0;
  const int line = node.Mark().line;
  return line >= 0 ? line + 1 : 0;
}

YAML::Node LoadYamlFile(const std::string& path) {
  std::istringstream in(ReadRegularFile(path));  // a pipe, a device, a loop: refused
  std::stringstream text;
  std::string line;
  bool first = true;
  while (std::getline(in, line)) {
    if (first && line.rfind("\xEF\xBB\xBF", 0) == 0) line.erase(0, 3);  // UTF-8 BOM
    // OpenCV writes "%YAML:1.0", which is not a valid YAML directive; keep line numbers intact.
    if (first && line.rfind("%YAML", 0) == 0) line = "";
    first = false;
    text << line << '\n';
  }
  if (in.bad()) throw InputError(path, 0, "", "cannot read file");
  YAML::Node root;
  try {
    root = YAML::Load(text.str());
  } catch (const YAML::DeepRecursion& e) {  // yaml-cpp's own depth guard ("bad file")
    throw InputError(path, e.mark.line + 1, "", TooDeep());
  } catch (const YAML::Exception& e) {
    throw InputError(path, e.mark.line + 1, "", "invalid YAML: " + e.msg);
  }
  uint64_t nodes = 0;
  CheckYamlShape(root, path, 0, &nodes);
  return root;
}

YAML::Node LoadYamlMap(const std::string& path) {
  YAML::Node root = LoadYamlFile(path);
  if (root.IsNull()) return YAML::Node(YAML::NodeType::Map);
  if (!root.IsMap())
    throw InputError(path, YamlLine(root), "",
                     std::string("expected a map of keys at the top, found ") + KindName(root));
  for (const auto& item : root) {
    if (!item.first.IsScalar())
      throw InputError(path, YamlLine(item.first), "",
                       std::string("a key must be a single value, found ") + KindName(item.first));
  }
  return root;
}

YAML::Node YamlMapField(const YAML::Node& node, const std::string& field, const std::string& path) {
  const YAML::Node value = Field(node, field, path);
  if (!value.IsMap())
    throw InputError(path, YamlLine(value), field,
                     std::string("expected a map, found ") + KindName(value));
  return value;
}

YAML::Node YamlListField(const YAML::Node& node, const std::string& field,
                         const std::string& path) {
  const YAML::Node value = Field(node, field, path);
  if (!value.IsSequence())
    throw InputError(path, YamlLine(value), field,
                     std::string("expected a list, found ") + KindName(value));
  return value;
}

double YamlDouble(const YAML::Node& node, const std::string& field, const std::string& path) {
  const YAML::Node value = Scalar(node, field, path);
  const ParsedNumber<double> x = ParseYamlNumber(value.Scalar());
  if (!x.ok())
    throw InputError(path, YamlLine(value), field, DescribeNumberText(value.Scalar(), x));
  return x.value;
}

double YamlDoubleIn(const YAML::Node& node, const std::string& field, const std::string& path,
                    double lo, double hi, const std::string& unit) {
  const double x = YamlDouble(node, field, path);
  if (!(x >= lo && x <= hi))
    throw InputError(path, YamlLine(node[field]), field,
                     fmt::format("{:g} is outside {}", x, limits::RangeText(lo, hi, unit)));
  return x;
}

long long YamlInteger(const YAML::Node& node, const std::string& field, const std::string& path,
                      long long lo, long long hi) {
  const YAML::Node value = Scalar(node, field, path);
  const long long x = RequireIntegerText(value.Scalar(), path, YamlLine(value), field);
  if (x < lo || x > hi)
    throw InputError(path, YamlLine(value), field,
                     fmt::format("{} is outside [{}, {}]", x, lo, hi));
  return x;
}

std::string YamlString(const YAML::Node& node, const std::string& field, const std::string& path) {
  return Scalar(node, field, path).Scalar();
}

std::string YamlKey(const YAML::Node& key, const std::string& path, const std::string& within) {
  if (!key.IsScalar())
    throw InputError(path, YamlLine(key), within,
                     std::string("a key must be a single value, found ") + KindName(key));
  return key.Scalar();
}

std::vector<double> YamlDoubles(const YAML::Node& node, const std::string& field,
                                const std::string& path, size_t expected_size) {
  const YAML::Node value = YamlListField(node, field, path);
  std::vector<double> out;
  for (const auto& item : value) {
    if (!item.IsScalar())
      throw InputError(path, YamlLine(item), field,
                       std::string("list holds ") + KindName(item) + ", not a number");
    const ParsedNumber<double> x = ParseYamlNumber(item.Scalar());
    if (!x.ok())
      throw InputError(path, YamlLine(item), field,
                       "list item " + DescribeNumberText(item.Scalar(), x));
    out.push_back(x.value);
  }
  if (expected_size > 0 && out.size() != expected_size) {
    throw InputError(path, YamlLine(value), field,
                     "expected " + std::to_string(expected_size) + " values, found " +
                         std::to_string(out.size()));
  }
  return out;
}

Eigen::Matrix4d YamlTransform(const YAML::Node& node, const std::string& field,
                              const std::string& path) {
  const YAML::Node value = Field(node, field, path);
  Eigen::Matrix4d T;
  if (value.IsSequence() && value.size() == 4 && value[0].IsSequence()) {  // Kalibr: 4 rows
    for (size_t r = 0; r < 4; ++r) {
      const YAML::Node row = value[r];
      if (!row.IsSequence() || row.size() != 4)
        throw InputError(path, YamlLine(value), field, "expected 4 rows of 4 numbers");
      YAML::Node holder(YAML::NodeType::Map);
      holder["row"] = row;
      const std::vector<double> values = YamlDoubles(holder, "row", path, 4);
      for (int c = 0; c < 4; ++c) T(static_cast<int>(r), c) = values[c];
    }
    return T;
  }
  const std::vector<double> data =
      value.IsMap() ? YamlDoubles(value, "data", path, 16) : YamlDoubles(node, field, path, 16);
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) T(r, c) = data[4 * r + c];
  return T;
}

Pose YamlRigidTransform(const YAML::Node& node, const std::string& field, const std::string& path) {
  const Eigen::Matrix4d T = YamlTransform(node, field, path);
  const long line = YamlLine(node[field]);
  if ((T.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).cwiseAbs().maxCoeff() > 1e-9)
    throw InputError(path, line, field, "not a rigid transform: last row is not (0, 0, 0, 1)");
  const Eigen::Matrix3d R = T.topLeftCorner<3, 3>();
  const double orthonormality_error =
      (R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  if (!(orthonormality_error <= limits::kRotationMatrixTolerance) || !(R.determinant() > 0.0))
    throw InputError(
        path, line, field,
        fmt::format("not a rigid transform: the rotation part has max |R^T R - I| "
                    "= {:.3g} and det = {:.3g} (tolerance {})",
                    orthonormality_error, R.determinant(), limits::kRotationMatrixTolerance));
  const Eigen::Vector3d t = T.topRightCorner<3, 1>();
  if (!(t.cwiseAbs().maxCoeff() <= limits::kMaxPosition_m))
    throw InputError(
        path, line, field,
        fmt::format("translation {:g} m is outside {}", t.cwiseAbs().maxCoeff(),
                    limits::RangeText(-limits::kMaxPosition_m, limits::kMaxPosition_m, "m")));
  // Nearest rotation of a matrix printed with few decimals: the normalised quaternion.
  return Pose(Eigen::Quaterniond(R).normalized(), t);
}

}  // namespace mavloc
