// IMU samples and noise model (DESIGN.md):
//   w_m = w_B + b_g + n_g,   a_m = R_W_B^T (a_W - g_W) + b_a + n_a,   g_W = (0, 0, -9.81).
// A resting level IMU reads a_m = (0, 0, +9.81). Noise is given as continuous-time densities as in
// Kalibr; a per-sample standard deviation converts with sigma_d = sigma_c / sqrt(dt).
#pragma once

#include <Eigen/Core>
#include <cmath>

#include "core/time.h"

namespace mavloc {

constexpr double kGravityMagnitude = 9.81;
inline Eigen::Vector3d GravityW() { return {0.0, 0.0, -kGravityMagnitude}; }

struct ImuSample {
  TimeNs t_ns = 0;
  Eigen::Vector3d gyro_rad_s = Eigen::Vector3d::Zero();  // w_m, in B
  Eigen::Vector3d accel_m_s2 = Eigen::Vector3d::Zero();  // a_m (specific force), in B
};

// Continuous-time noise densities (Kalibr names).
struct ImuNoise {
  double gyroscope_noise_density = 0.0;      // rad / s / sqrt(Hz)
  double gyroscope_random_walk = 0.0;        // rad / s^2 / sqrt(Hz)
  double accelerometer_noise_density = 0.0;  // m / s^2 / sqrt(Hz)
  double accelerometer_random_walk = 0.0;    // m / s^3 / sqrt(Hz)
};

// Every density times k (a noise model scaled as a whole: Kalibr users' inflation, the smoother's
// fitted scale).
inline ImuNoise ScaledImuNoise(const ImuNoise& noise, double k) {
  return {k * noise.gyroscope_noise_density, k * noise.gyroscope_random_walk,
          k * noise.accelerometer_noise_density, k * noise.accelerometer_random_walk};
}

// sigma_d = sigma_c / sqrt(dt) and its inverse.
inline double DiscreteSigma(double density, double dt_s) { return density / std::sqrt(dt_s); }
inline double DensityFromDiscreteSigma(double sigma, double dt_s) {
  return sigma * std::sqrt(dt_s);
}

// The EuRoC MAV's ADIS16448 (mav0/imu0/sensor.yaml of the EuRoC sequences).
inline ImuNoise EurocAdis16448Noise() { return {1.6968e-04, 1.9393e-05, 2.0e-3, 3.0e-3}; }

// White-noise densities from per-sample standard deviations as the papers state them, at rate_hz
// (sigma_c = sigma_d sqrt(dt)); no bias random walk.
inline ImuNoise NoiseFromPerSampleSigmas(double gyro_sigma_rad_s, double accel_sigma_m_s2,
                                         double rate_hz) {
  const double dt = 1.0 / rate_hz;
  ImuNoise noise;
  noise.gyroscope_noise_density = DensityFromDiscreteSigma(gyro_sigma_rad_s, dt);
  noise.accelerometer_noise_density = DensityFromDiscreteSigma(accel_sigma_m_s2, dt);
  return noise;
}

}  // namespace mavloc
