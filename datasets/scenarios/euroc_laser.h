// Scenario "euroc-laser": the laser-spot paper's real-data experiment (Martinelli & Troiani,
// INRIA RR-7906, 2012, section 5.2) on EuRoC V1_01_easy: the real IMU and the real ground truth,
// with the laser spot simulated from the true poses, the same plane and laser as laser-plane.
//
// Data: <data>/mav0/imu0 (the whole 145.6 s IMU stream, 200 Hz) and <data>/groundtruth_full_tum.txt
// (the full original ground truth, 200 Hz). The setting `data` defaults to
// ../shared/data/euroc_v1_01_easy, looked up relative to the current directory and then to the
// executable's folder and its parents; a missing folder is an InputError naming the paths tried.
//
// Frames: the EuRoC ground truth (state_groundtruth_estimate0, of which groundtruth_full_tum.txt is
// the full-length copy; identical rows) is the pose of the IMU frame imu0 = body frame B in the
// Vicon world frame W (z up): T_W_B with B = S of imu0's sensor.yaml (T_BS = identity). It is
// used as T_W_B directly; velocities are central differences of the positions over +-10 ms, the
// biases of every row are the ASL estimate's first row (its only source; constant). The real cam0
// looks forward, so the laser camera is a virtual down-looking camera cam0 at the IMU origin:
// z_C = -x_B (x_B points up on the resting vehicle), x_C = y_B, y_C = -z_B; the laser is at
// [L, 0, 0] along z_C (L = 0.3 m). The plane: normal Rx(alpha) e_z (alpha = 22.5 deg), placed
// clearance_m (0.5) below the lowest point of the camera's path along the normal.
//
// Settings: data, alpha_deg (22.5), L (0.3), clearance_m (0.5), camera_rate_hz (10),
// bearing_noise_deg (1), imu (real; from_ground_truth replaces the IMU by one derived from the
// ground truth, without bias: it separates the real IMU's biases from the trajectory's excitation).
// The seed draws the bearing noise.
#pragma once

#include <string>
#include <vector>

#include "core/dataset.h"
#include "datasets/scenarios/scenario.h"

namespace mavloc {

Dataset GenerateEurocLaser(const ScenarioOptions& options);

// The default data folder resolved as described above, or "" when absent.
std::string FindDefaultEurocLaserData();

// An IMU stream derived from the ground truth (no bias, no noise): body rates from consecutive
// attitudes, the kinematic acceleration from second differences of the positions over +-10 rows
// (the ground truth's millimetre noise would otherwise dominate), specific force R^T (a - g). The
// stated noise densities are small floors (gyro 1e-4 rad/s/sqrt(Hz), accel 5e-3 m/s^2/sqrt(Hz)).
ImuSensor ImuFromGroundTruth(const std::vector<GroundTruthState>& truth);

// The ground truth of [t_begin, t_end] from the rows of groundtruth_full_tum.txt: T_W_B as read,
// v by central differences over +-2 rows, the biases of bias_source (constant).
std::vector<GroundTruthState> EurocGroundTruth(const std::vector<StampedPose>& poses,
                                               const GroundTruthState& bias_source, TimeNs t_begin,
                                               TimeNs t_end);

}  // namespace mavloc
