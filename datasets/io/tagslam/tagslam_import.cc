#include "datasets/io/tagslam/tagslam_import.h"

#include <fmt/format.h>

#include <algorithm>
#include <filesystem>

#include "core/errors.h"
#include "core/stamp_rate.h"
#include "datasets/io/rosbag/rosbag_reader.h"
#include "datasets/io/tagslam/tagslam_trajectories.h"
#include "datasets/io/tum_io.h"

namespace mavloc {
namespace {

namespace fs = std::filesystem;

// <test_dir>/<stem>.bag, else <test_dir>/<stem>.bag.bz2 (returned even when absent).
std::string BagInFolder(const std::string& test_dir, const std::string& stem) {
  const fs::path plain = fs::path(test_dir) / (stem + ".bag");
  if (fs::exists(plain)) return plain.string();
  return (fs::path(test_dir) / (stem + ".bag.bz2")).string();
}

// Keeps the first of repeated stamps and drops stamps that go back in time (TUM readers refuse
// both); returns how many were dropped.
long KeepIncreasing(std::vector<StampedPose>* poses) {
  std::vector<StampedPose> kept;
  kept.reserve(poses->size());
  for (const StampedPose& pose : *poses)
    if (kept.empty() || pose.t_ns > kept.back().t_ns) kept.push_back(pose);
  const long dropped = static_cast<long>(poses->size() - kept.size());
  *poses = std::move(kept);
  return dropped;
}

void AddTrajectory(const std::string& relative_path, const std::string& source,
                   const std::string& frame, std::vector<StampedPose> poses, TagslamImport* out) {
  TagslamTrajectoryFile file;
  file.relative_path = relative_path;
  file.source = source;
  file.frame = frame;
  file.dropped_repeated_stamps = KeepIncreasing(&poses);
  file.poses = std::move(poses);
  if (file.dropped_repeated_stamps > 0)
    out->notes.push_back(fmt::format("{}: {} repeated or decreasing stamps dropped", source,
                                     file.dropped_repeated_stamps));
  if (file.poses.empty()) {
    out->notes.push_back(source + ": no poses, not written");
    return;
  }
  out->trajectories.push_back(std::move(file));
}

// The reference bag asked for, or the folder's when present (empty when there is none).
std::string ReferenceBag(const TagslamImportOptions& options) {
  if (!options.reference_bag.empty()) {
    if (!fs::exists(options.reference_bag))
      throw InputError(options.reference_bag, 0, "", "file does not exist");
    return options.reference_bag;
  }
  const std::string in_folder = BagInFolder(options.test_dir, "reference");
  return fs::exists(in_folder) ? in_folder : "";
}

// T_rig_cam of the cameras camera_poses.yaml leaves out, from TagSLAM's /tf in the reference bag.
void CameraPosesFromReference(const std::string& reference_bag, TagslamImport* out) {
  for (TagslamCamera& camera : out->tagslam_cameras) {
    if (camera.T_B_C || !camera.model || camera.rig_body.empty()) continue;
    LogTopicSpec spec;
    spec.path = reference_bag;
    spec.topic = "/tf";
    spec.tf_parent = camera.rig_body;
    spec.tf_child = camera.name;
    const LogTrajectory tf = ReadRosbagTrajectory(spec);
    if (tf.states.empty()) continue;
    camera.T_B_C = tf.states.back().T_W_B;
    const Eigen::Vector3d& p = camera.T_B_C->p;
    out->notes.push_back(fmt::format(
        "{}: T_B_C from TagSLAM's optimised /tf {}->{} in {} (p = {:.4f}, {:.4f}, {:.4f} m): a "
        "comparison with TagSLAM's reference is not independent of TagSLAM for this camera",
        camera.name, camera.rig_body, camera.name, fs::path(reference_bag).filename().string(),
        p.x(), p.y(), p.z()));
  }
}

// The rig's trajectories: TagSLAM's reference and the logged odometry (tagslam_trajectories.h).
void ReadTrajectories(const TagslamImportOptions& options, const std::string& rig_body,
                      TagslamImport* out) {
  const std::string reference_bag = ReferenceBag(options);
  const std::string name = fs::path(reference_bag).filename().string();
  if (!reference_bag.empty()) {
    LogTopicSpec spec;
    spec.path = reference_bag;
    spec.topic = TagslamBodyTopic(rig_body);
    AddTrajectory("reference/tagslam_" + rig_body + ".txt", name + ":" + spec.topic,
                  "W (TagSLAM's world)", PosesOf(ReadRosbagTrajectory(spec)), out);
  } else {
    out->notes.push_back("no reference.bag[.bz2]: TagSLAM's trajectory not written");
  }
  for (const TagslamOdometry& odometry : out->map.odometry) {
    if (odometry.body != rig_body) continue;
    LogTopicSpec spec;
    spec.path = out->tags_bag;
    spec.topic = odometry.topic;
    const std::string source = fs::path(out->tags_bag).filename().string() + ":" + spec.topic;
    AddTrajectory("reference/odometry_" + rig_body + ".txt", source,
                  "O (the odometry's own frame), rig body = odometry body * T_body_odom^-1",
                  OdometryOfBody(ReadRosbagTrajectory(spec), odometry.T_body_odom), out);
  }
}

std::string UsableWhyNot(const TagslamCamera& camera) {
  if (!camera.model) return "unsupported model: " + camera.unsupported;
  if (!camera.T_B_C) return "no pose in camera_poses.yaml (TagSLAM estimates it)";
  if (camera.tag_topic.empty()) return "no tagtopic in cameras.yaml";
  return "";
}

std::string IdList(const std::vector<int>& ids) {
  std::string out;
  for (int id : ids) out += (out.empty() ? "" : ", ") + std::to_string(id);
  return "[" + out + "]";
}

}  // namespace

TagslamImport ImportTagslamTest(const TagslamImportOptions& options) {
  const fs::path dir(options.test_dir);
  if (!fs::is_directory(dir))
    throw InputError(options.test_dir, 0, "", "TagSLAM test folder does not exist");
  TagslamImport out;
  out.map = ReadTagslamMap((dir / "tagslam.yaml").string());
  const fs::path poses = dir / "camera_poses.yaml";
  out.tagslam_cameras =
      ReadTagslamCameras((dir / "cameras.yaml").string(), fs::exists(poses) ? poses.string() : "");
  out.tags_bag =
      options.tags_bag.empty() ? BagInFolder(options.test_dir, "tag_detections") : options.tags_bag;
  if (!fs::exists(out.tags_bag)) throw InputError(out.tags_bag, 0, "", "file does not exist");
  if (options.camera_poses_from_reference) {
    const std::string reference_bag = ReferenceBag(options);
    if (reference_bag.empty())
      throw InputError(options.test_dir, 0, "", "no reference.bag[.bz2] to take camera poses from");
    CameraPosesFromReference(reference_bag, &out);
  }

  // Which cameras.
  std::vector<const TagslamCamera*> chosen;
  auto find = [&](const std::string& name) -> const TagslamCamera* {
    for (const TagslamCamera& c : out.tagslam_cameras)
      if (c.name == name) return &c;
    return nullptr;
  };
  if (options.cameras.empty()) {
    for (const TagslamCamera& camera : out.tagslam_cameras) {
      const std::string why = UsableWhyNot(camera);
      if (!why.empty()) {
        out.notes.push_back(
            fmt::format("{} ({}) not imported: {}", camera.name, camera.tag_topic, why));
      } else if (chosen.size() == 2) {
        out.notes.push_back(fmt::format(
            "{} not imported: a dataset holds two tag streams (import it alone with --camera {})",
            camera.name, camera.name));
      } else {
        chosen.push_back(&camera);
      }
    }
    if (chosen.empty())
      throw InputError((dir / "cameras.yaml").string(), 0, "",
                       "no camera has a supported model, a pose and a tag topic");
  } else {
    if (options.cameras.size() > 2)
      throw InputError("", 0, "camera", "at most two cameras per dataset (tags0, tags1)");
    for (const std::string& name : options.cameras) {
      const TagslamCamera* camera = find(name);
      if (!camera)
        throw InputError((dir / "cameras.yaml").string(), 0, name, "no such camera in the file");
      const std::string why = UsableWhyNot(*camera);
      if (!why.empty()) throw InputError((dir / "cameras.yaml").string(), 0, name, why);
      if (std::find(chosen.begin(), chosen.end(), camera) != chosen.end())
        throw InputError("", 0, "camera", name + " asked twice");
      chosen.push_back(camera);
    }
  }

  for (const TagslamCamera* camera : chosen) {
    if (camera->rig_body != chosen.front()->rig_body)
      throw InputError((dir / "cameras.yaml").string(), 0, camera->name,
                       "rig_body '" + camera->rig_body + "' differs from " + chosen.front()->name +
                           "'s: one dataset holds one rig");
  }
  Dataset& d = out.dataset;
  d.name = dir.filename().empty() ? dir.parent_path().filename().string() : dir.filename().string();
  d.map = out.map.map;
  for (size_t index = 0; index < chosen.size(); ++index) {
    const TagslamCamera& source = *chosen[index];
    TagslamImportCamera report;
    report.dataset_name = "cam" + std::to_string(index);
    report.tagslam_name = source.name;
    report.tag_topic = source.tag_topic;
    std::vector<TagObservation> read =
        ReadRosbagTags(out.tags_bag, source.tag_topic, static_cast<int>(index));
    report.detections = static_cast<long>(read.size());
    std::vector<TagObservation> kept;
    kept.reserve(read.size());
    for (TagObservation& observation : read) {
      const int id = RemapTagId(out.map.id_remaps, observation.tag_id, observation.t_ns);
      if (id != observation.tag_id) ++report.remapped;
      observation.tag_id = id;
      if (out.map.ignored_tags.count(id)) {
        ++report.ignored;
        continue;
      }
      if (d.map.tags.count(id)) ++report.in_map;
      const bool inside =
          std::all_of(observation.corners_px.begin(), observation.corners_px.end(),
                      [&](const Eigen::Vector2d& uv) { return source.model->IsInside(uv); });
      if (!inside) ++report.outside_image;
      kept.push_back(observation);
    }
    // tags0/tags1 are time-ordered (estimators take a run of equal stamps as one frame); the bag
    // is in receive order, so sort by header stamp, keeping the detector's order within a frame.
    std::stable_sort(
        kept.begin(), kept.end(),
        [](const TagObservation& a, const TagObservation& b) { return a.t_ns < b.t_ns; });
    CameraSensor camera;
    camera.name = report.dataset_name;
    camera.T_B_C = *source.T_B_C;
    camera.model = *source.model;
    std::vector<TimeNs> stamps;
    for (const TagObservation& observation : kept)
      if (stamps.empty() || stamps.back() != observation.t_ns) stamps.push_back(observation.t_ns);
    for (TimeNs t : stamps) camera.frames.push_back({t, ""});
    camera.rate_hz = MedianRateHz(stamps);
    report.frames = static_cast<long>(stamps.size());
    if (report.outside_image > 0)
      out.notes.push_back(fmt::format(
          "{} ({}): {} detections have a corner outside the {}x{} image of cameras.yaml",
          report.dataset_name, source.name, report.outside_image, source.model->width(),
          source.model->height()));
    d.cameras.push_back(camera);
    (index == 0 ? d.tags : d.tags1) = std::move(kept);
    out.cameras.push_back(report);
  }
  const TagslamMap& m = out.map;
  if (!m.tags_without_pose.empty())
    out.notes.push_back(
        fmt::format("{} tags listed without a pose are not in the map (TagSLAM estimates them): {}",
                    m.tags_without_pose.size(), IdList(m.tags_without_pose)));
  if (!m.tags_on_dynamic_bodies.empty())
    out.notes.push_back(fmt::format("{} tags on moving bodies are not in the map: {}",
                                    m.tags_on_dynamic_bodies.size(),
                                    IdList(m.tags_on_dynamic_bodies)));
  if (!m.tags_of_unposed_bodies.empty())
    out.notes.push_back(
        fmt::format("{} tags of static bodies without a pose are not in the map: {}",
                    m.tags_of_unposed_bodies.size(), IdList(m.tags_of_unposed_bodies)));
  if (!m.ignored_tags.empty())
    out.notes.push_back(fmt::format(
        "{} ignored tag ids (ignore_tags) are dropped from the map and the detections: {}",
        m.ignored_tags.size(), IdList({m.ignored_tags.begin(), m.ignored_tags.end()})));
  out.notes.push_back("no IMU in the log: no imu0 folder; estimators that need one do not apply");
  const std::string& rig = chosen.front()->rig_body;
  if (rig.empty())
    out.notes.push_back("the cameras name no rig_body: no trajectory of it written");
  else if (options.trajectories)
    ReadTrajectories(options, rig, &out);
  return out;
}

std::map<std::string, std::string> TagslamImport::ExtraFiles() const {
  std::map<std::string, std::string> files{{"import.yaml", ImportYaml()}};
  for (const TagslamTrajectoryFile& file : trajectories)
    files[file.relative_path] = TumTrajectoryText(file.poses);
  return files;
}

std::string TagslamImport::ImportYaml() const {
  std::string y = "# how this dataset was imported (mavloc import-tagslam)\n";
  y += fmt::format("source: tagslam\ntags_bag: \"{}\"\n", tags_bag);
  y += "map_frame: world  # TagSLAM's world frame; its gravity direction is not known\n";
  y += fmt::format("map_tags: {}\n", map.map.tags.size());
  y += fmt::format("listed_tags: {}\n", map.listed_tags.size());
  y += fmt::format("tags_without_pose: {}\n", IdList(map.tags_without_pose));
  y += fmt::format("tags_on_moving_bodies: {}\n", IdList(map.tags_on_dynamic_bodies));
  y +=
      fmt::format("ignored_tags: {}\n", IdList({map.ignored_tags.begin(), map.ignored_tags.end()}));
  y += fmt::format("id_remaps: {}\n", map.id_remaps.size());
  y += "cameras:\n";
  for (const TagslamImportCamera& c : cameras) {
    y += fmt::format(
        "  {}:\n    tagslam_camera: {}\n    tag_topic: \"{}\"\n    detections: {}\n"
        "    frames: {}\n    detections_of_map_tags: {}\n    remapped: {}\n    ignored: {}\n"
        "    outside_image: {}\n",
        c.dataset_name, c.tagslam_name, c.tag_topic, c.detections, c.frames, c.in_map, c.remapped,
        c.ignored, c.outside_image);
  }
  y += "trajectories:  # TUM files beside the dataset, for comparisons\n";
  for (const TagslamTrajectoryFile& t : trajectories) {
    y += fmt::format(
        "  - {{file: {}, source: \"{}\", frame: \"{}\", poses: {}, dropped_repeated_stamps: "
        "{}}}\n",
        t.relative_path, t.source, t.frame, t.poses.size(), t.dropped_repeated_stamps);
  }
  y += "notes:\n";
  for (const std::string& note : notes) y += fmt::format("  - \"{}\"\n", note);
  return y;
}

}  // namespace mavloc
