#include "datasets/io/tagslam/tagslam_cameras_io.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "core/errors.h"
#include "core/physical_limits.h"
#include "datasets/io/calibration_io.h"
#include "datasets/io/tagslam/tagslam_yaml.h"
#include "datasets/io/yaml_util.h"

namespace mavloc {
namespace {

// The model of one camera, or nullopt with *why when mavloc's models cannot represent it.
std::optional<CameraModel> ReadModel(const YAML::Node& camera, const std::string& path,
                                     std::string* why) {
  const std::string projection =
      camera["camera_model"] ? YamlString(camera, "camera_model", path) : "pinhole";
  const std::vector<double> intrinsics = YamlDoubles(camera, "intrinsics", path, 4);
  const std::vector<double> resolution = YamlDoubles(camera, "resolution", path, 2);
  const std::string name = YamlString(camera, "distortion_model", path);
  const std::vector<double> k = YamlDoubles(camera, "distortion_coeffs", path);
  const long line = YamlLine(camera["distortion_coeffs"]);
  // Checked before the cast to int (fuzz_tagslam_cameras found 8.3e15 cast unchecked).
  if (resolution[0] < 1 || resolution[1] < 1 || resolution[0] != std::floor(resolution[0]) ||
      resolution[1] != std::floor(resolution[1]) || resolution[0] > limits::kMaxResolution_px ||
      resolution[1] > limits::kMaxResolution_px)
    throw InputError(path, YamlLine(camera["resolution"]), "resolution",
                     fmt::format("expected two integers in [1, {}]", limits::kMaxResolution_px));
  CheckIntrinsicsRange(camera, "intrinsics", "intrinsics", path, intrinsics);
  CheckDistortionRange(camera, "distortion_coeffs", "distortion_coeffs", path, k);
  if (projection != "pinhole") {
    *why = "camera_model '" + projection + "' (mavloc has pinhole only)";
    return std::nullopt;
  }
  DistortionModel model = DistortionModel::kNone;
  if (name == "equidistant" || name == "equi" || name == "fisheye") {
    if (k.size() != 4)
      throw InputError(path, line, "distortion_coeffs",
                       fmt::format("equidistant needs 4 coefficients, found {}", k.size()));
    model = DistortionModel::kEquidistant;
  } else if (name == "radtan" || name == "plumb_bob" || name == "radial-tangential") {
    if (k.size() != 4 && k.size() != 5)
      throw InputError(path, line, "distortion_coeffs",
                       fmt::format("{} needs 4 or 5 coefficients, found {}", name, k.size()));
    if (k.size() == 5 && k[4] != 0.0) {
      *why = fmt::format(
          "{} with k3 = {} (mavloc's radial-tangential model has k1, k2, p1, p2 only)", name, k[4]);
      return std::nullopt;
    }
    model = DistortionModel::kRadialTangential;
  } else if (name == "none") {
    model = DistortionModel::kNone;
  } else {
    *why = "distortion_model '" + name + "' (mavloc has equidistant and radtan)";
    return std::nullopt;
  }
  return CameraModel(static_cast<int>(resolution[0]), static_cast<int>(resolution[1]),
                     Eigen::Vector4d(intrinsics[0], intrinsics[1], intrinsics[2], intrinsics[3]),
                     model, {k[0], k[1], k[2], k[3]});
}

}  // namespace

std::vector<TagslamCamera> ReadTagslamCameras(const std::string& cameras_path,
                                              const std::string& camera_poses_path) {
  const YAML::Node cameras = LoadYamlFile(cameras_path);
  if (!cameras.IsMap()) throw InputError(cameras_path, 0, "", "not a YAML map of cameras");
  YAML::Node poses;
  if (!camera_poses_path.empty()) {
    poses = LoadYamlFile(camera_poses_path);
    if (!poses.IsMap() && !poses.IsNull())
      throw InputError(camera_poses_path, 0, "", "not a YAML map of cameras");
  }
  std::vector<TagslamCamera> out;
  // TagSLAM's order: cam0, cam1, ... cam99 (camera2.cpp parse_cameras).
  for (int index = 0; index < 100; ++index) {
    const std::string name = "cam" + std::to_string(index);
    const YAML::Node node = cameras[name];
    if (!node) continue;
    if (!node.IsMap()) throw InputError(cameras_path, YamlLine(node), name, "not a map");
    TagslamCamera camera;
    camera.name = name;
    camera.model = ReadModel(node, cameras_path, &camera.unsupported);
    if (node["rostopic"]) camera.image_topic = YamlString(node, "rostopic", cameras_path);
    if (node["tagtopic"]) camera.tag_topic = YamlString(node, "tagtopic", cameras_path);
    if (node["rig_body"]) camera.rig_body = YamlString(node, "rig_body", cameras_path);
    if (poses.IsMap() && poses[name])
      camera.T_B_C = ReadTagslamPose(poses[name], "pose", camera_poses_path);
    out.push_back(camera);
  }
  if (out.empty()) throw InputError(cameras_path, 0, "", "no camera cam0..cam99 in the file");
  if (poses.IsMap()) {
    for (const auto& entry : poses) {
      const std::string name = YamlKey(entry.first, camera_poses_path);
      const bool known = std::any_of(out.begin(), out.end(),
                                     [&](const TagslamCamera& c) { return c.name == name; });
      if (!known)
        throw InputError(camera_poses_path, YamlLine(entry.first), name,
                         "camera pose for a camera that " + cameras_path + " does not list");
    }
  }
  return out;
}

}  // namespace mavloc
