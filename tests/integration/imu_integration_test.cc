// The key test of sign and frame conventions: integrating the noiseless synthetic IMU from the
// true initial state reproduces the trajectory (below 1 mm after 10 s at 200 Hz).
#include <gtest/gtest.h>

#include "core/random.h"
#include "core/rotation.h"
#include "datasets/simulation/imu_simulator.h"
#include "datasets/simulation/random_motion_trajectory.h"
#include "datasets/simulation/spline_trajectory.h"
#include "solver/imu/imu_integrator.h"

namespace mavloc {
namespace {

std::unique_ptr<SplineTrajectory> AggressiveTrajectory(uint64_t seed, AttitudeMode mode) {
  Rng rng(seed);
  std::vector<Waypoint> waypoints;
  for (double t = 0.0; t <= 10.0; t += 1.0) {
    Waypoint w;
    w.t_s = t;
    w.p_W = Eigen::Vector3d{rng.Uniform(-2, 2), rng.Uniform(-2, 2), rng.Uniform(0.5, 2.5)};
    w.yaw_rad = rng.Uniform(-M_PI, M_PI);
    w.roll_rad = rng.Uniform(-0.5, 0.5);
    w.pitch_rad = rng.Uniform(-0.5, 0.5);
    waypoints.push_back(w);
  }
  return SplineTrajectory::FromWaypoints(1'403'715'273'262'142'976, waypoints, mode, 0.5);
}

struct IntegrationErrors {
  double max_position_m = 0.0;
  double max_rotation_rad = 0.0;
};

// Integrates the trajectory's noiseless IMU (with known constant biases, removed) for 10 s from
// the true initial state, checking every second.
IntegrationErrors IntegrateTenSeconds(const Trajectory& trajectory, double rate_hz) {
  ImuSimulationOptions options;
  options.rate_hz = rate_hz;
  options.initial_gyro_bias = Eigen::Vector3d(0.01, -0.02, 0.005);
  options.initial_accel_bias = Eigen::Vector3d(0.1, 0.05, -0.08);
  const auto sim = SimulateImu(trajectory, options, 1);
  const auto& gt0 = sim.ground_truth.front();
  NavState state{gt0.t_ns, gt0.T_W_B.q, gt0.T_W_B.p, gt0.v_W};
  const ImuIntegrator integrator(&sim.imu.samples);
  const ImuBiases biases{options.initial_gyro_bias, options.initial_accel_bias};
  IntegrationErrors e;
  const TimeNs t_end = gt0.t_ns + 10 * kNsPerSecond;
  EXPECT_LE(t_end, sim.imu.samples.back().t_ns);
  double path_length_m = 0.0;  // along the true trajectory, sampled every 10 ms
  for (TimeNs t = gt0.t_ns + kNsPerSecond / 100; t <= t_end; t += kNsPerSecond / 100)
    path_length_m += (trajectory.At(t).p_W - trajectory.At(t - kNsPerSecond / 100).p_W).norm();
  for (TimeNs t = gt0.t_ns + kNsPerSecond; t <= t_end; t += kNsPerSecond) {
    state = integrator.Integrate(state, t, biases);
    const auto truth = trajectory.At(t);
    e.max_position_m = std::max(e.max_position_m, (state.p_W - truth.p_W).norm());
    e.max_rotation_rad =
        std::max(e.max_rotation_rad, RotationAngleBetween(state.q_W_B, truth.q_W_B));
  }
  // The motion is not trivial: the vehicle travels metres (along its path; where it ends may be
  // near where it started).
  EXPECT_GT(path_length_m, 1.0);
  return e;
}

class ImuIntegration : public ::testing::TestWithParam<std::tuple<AttitudeMode, uint64_t>> {};

TEST_P(ImuIntegration, NoiselessImuReproducesTheTrajectory) {
  const auto [mode, seed] = GetParam();
  const IntegrationErrors e = IntegrateTenSeconds(*AggressiveTrajectory(seed, mode), 200.0);
  EXPECT_LT(e.max_position_m, 1e-3) << "m after 10 s";
  EXPECT_LT(e.max_rotation_rad, 1e-5) << "rad after 10 s";
}

// The laser paper's random motion at its 100 Hz IMU rate: the smoothed trajectory is integrable
// (the unsmoothed process, with its acceleration jumping every 0.01 s, drifted by centimetres).
TEST(ImuIntegration, NoiselessImuReproducesTheRandomMotion) {
  for (uint64_t seed = 1; seed <= 3; ++seed) {
    RandomMotionOptions options;
    options.start_ns = 1'000'000'000;
    options.duration_s = 11.0;
    const IntegrationErrors e = IntegrateTenSeconds(RandomMotionTrajectory(options, seed), 100.0);
    std::printf("seed %d: %.3g m %.3g rad\n", int(seed), e.max_position_m, e.max_rotation_rad);
    EXPECT_LT(e.max_position_m, 1e-4) << "m after 10 s, seed " << seed;
    EXPECT_LT(e.max_rotation_rad, 1e-6) << "rad after 10 s, seed " << seed;
  }
}

INSTANTIATE_TEST_SUITE_P(Trajectories, ImuIntegration,
                         ::testing::Combine(::testing::Values(AttitudeMode::kQuadrotor,
                                                              AttitudeMode::kEuler),
                                            ::testing::Values(1u, 2u, 3u)));

TEST(ImuIntegration, EulerIntegrationIsWorseThanRk4) {
  // Guards the test above from passing trivially: a first-order integrator misses the 1 mm bound.
  const auto trajectory = AggressiveTrajectory(1, AttitudeMode::kEuler);
  const auto sim = SimulateImu(*trajectory, {}, 1);
  const auto& gt0 = sim.ground_truth.front();
  Eigen::Quaterniond q = gt0.T_W_B.q;
  Eigen::Vector3d p = gt0.T_W_B.p, v = gt0.v_W;
  const TimeNs t_end = gt0.t_ns + 10 * kNsPerSecond;
  for (size_t i = 0; i + 1 < sim.imu.samples.size() && sim.imu.samples[i].t_ns < t_end; ++i) {
    const auto& s = sim.imu.samples[i];
    const double dt = NsToSeconds(sim.imu.samples[i + 1].t_ns - s.t_ns);
    const Eigen::Vector3d a = q * s.accel_m_s2 + GravityW();
    p += v * dt + 0.5 * a * dt * dt;
    v += a * dt;
    q = (q * ExpQuaternion(s.gyro_rad_s * dt)).normalized();
  }
  EXPECT_GT((p - trajectory->At(t_end).p_W).norm(), 1e-3);
}

}  // namespace
}  // namespace mavloc
