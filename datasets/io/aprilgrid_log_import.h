// Assembling an ASL dataset from a Kalibr-style aprilgrid calibration log (EuRoC's imu_april as
// yac ships it): an IMU CSV, per-image corner folders for one or more cameras, and calibration
// sources for the target, the cameras and the IMU noise (datasets/io/calibration_io.h).
//
// The dataset: imu0 (B = the IMU, T_BS identity, noise densities), cam0..camK (K = the highest
// camera with corners; sensor.yaml with intrinsics and T_B_C, data.csv listing every corner file
// as a frame whose image is absent), tags0/tags1 (complete tags; corners in mavloc's order), and
// map.yaml with `frame: board` and the aprilgrid's tags in the board frame M (core/aprilgrid.h),
// the grid itself kept as map parameters aprilgrid_* (datasets/io/aprilgrid_target_io.h).
//
// Each calibration item (target, a camera's intrinsics, its T_B_C, its pose in cam0, the IMU
// noise) comes from the first source that holds it: the specific sources first (`target`,
// `intrinsics`, `extrinsics`, `imu_noise`, each in the order given), then the general `configs`.
// A camera's T_B_C is, in that order: given directly (EuRoC T_BS, Kalibr T_cam_imu inverted, yac
// T_imu0_camN); cam0's T_B_C composed with the camera's pose in cam0 (yac T_cam0_camN, Kalibr
// T_cn_cnm1); the pose in cam0 alone (B taken at cam0); identity. The last two are coarse guesses
// and are said so in the notes.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "core/aprilgrid.h"
#include "core/dataset.h"
#include "datasets/io/aprilgrid_corners_io.h"

namespace mavloc {

struct AprilgridLogInputs {
  std::string imu_csv;
  std::vector<std::string> corners;     // "camN=FOLDER" (a plain FOLDER is cam0)
  std::vector<std::string> configs;     // "[camN=]PATH": everything a source holds
  std::vector<std::string> target;      // PATH: the aprilgrid only
  std::vector<std::string> intrinsics;  // "[camN=]PATH": camera models only
  std::vector<std::string> extrinsics;  // "[camN=]PATH": T_B_C and poses in cam0 only
  std::vector<std::string> imu_noise;   // PATH: IMU noise densities (and rate) only
};

struct AprilgridLogCamera {
  std::string name;            // camN
  std::string corners_folder;  // empty for a camera written only to keep the indices (no corners)
  AprilgridCornerStats stats;
  std::string intrinsics_from;
  std::string T_B_C_from;
  bool T_B_C_known = false;  // false: a guess (identity, or the pose in cam0)
};

struct AprilgridLogImport {
  Dataset dataset;
  AprilgridTarget target;
  std::vector<AprilgridLogCamera> cameras;
  std::string imu_noise_from;
  std::vector<std::string> notes;  // provenance, guesses and consistency checks, one line each

  // import.yaml: where everything came from and the counts (written beside map.yaml).
  std::string ImportYaml() const;
};

// Reads and checks every input (InputError naming the file, line and field; a camera with corners
// but no intrinsics; no target; no IMU noise; IMU and frames not overlapping) and returns the
// dataset; writes nothing.
AprilgridLogImport ImportAprilgridLog(const AprilgridLogInputs& inputs);

}  // namespace mavloc
