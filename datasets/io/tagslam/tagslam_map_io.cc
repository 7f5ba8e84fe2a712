#include "datasets/io/tagslam/tagslam_map_io.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>

#include "core/errors.h"
#include "core/physical_limits.h"
#include "core/rotation.h"
#include "datasets/io/tagslam/tagslam_yaml.h"
#include "datasets/io/yaml_util.h"

namespace mavloc {
namespace {

struct BodyContext {
  std::string name;
  bool is_static = false;
  std::optional<Pose> T_W_body;
  std::optional<double> default_tag_size_m;
};

void ReadBodyTags(const YAML::Node& tags, const BodyContext& body, const std::string& path,
                  TagslamMap* out) {
  if (!tags) return;
  if (!tags.IsSequence()) throw InputError(path, YamlLine(tags), body.name + ".tags", "not a list");
  for (const YAML::Node& tag : tags) {
    const std::string where = body.name + ".tags";
    if (!tag.IsMap()) throw InputError(path, YamlLine(tag), where, "entry is not a map");
    const int id = YamlInt(tag, "id", path);
    if (id < 0) throw InputError(path, YamlLine(tag["id"]), "id", "negative tag id");
    if (!out->listed_tags.insert(id).second)
      throw InputError(path, YamlLine(tag["id"]), "id", fmt::format("tag {} listed twice", id));
    double size_m = 0.0;
    if (tag["size"]) {
      size_m = YamlDouble(tag, "size", path);
      if (size_m > limits::kMaxTagSize_m)
        throw InputError(path, YamlLine(tag["size"]), "size",
                         fmt::format("tag {}: {:g} is outside {}", id, size_m,
                                     limits::RangeText(0.0, limits::kMaxTagSize_m, "m")));
    } else if (body.default_tag_size_m) {
      size_m = *body.default_tag_size_m;
    } else {
      throw InputError(
          path, YamlLine(tag), "size",
          fmt::format("tag {} has no size and body {} no default_tag_size", id, body.name));
    }
    if (!(size_m > 0.0))
      throw InputError(path, YamlLine(tag), "size", fmt::format("tag {}: must be > 0", id));
    const std::optional<Pose> T_body_tag =
        tag["pose"] ? std::optional<Pose>(ReadTagslamPose(tag, "pose", path)) : std::nullopt;
    if (out->ignored_tags.count(id)) continue;
    if (!body.is_static) {
      out->tags_on_dynamic_bodies.push_back(id);
      continue;
    }
    if (!T_body_tag) {
      out->tags_without_pose.push_back(id);
      continue;
    }
    if (!body.T_W_body) {
      out->tags_of_unposed_bodies.push_back(id);
      continue;
    }
    TagInfo info;
    info.id = id;
    info.size_m = size_m;
    info.T_W_T = *body.T_W_body * *T_body_tag;
    out->map.tags[id] = info;
  }
}

void ReadIdRemaps(const YAML::Node& remaps, const std::string& path, TagslamMap* out) {
  if (!remaps) return;
  if (!remaps.IsSequence()) throw InputError(path, YamlLine(remaps), "tag_id_remap", "not a list");
  for (const YAML::Node& entry : remaps) {
    const int detected = YamlInt(entry, "id", path);
    const YAML::Node list = entry["remaps"];
    if (!list || !list.IsSequence())
      throw InputError(path, YamlLine(entry), "remaps", "missing or not a list");
    for (const YAML::Node& remap : list) {
      TagslamIdRemap r;
      r.detected_id = detected;
      r.remap_id = YamlInt(remap, "remap_id", path);
      r.t_begin_ns = YamlRosTime(remap, "start_time", path);
      r.t_end_ns = YamlRosTime(remap, "end_time", path);
      if (r.t_end_ns < r.t_begin_ns)
        throw InputError(path, YamlLine(remap["end_time"]), "end_time", "before start_time");
      out->id_remaps.push_back(r);
    }
  }
}

}  // namespace

std::optional<TimeNs> ParseRosTimeText(const std::string& text) {
  const size_t dot = text.find('.');
  const std::string seconds = text.substr(0, dot);
  const std::string fraction = dot == std::string::npos ? "" : text.substr(dot + 1);
  auto digits = [](const std::string& s) {
    return std::all_of(s.begin(), s.end(), [](unsigned char c) { return std::isdigit(c); });
  };
  if (seconds.empty() || seconds.size() > 10 || !digits(seconds) || fraction.size() > 9 ||
      !digits(fraction))
    return std::nullopt;
  std::string ns = fraction;
  ns.resize(9, '0');
  return static_cast<TimeNs>(std::stoll(seconds)) * 1000000000LL + std::stoll(ns);
}

int RemapTagId(const std::vector<TagslamIdRemap>& remaps, int detected_id, TimeNs t_ns) {
  for (const TagslamIdRemap& r : remaps) {
    if (r.detected_id == detected_id && t_ns >= r.t_begin_ns && t_ns <= r.t_end_ns)
      return r.remap_id;
  }
  return detected_id;
}

TagslamMap ReadTagslamMap(const std::string& path) {
  const YAML::Node root = LoadYamlFile(path);
  if (!root.IsMap()) throw InputError(path, 0, "", "not a YAML map");
  TagslamMap out;
  out.map.frame = MapFrame::kWorld;
  if (root["default_body"]) out.default_body = YamlString(root, "default_body", path);
  const YAML::Node bodies = root["bodies"];
  if (!bodies) throw InputError(path, 0, "bodies", "missing");
  if (!bodies.IsSequence()) throw InputError(path, YamlLine(bodies), "bodies", "not a list");
  // Ignored ids first: TagSLAM drops their detections whichever body lists them.
  for (const YAML::Node& item : bodies) {
    if (!item.IsMap() || item.size() != 1)
      throw InputError(path, YamlLine(item), "bodies", "entry is not a single 'name: {...}' map");
    const YAML::Node body = item.begin()->second;
    if (!body.IsMap()) continue;
    for (int id : YamlInts(body, "ignore_tags", path)) out.ignored_tags.insert(id);
  }
  for (const YAML::Node& item : bodies) {
    BodyContext body;
    body.name = YamlKey(item.begin()->first, path, "bodies");
    const YAML::Node node = item.begin()->second;
    if (!node.IsMap()) throw InputError(path, YamlLine(item), body.name, "body is not a map");
    body.is_static = node["is_static"] && YamlBool(node, "is_static", path);
    if (node["default_tag_size"]) {
      body.default_tag_size_m = YamlDouble(node, "default_tag_size", path);
      if (!(*body.default_tag_size_m > 0.0 && *body.default_tag_size_m <= limits::kMaxTagSize_m))
        throw InputError(path, YamlLine(node["default_tag_size"]), "default_tag_size",
                         fmt::format("{:g} must be > 0 and within {}", *body.default_tag_size_m,
                                     limits::RangeText(0.0, limits::kMaxTagSize_m, "m")));
    }
    if (node["pose"]) body.T_W_body = ReadTagslamPose(node, "pose", path);
    (body.is_static ? out.static_bodies : out.dynamic_bodies).push_back(body.name);
    ReadBodyTags(node["tags"], body, path, &out);
    if (!body.is_static && node["odom_topic"]) {
      TagslamOdometry odometry;
      odometry.body = body.name;
      odometry.topic = YamlString(node, "odom_topic", path);
      if (node["odom_frame_id"]) odometry.frame_id = YamlString(node, "odom_frame_id", path);
      if (node["T_body_odom"]) {
        odometry.T_body_odom = ReadTagslamPose(node, "T_body_odom", path);
        odometry.has_T_body_odom = true;
      }
      out.odometry.push_back(odometry);
    }
  }
  ReadIdRemaps(root["tag_id_remap"], path, &out);
  return out;
}

}  // namespace mavloc
