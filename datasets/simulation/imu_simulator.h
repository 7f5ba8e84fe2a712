// IMU synthesis from a trajectory (DESIGN.md IMU model):
//   w_m = w_B + b_g + n_g,   a_m = R_W_B^T (a_W - g_W) + b_a + n_a,
// with n ~ N(0, sigma_d^2), sigma_d = density / sqrt(dt), and biases either constant or a random
// walk b_{k+1} = b_k + N(0, random_walk^2 dt). The ground truth written alongside carries the true
// bias of every sample.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "core/dataset.h"
#include "datasets/simulation/trajectory.h"

namespace mavloc {

struct ImuSimulationOptions {
  double rate_hz = 200.0;
  ImuNoise noise;  // densities and random walks; zero = noiseless
  Eigen::Vector3d initial_gyro_bias = Eigen::Vector3d::Zero();
  Eigen::Vector3d initial_accel_bias = Eigen::Vector3d::Zero();
  bool bias_random_walk = false;  // if false the biases stay at their initial values
  // The turn-on bias standard deviations the dataset states (ImuSensor); unset = the largest
  // initial bias component (zero for bias-free sensors).
  std::optional<double> gyro_bias_sigma_rad_s;
  std::optional<double> accel_bias_sigma_m_s2;
};

// A EuRoC-like IMU at rate_hz: the ADIS16448 noise densities when `noise`; when `bias`, random
// initial biases (N(0, 0.002 rad/s) gyro, N(0, 0.05 m/s^2) accelerometer per axis, drawn from
// bias_seed) that random-walk when `noise` is on too.
ImuSimulationOptions EurocLikeImuOptions(double rate_hz, bool noise, bool bias, uint64_t bias_seed);

struct ImuSimulation {
  ImuSensor imu;
  std::vector<GroundTruthState> ground_truth;  // one row per IMU sample (true pose, v, biases)
};

// Samples [trajectory.start_ns(), trajectory.end_ns()] at rate_hz; noise drawn from imu_seed only.
ImuSimulation SimulateImu(const Trajectory& trajectory, const ImuSimulationOptions& options,
                          uint64_t imu_seed);

// SimulateImu into a dataset: its imu0 stream and its ground truth.
void AddSimulatedImu(const Trajectory& trajectory, const ImuSimulationOptions& options,
                     uint64_t imu_seed, Dataset* dataset);

}  // namespace mavloc
