#include "datasets/io/aprilgrid_target_io.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "core/errors.h"
#include "core/physical_limits.h"
#include "datasets/io/yaml_util.h"

namespace mavloc {

namespace {

// One key in either spelling (yac's snake_case first, then Kalibr's camelCase).
YAML::Node Key(const YAML::Node& node, const char* yac, const char* kalibr, std::string* used) {
  if (node[yac]) {
    *used = yac;
    return node[yac];
  }
  *used = kalibr;
  return node[kalibr];
}

int PositiveCount(const YAML::Node& node, const char* yac, const char* kalibr,
                  const std::string& path) {
  std::string used;
  const YAML::Node value = Key(node, yac, kalibr, &used);
  if (!value)
    throw InputError(path, node.Mark().line + 1, std::string(yac) + "' / '" + kalibr,
                     "missing from the aprilgrid description");
  const double x = YamlDouble(node, used, path);
  if (x != std::floor(x) || x < 1 || x > 10000)
    throw InputError(path, value.Mark().line + 1, used, "must be a positive integer count");
  return static_cast<int>(x);
}

double Number(const YAML::Node& node, const char* yac, const char* kalibr,
              const std::string& path) {
  std::string used;
  if (!Key(node, yac, kalibr, &used))
    throw InputError(path, node.Mark().line + 1, std::string(yac) + "' / '" + kalibr,
                     "missing from the aprilgrid description");
  return YamlDouble(node, used, path);
}

AprilgridTarget ParseTarget(const YAML::Node& node, const std::string& path) {
  if (const YAML::Node type = node["target_type"]) {
    const std::string name = type.IsScalar() ? type.Scalar() : "";
    if (name != "aprilgrid")
      throw InputError(path, type.Mark().line + 1, "target_type",
                       "'" + name + "' is not supported (only 'aprilgrid')");
  }
  AprilgridTarget target;
  target.tag_rows = PositiveCount(node, "tag_rows", "tagRows", path);
  target.tag_cols = PositiveCount(node, "tag_cols", "tagCols", path);
  target.tag_size_m = Number(node, "tag_size", "tagSize", path);
  target.tag_spacing = Number(node, "tag_spacing", "tagSpacing", path);
  // The upper bounds here, with the line of the value: the corner files are checked against the
  // target, so a target left unchecked is blamed on the first corner file instead.
  std::string used;
  const YAML::Node size = Key(node, "tag_size", "tagSize", &used);
  if (target.tag_size_m > limits::kMaxTagSize_m)
    throw InputError(
        path, YamlLine(size), used,
        fmt::format("tag_size must be a positive length in metres: {:g} is outside {}",
                    target.tag_size_m, limits::RangeText(0.0, limits::kMaxTagSize_m, "m")));
  const YAML::Node spacing = Key(node, "tag_spacing", "tagSpacing", &used);
  const double extent_m = std::max(target.tag_rows, target.tag_cols) * target.tag_size_m *
                          (1.0 + std::abs(target.tag_spacing));
  if (target.tag_size_m > 0.0 && !(extent_m <= limits::kMaxPosition_m))
    throw InputError(path, YamlLine(spacing), used,
                     fmt::format("{:g} makes the grid {:g} m wide, beyond {}", target.tag_spacing,
                                 extent_m, limits::RangeText(0.0, limits::kMaxPosition_m, "m")));
  const std::string why = target.Validate();
  if (!why.empty()) throw InputError(path, node.Mark().line + 1, "", "invalid aprilgrid: " + why);
  return target;
}

bool HasTarget(const YAML::Node& node) {
  return node.IsMap() && (node["tag_rows"] || node["tagRows"]);
}

constexpr const char* kKeyRows = "aprilgrid_tag_rows";
constexpr const char* kKeyCols = "aprilgrid_tag_cols";
constexpr const char* kKeySize = "aprilgrid_tag_size_m";
constexpr const char* kKeySpacing = "aprilgrid_tag_spacing";

}  // namespace

std::optional<AprilgridTarget> FindAprilgridTarget(const YAML::Node& root,
                                                   const std::string& path) {
  if (!root.IsMap()) return std::nullopt;
  if (HasTarget(root)) return ParseTarget(root, path);
  if (const YAML::Node nested = root["calib_target"]) {
    if (HasTarget(nested)) return ParseTarget(nested, path);
    // A calib_target that is not an aprilgrid (e.g. a checkerboard) is named, not ignored.
    if (nested.IsMap() && nested["target_type"]) return ParseTarget(nested, path);
  }
  return std::nullopt;
}

AprilgridTarget ReadAprilgridTarget(const std::string& path) {
  const auto target = FindAprilgridTarget(LoadYamlFile(path), path);
  if (!target)
    throw InputError(path, 0, "",
                     "no aprilgrid description (tagRows/tag_rows at the top level or under "
                     "calib_target)");
  return *target;
}

std::map<std::string, double> AprilgridMapParameters(const AprilgridTarget& target) {
  return {{kKeyRows, target.tag_rows},
          {kKeyCols, target.tag_cols},
          {kKeySize, target.tag_size_m},
          {kKeySpacing, target.tag_spacing}};
}

std::optional<AprilgridTarget> AprilgridFromMap(const WorldMap& map) {
  const auto& p = map.parameters;
  const char* keys[] = {kKeyRows, kKeyCols, kKeySize, kKeySpacing};
  int present = 0;
  for (const char* key : keys) present += p.count(key) ? 1 : 0;
  if (present == 0) return std::nullopt;
  for (const char* key : keys) {
    if (!p.count(key))
      throw InputError("map.yaml", 0, std::string("parameters.") + key,
                       "missing (the map names an aprilgrid only partly)");
  }
  AprilgridTarget target;
  target.tag_rows = static_cast<int>(p.at(kKeyRows));
  target.tag_cols = static_cast<int>(p.at(kKeyCols));
  target.tag_size_m = p.at(kKeySize);
  target.tag_spacing = p.at(kKeySpacing);
  const std::string why = target.Validate();
  if (!why.empty() || target.tag_rows != p.at(kKeyRows) || target.tag_cols != p.at(kKeyCols))
    throw InputError("map.yaml", 0, "parameters.aprilgrid_*",
                     "not a valid aprilgrid" + (why.empty() ? "" : ": " + why));
  return target;
}

}  // namespace mavloc
