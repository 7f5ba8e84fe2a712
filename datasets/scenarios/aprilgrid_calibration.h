// Scenario "aprilgrid-calibration": a Kalibr-style camera-IMU calibration log. A
// stereo rig with EuRoC's cam0 and cam1 (intrinsics, radial-tangential distortion and T_B_C of
// mav0/cam{0,1}/sensor.yaml) and an ADIS16448-like IMU is waved in front of a 6 x 6 aprilgrid
// (core/aprilgrid.h: tag 0.088 m, spacing 0.3) hung on a wall. The map is the board
// (map.frame = kBoard, tags in the board frame M); the board is tilted to gravity by
// R_W_M = Ry(board_pitch) Rx(board_roll) (yaw is gauge), so the gravity direction in M is not an
// axis. Ground truth is written in the W of core/board_frame.h for the true gravity direction, so
// that an estimator's T_W_B compares directly.
//
// Motion (smooth, excited in every axis): a quintic B-spline whose control points, every
// control_interval_s, sample two sinusoids per component (frequencies in [0.15, 0.6] Hz and phases
// drawn from the seed, amplitudes 0.6 and 0.4 of the component's). cam0's optical axis passes
// through a target point near the board centre
// (+-target_amplitude_m in the board plane) at a distance distance_m +- distance_amplitude_m; the
// camera turns about its x and y axes by up to +-rotation_amplitude_deg / 1.2 and about its
// optical axis by up to +-rotation_amplitude_deg (roll, pitch, yaw of R_M_C relative to facing
// the board). The body B (IMU) follows from cam0 by the true T_B_C0.
//
// Observations: cameras at camera_rate_hz (cam0 and cam1 share the stamps); a frame stamped t
// shows the board at the exposure time t + t_d (time_offset_ms): "measurement time = image stamp
// + t_d". A tag is observed when its four corners are in front of the camera, inside the image
// (2 px border) and the board faces the camera (within 75 deg); each corner gets N(0,
// pixel_noise_px^2) per coordinate. tags0 / tags1 carry the distorted corners.
//
// What the dataset states: cam{0,1}/sensor.yaml T_B_C are the truth moved by extrinsics_error_m
// and extrinsics_error_deg in random directions (0 = the truth), so a calibration can be started
// from a wrong guess; the truth is in scenario_info (cam0_T_B_C_true, cam1_T_B_C_true as
// "x y z qw qx qy qz", time_offset_s, board_roll_deg, board_pitch_deg) and truth_quantities0
// (board_roll, board_pitch at every frame). The IMU: imu_rate_hz, EuRoC ADIS16448 densities
// (imu_noise), turn-on biases N(0, 0.002 rad/s), N(0, 0.05 m/s^2) random-walking (bias).
//
// Settings (`--set key=value`, defaults in brackets): pixel_noise_px [0.3], imu_noise [1],
// bias [1], time_offset_ms [5], extrinsics_error_m [0], extrinsics_error_deg [0],
// board_roll_deg [95], board_pitch_deg [10], distance_m [0.9], distance_amplitude_m [0.3],
// target_amplitude_m [0.1], rotation_amplitude_deg [30], control_interval_s [0.2],
// camera_rate_hz [20], imu_rate_hz [200], stereo [1] (0: cam0 only). `--render` also renders
// every camera frame (datasets/rendering/aprilgrid_renderer.h, 1 grey level of noise; about 0.2 s
// a frame), for `mavloc detect-tags --family aprilgrid`. Duration: --duration
// (default 30 s, at least 3 s).
#pragma once

#include <Eigen/Core>
#include <optional>

#include "core/dataset.h"
#include "core/pose.h"
#include "datasets/scenarios/scenario.h"

namespace mavloc {

Dataset GenerateAprilgridCalibration(const ScenarioOptions& options);

// The truth an aprilgrid-calibration dataset carries in scenario_info; nullopt for other datasets.
struct AprilgridCalibrationTruth {
  Pose T_B_C[2];  // cam0, cam1
  double time_offset_s = 0.0;
  Eigen::Vector3d up_M = Eigen::Vector3d::UnitZ();  // gravity direction (up) in the board frame
};
std::optional<AprilgridCalibrationTruth> AprilgridCalibrationTruthOf(const Dataset& dataset);

// EuRoC's cam1 (752 x 480, intrinsics and radial-tangential distortion of
// mav0/cam1/sensor.yaml) and the EuRoC T_B_C of cam0 and cam1 (T_BS of those files).
CameraModel EurocCam1Model();
Pose EurocCameraExtrinsic(int camera_index);

}  // namespace mavloc
