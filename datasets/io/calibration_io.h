// Reading camera and IMU calibrations (and an aprilgrid description) from the files calibration
// tools write, so that a log of raw measurements can become a dataset (import-aprilgrid):
// - EuRoC/ASL: a dataset root or its mav0/ folder (camN/sensor.yaml, imu0/sensor.yaml), a camN/
//   folder, or one sensor.yaml (camera: T_BS = T_B_C, resolution, camera_model pinhole,
//   intrinsics fu fv cu cv, distortion_model, distortion_coefficients, rate_hz; imu: Kalibr's noise
//   names, rate_hz);
// - Kalibr: camchain.yaml (camN: camera_model pinhole, intrinsics, distortion_model radtan|equi,
//   distortion_coeffs, resolution, T_cam_imu = T_C_B, T_cn_cnm1 = T_{C_n C_(n-1)}, 4x4 nested
//   lists) and imu.yaml (accelerometer_noise_density, accelerometer_random_walk,
//   gyroscope_noise_density, gyroscope_random_walk, update_rate), target.yaml
//   (datasets/io/aprilgrid_target_io.h);
// - yac (chutsu/yac config.yaml): camN: resolution, proj_model pinhole, dist_model radtan4|equi4,
//   proj_params fu fv cu cv, dist_params; T_cam0_camN {rows, cols, data} = T_C0_CN, T_imu0_camN =
//   T_B_CN; imu0: rate, sigma_g_c, sigma_a_c, sigma_gw_c, sigma_aw_c (continuous densities, the
//   same quantities as Kalibr's); calib_target.
// B is the IMU frame (imu0), as in EuRoC. Bad input throws InputError naming file, line, field.
#pragma once

#include <yaml-cpp/yaml.h>

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/aprilgrid.h"
#include "core/camera_model.h"
#include "core/imu.h"
#include "core/pose.h"

namespace mavloc {

// What one source says about one camera; every item is optional. `*_from` names the file and key.
struct CameraCalibration {
  std::optional<CameraModel> model;  // resolution, intrinsics, distortion
  std::string model_from;
  std::optional<Pose> T_B_C;  // the camera in the body (IMU) frame
  std::string T_B_C_from;
  std::optional<Pose> T_C0_C;  // the camera in cam0's frame (stereo calibrations)
  std::string T_C0_C_from;
  std::optional<double> rate_hz;
};

struct ImuCalibration {
  ImuNoise noise;  // continuous-time densities (Kalibr names)
  std::optional<double> rate_hz;
  std::string from;
};

struct CalibrationSource {
  std::string path;
  std::optional<AprilgridTarget> target;
  std::map<int, CameraCalibration> cameras;  // camera index N of camN
  std::optional<ImuCalibration> imu;
};

// The sanity ranges of core/physical_limits.h for camera values read from YAML, shared by every
// calibration reader (the ranges euroc_io.cc applies to sensor.yaml): intrinsics [fu fv cu cv]
// with focal lengths in (0, kMaxFocalLength_px] and the principal point within
// +-kMaxPixelCoordinate; every distortion coefficient within +-kMaxDistortionCoefficient. `key` is
// the list's key in `node` (for the line), `field` its name in the message. Throw InputError.
void CheckIntrinsicsRange(const YAML::Node& node, const std::string& key, const std::string& field,
                          const std::string& path, const std::vector<double>& intrinsics);
void CheckDistortionRange(const YAML::Node& node, const std::string& key, const std::string& field,
                          const std::string& path, const std::vector<double>& coefficients);

// "camN=PATH" -> {N, PATH}; a plain PATH -> {nullopt, PATH}.
std::pair<std::optional<int>, std::string> SplitCameraPrefix(const std::string& spec);

// Reads a file or folder in any of the layouts above. `camera` (from a "camN=" prefix) restricts
// the source to camera N and names the camera of a lone sensor.yaml whose folder is not camN.
// Throws InputError when the path holds none of them, or a camera it names is not in it.
CalibrationSource ReadCalibrationSource(const std::string& path,
                                        std::optional<int> camera = std::nullopt);

}  // namespace mavloc
