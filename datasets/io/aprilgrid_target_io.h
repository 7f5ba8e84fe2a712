// Reading Kalibr's aprilgrid description (core/aprilgrid.h) from YAML, in the two spellings in use:
// - Kalibr's target.yaml (kalibr wiki "Calibration targets"): target_type: 'aprilgrid', tagRows,
//   tagCols, tagSize [m], tagSpacing [ratio of tagSize];
// - yac's (chutsu/yac) keys tag_rows, tag_cols, tag_size, tag_spacing, at the top level of a
//   target.yaml or under `calib_target:` of a calibration config.yaml.
// And the target kept in a map's parameters (map.yaml `parameters: aprilgrid_*`), so that a
// dataset imported from an aprilgrid log still says which grid its tags came from.
#pragma once

#include <yaml-cpp/yaml.h>

#include <map>
#include <optional>
#include <string>

#include "core/aprilgrid.h"
#include "core/dataset.h"

namespace mavloc {

// The aprilgrid described at the top level of `root` or under its `calib_target`; nullopt when
// neither holds a tag_rows/tagRows key. Throws InputError (path, line, field) for a missing or
// malformed key, a target_type other than aprilgrid, or an invalid target.
std::optional<AprilgridTarget> FindAprilgridTarget(const YAML::Node& root, const std::string& path);
// Same from a file; throws InputError when the file holds no aprilgrid description.
AprilgridTarget ReadAprilgridTarget(const std::string& path);

// map.yaml parameters aprilgrid_tag_rows, aprilgrid_tag_cols, aprilgrid_tag_size_m,
// aprilgrid_tag_spacing, and back (nullopt when the map has none of them; InputError naming the
// key when they are incomplete or invalid).
std::map<std::string, double> AprilgridMapParameters(const AprilgridTarget& target);
std::optional<AprilgridTarget> AprilgridFromMap(const WorldMap& map);

}  // namespace mavloc
