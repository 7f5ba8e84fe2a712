// Importing one of TagSLAM's test folders (berndpfrommer/tagslam_test: tagslam.yaml,
// cameras.yaml, camera_poses.yaml, tag_detections.bag[.bz2]) into a mavloc ASL dataset whose tag
// estimators (tag-pnp) run on it.
//
// The dataset: cam0 (and cam1) = the chosen TagSLAM cameras in the order asked, with their model
// and T_B_C (B = TagSLAM's rig body; tagslam_cameras_io.h), frames = the distinct stamps of the
// camera's detections (no images); tags0 (tags1) = the detections of the camera's `tagtopic`
// (datasets/io/rosbag/rosbag_reader.h ReadRosbagTags: header.stamp, mavloc's corner order), with
// tag_id_remap applied and every ignored id dropped; map.yaml = the known tags of
// tagslam_map_io.h (frame: world, TagSLAM's world). There is no IMU in these logs: the dataset has
// no imu0 folder (no samples are faked), so only the estimators that need no IMU apply.
//
// Besides the dataset, the import keeps the folder's trajectories of the rig body as TUM files
// (tagslam_trajectories.h): reference/tagslam_<body>.txt, TagSLAM's optimised T_W_B from
// reference.bag[.bz2], and reference/odometry_<body>.txt, the logged odometry (the rig's odom_topic
// in the detections bag) converted to the body with T_body_odom, in its own odometry frame.
//
// Only cameras with a supported model (equidistant, radtan without k3) and a pose in
// camera_poses.yaml can be imported; by default the first two such cameras that have a tag topic.
// mavloc's tag estimators use tags0 with cameras[0]: to run one per TagSLAM camera, import once per
// camera (`cameras = {"cam1"}` puts TagSLAM's cam1 into the dataset's cam0, said in import.yaml).
#pragma once

#include <map>
#include <string>
#include <vector>

#include "core/dataset.h"
#include "datasets/io/tagslam/tagslam_cameras_io.h"
#include "datasets/io/tagslam/tagslam_map_io.h"

namespace mavloc {

struct TagslamImportOptions {
  std::string test_dir;
  // The detections bag; empty: <test_dir>/tag_detections.bag, else
  // <test_dir>/tag_detections.bag.bz2.
  std::string tags_bag;
  // TagSLAM camera names (camN) to import, in dataset order (at most 2: tags0, tags1); empty: the
  // default above.
  std::vector<std::string> cameras;
  // TagSLAM's output bag; empty: <test_dir>/reference.bag[.bz2] when present (else none).
  std::string reference_bag;
  bool trajectories = true;  // false: neither reference/ file is written
  // Cameras without a pose in camera_poses.yaml take TagSLAM's optimised T_rig_cam from the
  // reference bag's /tf (parent = the rig body, child = camN). A comparison with that reference
  // is then not independent of TagSLAM for these cameras (the import notes it).
  bool camera_poses_from_reference = false;
};

// A trajectory kept beside the dataset (TUM file, path relative to the dataset root).
struct TagslamTrajectoryFile {
  std::string relative_path;  // "reference/tagslam_rig.txt"
  std::string source;         // "reference.bag.bz2:/tagslam/odom/body_rig"
  std::string frame;          // "W (TagSLAM's world)" or "O (the odometry's own frame)"
  std::vector<StampedPose> poses;
  long dropped_repeated_stamps = 0;
};

struct TagslamImportCamera {
  std::string dataset_name;  // cam0 / cam1 in the dataset
  std::string tagslam_name;  // camN in cameras.yaml
  std::string tag_topic;
  long detections = 0;     // observations read from the topic
  long frames = 0;         // distinct stamps
  long in_map = 0;         // observations of a tag of the map
  long remapped = 0;       // observations whose id tag_id_remap changed
  long ignored = 0;        // observations of ignored ids (dropped)
  long outside_image = 0;  // observations with a corner outside the stated resolution
};

struct TagslamImport {
  Dataset dataset;
  TagslamMap map;
  std::vector<TagslamCamera> tagslam_cameras;  // every camera of cameras.yaml
  std::vector<TagslamImportCamera> cameras;    // the imported ones, in dataset order
  std::string tags_bag;
  std::vector<TagslamTrajectoryFile> trajectories;
  std::vector<std::string> notes;  // what was left out and why, one line each

  // import.yaml: sources, camera mapping, counts, what is not in the map.
  std::string ImportYaml() const;
  // Every file written beside the dataset's own: import.yaml and the trajectories (TUM text).
  std::map<std::string, std::string> ExtraFiles() const;
};

// Reads and checks everything (InputError naming the file, line/message index and field); writes
// nothing.
TagslamImport ImportTagslamTest(const TagslamImportOptions& options);

}  // namespace mavloc
