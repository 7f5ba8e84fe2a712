#include "datasets/simulation/imu_simulator.h"

#include <cmath>
#include <stdexcept>

#include "core/random.h"

namespace mavloc {

ImuSimulationOptions EurocLikeImuOptions(double rate_hz, bool noise, bool bias,
                                         uint64_t bias_seed) {
  ImuSimulationOptions options;
  options.rate_hz = rate_hz;
  if (noise) options.noise = EurocAdis16448Noise();
  if (bias) {
    Rng bias_rng(bias_seed);
    options.initial_gyro_bias = bias_rng.Gaussian3(0.002);
    options.initial_accel_bias = bias_rng.Gaussian3(0.05);
    options.bias_random_walk = noise;
    options.gyro_bias_sigma_rad_s = 0.002;
    options.accel_bias_sigma_m_s2 = 0.05;
  }
  return options;
}

ImuSimulation SimulateImu(const Trajectory& trajectory, const ImuSimulationOptions& options,
                          uint64_t imu_seed) {
  if (!(options.rate_hz > 0.0)) throw std::invalid_argument("SimulateImu: rate must be > 0");
  ImuSimulation out;
  out.imu.name = "imu0";
  out.imu.rate_hz = options.rate_hz;
  out.imu.noise = options.noise;
  out.imu.gyroscope_bias_sigma =
      options.gyro_bias_sigma_rad_s.value_or(options.initial_gyro_bias.cwiseAbs().maxCoeff());
  out.imu.accelerometer_bias_sigma =
      options.accel_bias_sigma_m_s2.value_or(options.initial_accel_bias.cwiseAbs().maxCoeff());
  Rng rng(imu_seed);
  const double dt = 1.0 / options.rate_hz;
  const TimeNs step_ns = SecondsToNs(dt);
  const double sigma_g = DiscreteSigma(options.noise.gyroscope_noise_density, dt);
  const double sigma_a = DiscreteSigma(options.noise.accelerometer_noise_density, dt);
  const double walk_g = options.noise.gyroscope_random_walk * std::sqrt(dt);
  const double walk_a = options.noise.accelerometer_random_walk * std::sqrt(dt);
  Eigen::Vector3d b_g = options.initial_gyro_bias, b_a = options.initial_accel_bias;
  for (TimeNs t = trajectory.start_ns(); t <= trajectory.end_ns(); t += step_ns) {
    const TrajectorySample s = trajectory.At(t);
    ImuSample sample;
    sample.t_ns = t;
    // Draw all noise terms in a fixed order so the stream depends on the seed only.
    const Eigen::Vector3d n_g = rng.Gaussian3(1.0) * sigma_g;
    const Eigen::Vector3d n_a = rng.Gaussian3(1.0) * sigma_a;
    sample.gyro_rad_s = s.w_B + b_g + n_g;
    sample.accel_m_s2 = s.q_W_B.conjugate() * (s.a_W - GravityW()) + b_a + n_a;
    out.imu.samples.push_back(sample);

    GroundTruthState gt;
    gt.t_ns = t;
    gt.T_W_B = s.T_W_B();
    gt.v_W = s.v_W;
    gt.b_g = b_g;
    gt.b_a = b_a;
    out.ground_truth.push_back(gt);

    if (options.bias_random_walk) {
      b_g += rng.Gaussian3(1.0) * walk_g;
      b_a += rng.Gaussian3(1.0) * walk_a;
    }
  }
  return out;
}

void AddSimulatedImu(const Trajectory& trajectory, const ImuSimulationOptions& options,
                     uint64_t imu_seed, Dataset* dataset) {
  ImuSimulation simulation = SimulateImu(trajectory, options, imu_seed);
  dataset->imu = std::move(simulation.imu);
  dataset->ground_truth = std::move(simulation.ground_truth);
}

}  // namespace mavloc
