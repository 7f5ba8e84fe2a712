// TagSLAM's tagslam.yaml (berndpfrommer/tagslam: src/body.cpp, src/tag2.cpp, src/yaml.cpp; the
// test folders of berndpfrommer/tagslam_test) -> the known tag map of a mavloc dataset.
//
// The file lists bodies. A static body (`is_static: true`, e.g. the building) carries tags whose
// poses are known in the body; the body's own `pose` is T_world_body. A dynamic body (the camera
// rig, `is_static: false`) may name its odometry topic and T_body_odom. Every pose is
//   pose: {position: {x, y, z}, rotation: {x, y, z}}
// where `rotation` is a rotation vector (axis * angle in radians, TagSLAM's make_transform via
// Eigen::AngleAxis; mavloc's ExpSO3), and the transform maps the child's coordinates into the
// parent's: p_parent = R(rotation) p_child + position.
//
// TagSLAM's tag frame is mavloc's (core/tag_geometry.h): origin at the centre of the black square,
// z out of the tag, object corners (-s/2,-s/2), (s/2,-s/2), (s/2,s/2), (-s/2,s/2) in the order
// of the detector's image corners (TagSLAM tag2.cpp make_object_corners). `size` (or the body's
// default_tag_size) is the edge of the black square, mavloc's TagInfo::size_m. So a tag of a
// static body enters the map as T_W_T = T_world_body * T_body_tag.
//
// W is TagSLAM's world frame. Its gravity direction is not known in general (test 11's building
// happens to be z-up, test 21's house frame is arbitrary); the map is still written as
// MapFrame::kWorld: the tag estimators that need no IMU (tag-pnp) work in any fixed frame, and
// TagSLAM's reference trajectory is in this same W, so poses compare without alignment.
// MapFrame::kBoard would make every tag estimator estimate gravity from imu0, which these logs do
// not have.
//
// Not in the map (each counted): tags listed without a pose (TagSLAM estimates them; mavloc's tag
// estimators need known tags), tags on dynamic bodies, tags of static bodies without a pose, and
// every id of a body's `ignore_tags` (their detections are dropped too, as TagSLAM does).
#pragma once

#include <optional>
#include <set>
#include <string>
#include <vector>

#include "core/dataset.h"
#include "core/pose.h"
#include "core/time.h"

namespace mavloc {

// tag_id_remap: detections of `detected_id` stamped within [t_begin_ns, t_end_ns] are tag
// `remap_id` (the same printed tag moved to another place during the log).
struct TagslamIdRemap {
  int detected_id = 0;
  int remap_id = 0;
  TimeNs t_begin_ns = 0;
  TimeNs t_end_ns = 0;
};

// The odometry a dynamic body names: `odom_topic`, `odom_frame_id` (the child frame of the odom
// messages) and T_body_odom, the odometry frame's pose in the body (identity when absent).
struct TagslamOdometry {
  std::string body;
  std::string topic;
  std::string frame_id;
  Pose T_body_odom;
  bool has_T_body_odom = false;
};

struct TagslamMap {
  WorldMap map;  // frame kWorld (TagSLAM's world), the tags of static bodies with known poses
  std::string default_body;
  std::vector<std::string> static_bodies;
  std::vector<std::string> dynamic_bodies;
  std::set<int> listed_tags;                // every tag id the bodies list
  std::set<int> ignored_tags;               // union of every body's ignore_tags
  std::vector<int> tags_without_pose;       // listed (with a size) but with no pose
  std::vector<int> tags_on_dynamic_bodies;  // on a moving body: not part of the static map
  std::vector<int> tags_of_unposed_bodies;  // on a static body that has no pose
  std::vector<TagslamIdRemap> id_remaps;
  std::vector<TagslamOdometry> odometry;
};

// Reads and checks tagslam.yaml. InputError names the file, line and field (a missing id, size
// or position component, a non-number, a duplicate tag id, a non-positive size, an id remap with
// an end before its start).
TagslamMap ReadTagslamMap(const std::string& path);

// The id a detection of `detected_id` at t_ns stands for, after tag_id_remap.
int RemapTagId(const std::vector<TagslamIdRemap>& remaps, int detected_id, TimeNs t_ns);

// A ROS time written as "seconds.nanoseconds" (e.g. 1541686885.999522770) -> ns, exactly (no
// detour through double). nullopt when the text is not of that form.
std::optional<TimeNs> ParseRosTimeText(const std::string& text);

}  // namespace mavloc
