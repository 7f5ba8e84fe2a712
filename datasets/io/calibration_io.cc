#include "datasets/io/calibration_io.h"

#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <regex>

#include "core/errors.h"
#include "core/physical_limits.h"
#include "datasets/io/aprilgrid_target_io.h"
#include "datasets/io/yaml_util.h"

namespace fs = std::filesystem;

namespace mavloc {

namespace {

long Line(const YAML::Node& node) { return node ? node.Mark().line + 1 : 0; }

std::string ScalarText(const YAML::Node& node, const std::string& field, const std::string& path) {
  const YAML::Node value = node[field];
  if (!value) throw InputError(path, Line(node), field, "missing");
  if (!value.IsScalar()) throw InputError(path, Line(value), field, "not a single value");
  return value.Scalar();
}

// "camN" -> N.
std::optional<int> CameraIndex(const std::string& name) {
  static const std::regex pattern("cam([0-9]{1,2})");
  std::smatch match;
  if (!std::regex_match(name, match, pattern)) return std::nullopt;
  return std::stoi(match[1].str());
}

CameraModel MakeModel(const YAML::Node& node, const std::string& path, const std::string& prefix,
                      const std::string& intrinsics_key, const std::string& distortion_model_key,
                      const std::string& coefficients_key, const std::string& camera_model_key) {
  const auto resolution = YamlDoubles(node, "resolution", path, 2);
  for (double r : resolution) {
    if (r != std::floor(r) || r < 1 || r > limits::kMaxResolution_px)
      throw InputError(path, Line(node["resolution"]), prefix + "resolution",
                       "must be two positive pixel counts");
  }
  if (node[camera_model_key]) {
    const std::string projection = ScalarText(node, camera_model_key, path);
    if (projection != "pinhole")
      throw InputError(path, Line(node[camera_model_key]), prefix + camera_model_key,
                       "'" + projection + "' is not supported (only pinhole)");
  }
  const auto k = YamlDoubles(node, intrinsics_key, path, 4);
  CheckIntrinsicsRange(node, intrinsics_key, prefix + intrinsics_key, path, k);
  DistortionModel model = DistortionModel::kNone;
  std::array<double, 4> coefficients{0, 0, 0, 0};
  if (node[distortion_model_key]) {
    std::string name = ScalarText(node, distortion_model_key, path);
    // yac appends the coefficient count: radtan4, equi4.
    if (name == "radtan4") name = "radtan";
    if (name == "equi4") name = "equi";
    const auto parsed = ParseDistortionModel(name);
    if (!parsed)
      throw InputError(path, Line(node[distortion_model_key]), prefix + distortion_model_key,
                       "unknown model '" + name +
                           "' (radtan/radial-tangential/radtan4, equi/equidistant/equi4 or none)");
    model = *parsed;
    if (model != DistortionModel::kNone) {
      const auto d = YamlDoubles(node, coefficients_key, path, 4);
      CheckDistortionRange(node, coefficients_key, prefix + coefficients_key, path, d);
      std::copy_n(d.begin(), 4, coefficients.begin());
    }
  }
  return CameraModel(static_cast<int>(resolution[0]), static_cast<int>(resolution[1]),
                     Eigen::Vector4d(k[0], k[1], k[2], k[3]), model, coefficients);
}

// EuRoC sensor.yaml of a camera.
CameraCalibration EurocCamera(const YAML::Node& yaml, const std::string& path) {
  CameraCalibration camera;
  camera.model = MakeModel(yaml, path, "", "intrinsics", "distortion_model",
                           "distortion_coefficients", "camera_model");
  camera.model_from = path;
  if (yaml["T_BS"]) {
    camera.T_B_C = YamlRigidTransform(yaml, "T_BS", path);
    camera.T_B_C_from = path + " (T_BS)";
  }
  // 0 means "not stated", as in euroc_io.cc (mavloc writes it for logs of unknown rate).
  if (yaml["rate_hz"])
    camera.rate_hz = YamlDoubleIn(yaml, "rate_hz", path, 0.0, limits::kMaxRate_hz, "Hz");
  return camera;
}

std::optional<ImuCalibration> ImuNoiseKeys(const YAML::Node& node, const std::string& path,
                                           const std::string& where) {
  struct Names {
    const char* gyro_white;
    const char* gyro_walk;
    const char* accel_white;
    const char* accel_walk;
    const char* rate;
  };
  // Kalibr/EuRoC names, then yac's.
  for (const Names& names :
       {Names{"gyroscope_noise_density", "gyroscope_random_walk", "accelerometer_noise_density",
              "accelerometer_random_walk", "update_rate"},
        Names{"sigma_g_c", "sigma_gw_c", "sigma_a_c", "sigma_aw_c", "rate"}}) {
    if (!node[names.gyro_white] && !node[names.accel_white]) continue;
    ImuCalibration imu;
    auto density = [&](const char* key, double max, const char* unit) {
      const double x = YamlDoubleIn(node, key, path, 0.0, max, unit);
      if (!(x > 0)) throw InputError(path, Line(node[key]), key, "must be a positive density");
      return x;
    };
    using limits::kMaxAccelNoise, limits::kMaxGyroNoise;
    imu.noise.gyroscope_noise_density = density(names.gyro_white, kMaxGyroNoise, "rad/s/sqrt(Hz)");
    imu.noise.gyroscope_random_walk = density(names.gyro_walk, kMaxGyroNoise, "rad/s^2/sqrt(Hz)");
    imu.noise.accelerometer_noise_density =
        density(names.accel_white, kMaxAccelNoise, "m/s^2/sqrt(Hz)");
    imu.noise.accelerometer_random_walk =
        density(names.accel_walk, kMaxAccelNoise, "m/s^3/sqrt(Hz)");
    for (const char* rate : {names.rate, "rate_hz"}) {
      if (node[rate]) {
        imu.rate_hz = YamlDoubleIn(node, rate, path, 0.0, limits::kMaxRate_hz, "Hz");
        if (!(*imu.rate_hz > 0))
          throw InputError(path, Line(node[rate]), rate, "must be a positive rate in Hz");
        break;
      }
    }
    imu.from = path + where;
    return imu;
  }
  return std::nullopt;
}

bool IsCameraSensorYaml(const YAML::Node& yaml) {
  return (yaml["sensor_type"] && yaml["sensor_type"].IsScalar() &&
          yaml["sensor_type"].Scalar() == "camera") ||
         (yaml["intrinsics"] && yaml["resolution"] && !yaml["cam0"]);
}

// A YAML file in any layout; `folder_camera` is the N of a camN/ folder holding it.
CalibrationSource ReadYamlSource(const std::string& path, std::optional<int> folder_camera) {
  const YAML::Node yaml = LoadYamlFile(path);
  CalibrationSource source;
  source.path = path;
  if (!yaml.IsMap()) throw InputError(path, 0, "", "not a YAML map of calibration keys");
  source.target = FindAprilgridTarget(yaml, path);
  if (IsCameraSensorYaml(yaml)) {
    if (!folder_camera)
      throw InputError(path, 0, "",
                       "a single camera's sensor.yaml outside a camN/ folder: say which camera "
                       "with camN=" +
                           path);
    source.cameras[*folder_camera] = EurocCamera(yaml, path);
  }
  if (!IsCameraSensorYaml(yaml)) {
    if (auto imu = ImuNoiseKeys(yaml, path, "")) source.imu = imu;
  }
  if (const YAML::Node imu0 = yaml["imu0"]) {
    if (imu0.IsMap() && !source.imu) source.imu = ImuNoiseKeys(imu0, path, " (imu0)");
  }
  // Multi-camera files: yac config.yaml, Kalibr camchain.yaml.
  std::map<int, Pose> T_cn_cnm1;  // Kalibr chain
  for (const auto& item : yaml) {
    const std::string key = YamlKey(item.first, path);
    const auto index = CameraIndex(key);
    if (!index || !item.second.IsMap()) continue;
    const YAML::Node node = item.second;
    const std::string prefix = key + ".";
    CameraCalibration camera;
    if (node["proj_params"]) {  // yac
      camera.model =
          MakeModel(node, path, prefix, "proj_params", "dist_model", "dist_params", "proj_model");
      camera.model_from = path + " (" + key + ", yac layout)";
    } else if (node["intrinsics"]) {  // Kalibr camchain
      camera.model = MakeModel(node, path, prefix, "intrinsics", "distortion_model",
                               "distortion_coeffs", "camera_model");
      camera.model_from = path + " (" + key + ", Kalibr camchain)";
      if (node["T_cam_imu"]) {
        camera.T_B_C = YamlRigidTransform(node, "T_cam_imu", path).Inverse();
        camera.T_B_C_from = path + " (" + key + ".T_cam_imu)";
      }
      if (node["T_cn_cnm1"]) T_cn_cnm1[*index] = YamlRigidTransform(node, "T_cn_cnm1", path);
    } else {
      continue;  // no parameters (yac's stereo_config.yaml template names only the models)
    }
    if (*index == 0) {
      camera.T_C0_C = Pose();
      camera.T_C0_C_from = "identity (cam0)";
    }
    source.cameras[*index] = camera;
  }
  // Kalibr's chain T_cn_cnm1 (camera n-1 in camera n) composed into T_C0_Cn.
  for (int n = 1; T_cn_cnm1.count(n) && source.cameras.count(n); ++n) {
    const auto previous = source.cameras.find(n - 1);
    if (previous == source.cameras.end() || !previous->second.T_C0_C) break;
    source.cameras[n].T_C0_C = *previous->second.T_C0_C * T_cn_cnm1.at(n).Inverse();
    source.cameras[n].T_C0_C_from = path + " (T_cn_cnm1 chain to cam" + std::to_string(n) + ")";
  }
  // yac / generic transforms at the top level: T_cam0_camN, T_imu0_camN, T_camN_imu0.
  static const std::regex relative("T_cam0_cam([0-9]{1,2})"), body("T_imu0_cam([0-9]{1,2})"),
      body_inverse("T_cam([0-9]{1,2})_imu0");
  for (const auto& item : yaml) {
    const std::string key = YamlKey(item.first, path);
    std::smatch match;
    if (std::regex_match(key, match, relative)) {
      const int n = std::stoi(match[1].str());
      source.cameras[n].T_C0_C = YamlRigidTransform(yaml, key, path);
      source.cameras[n].T_C0_C_from = path + " (" + key + ")";
    } else if (std::regex_match(key, match, body)) {
      const int n = std::stoi(match[1].str());
      source.cameras[n].T_B_C = YamlRigidTransform(yaml, key, path);
      source.cameras[n].T_B_C_from = path + " (" + key + ")";
    } else if (std::regex_match(key, match, body_inverse)) {
      const int n = std::stoi(match[1].str());
      source.cameras[n].T_B_C = YamlRigidTransform(yaml, key, path).Inverse();
      source.cameras[n].T_B_C_from = path + " (" + key + ", inverted)";
    }
  }
  return source;
}

// A dataset root, its mav0/, or a camN/ or imu0/ folder.
CalibrationSource ReadFolderSource(const fs::path& folder) {
  fs::path mav0 = folder;
  if (fs::is_directory(folder / "mav0")) mav0 = folder / "mav0";
  CalibrationSource source;
  source.path = folder.string();
  const std::string name = folder.filename().string();
  if (const auto index = CameraIndex(name); index && fs::exists(folder / "sensor.yaml")) {
    CalibrationSource one = ReadYamlSource((folder / "sensor.yaml").string(), index);
    one.path = folder.string();
    return one;
  }
  if (name == "imu0" && fs::exists(folder / "sensor.yaml"))
    return ReadYamlSource((folder / "sensor.yaml").string(), std::nullopt);
  for (const auto& entry : fs::directory_iterator(mav0)) {
    const std::string sub = entry.path().filename().string();
    const fs::path yaml = entry.path() / "sensor.yaml";
    if (!entry.is_directory() || !fs::exists(yaml)) continue;
    if (const auto index = CameraIndex(sub)) {
      source.cameras[*index] = ReadYamlSource(yaml.string(), index).cameras.at(*index);
    } else if (sub == "imu0") {
      source.imu = ReadYamlSource(yaml.string(), std::nullopt).imu;
    }
  }
  if (source.cameras.empty() && !source.imu)
    throw InputError(folder.string(), 0, "",
                     "no calibration here: expected an EuRoC dataset or mav0/ folder "
                     "(camN/sensor.yaml, imu0/sensor.yaml) or a camN/ folder");
  return source;
}

// Line of item i of the list `key` (its own line in a block list), else of the list.
long CalibrationItemLine(const YAML::Node& node, const std::string& key, size_t i) {
  const YAML::Node list = node[key];
  if (list && list.IsSequence() && i < list.size() && list[i]) return YamlLine(list[i]);
  return YamlLine(list);
}

}  // namespace

void CheckIntrinsicsRange(const YAML::Node& node, const std::string& key, const std::string& field,
                          const std::string& path, const std::vector<double>& intrinsics) {
  static const char* const kNames[] = {"fu", "fv", "cu", "cv"};
  for (size_t i = 0; i < intrinsics.size() && i < 4; ++i) {
    const bool focal = i < 2;
    const double lo = focal ? 0.0 : -limits::kMaxPixelCoordinate;
    const double hi = focal ? limits::kMaxFocalLength_px : limits::kMaxPixelCoordinate;
    const double x = intrinsics[i];
    if (!(x <= hi && (focal ? x > lo : x >= lo)))
      throw InputError(
          path, CalibrationItemLine(node, key, i), field,
          fmt::format("{} = {:g} is outside {}{}", kNames[i], x, limits::RangeText(lo, hi, "px"),
                      focal ? " (a focal length must be > 0)" : ""));
  }
}

void CheckDistortionRange(const YAML::Node& node, const std::string& key, const std::string& field,
                          const std::string& path, const std::vector<double>& coefficients) {
  const double max = limits::kMaxDistortionCoefficient;
  for (size_t i = 0; i < coefficients.size(); ++i) {
    if (!(std::abs(coefficients[i]) <= max))
      throw InputError(path, CalibrationItemLine(node, key, i), field,
                       fmt::format("coefficient {} = {:g} is outside {}", i + 1, coefficients[i],
                                   limits::RangeText(-max, max, "")));
  }
}

std::pair<std::optional<int>, std::string> SplitCameraPrefix(const std::string& spec) {
  static const std::regex pattern("(cam[0-9]{1,2})=(.*)");
  std::smatch match;
  if (std::regex_match(spec, match, pattern)) return {CameraIndex(match[1].str()), match[2].str()};
  return {std::nullopt, spec};
}

CalibrationSource ReadCalibrationSource(const std::string& path, std::optional<int> camera) {
  if (!fs::exists(path)) throw InputError(path, 0, "", "file or folder does not exist");
  CalibrationSource source;
  if (fs::is_directory(path)) {
    source = ReadFolderSource(fs::path(path));
  } else {
    // A sensor.yaml in a camN/ folder belongs to camera N; a "camN=" prefix overrides.
    std::optional<int> folder_camera =
        camera ? camera : CameraIndex(fs::path(path).parent_path().filename().string());
    source = ReadYamlSource(path, folder_camera);
  }
  if (camera) {
    const auto it = source.cameras.find(*camera);
    if (it == source.cameras.end())
      throw InputError(path, 0, "", fmt::format("describes no cam{}", *camera));
    const CameraCalibration only = it->second;
    source.cameras = {{*camera, only}};
  }
  if (source.cameras.empty() && !source.imu && !source.target)
    throw InputError(path, 0, "",
                     "holds no camera, IMU or aprilgrid calibration in a known layout (EuRoC "
                     "sensor.yaml, Kalibr camchain/imu/target.yaml, yac config.yaml)");
  return source;
}

}  // namespace mavloc
