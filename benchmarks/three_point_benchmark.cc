// Three-point paper solvers: time per call of the 2p-algorithm (eq. 1-4) and the 3p-algorithm
// (eq. 5-6, Levenberg-Marquardt over roll/pitch from a start 3 deg off), in the style of
// PoseLib's solver benchmark: on pre-generated random instances (the paper's triangle, D = 0.1 m,
// seen from 0.2-1 m with the line of sight 15-50 deg off the vertical), with the share of calls
// that return a solution and, for noiseless instances, that recover the truth (1e-6). Also the
// gravity EKF per IMU sample and the triangle-angle measurement of IV-C.
#include <benchmark/benchmark.h>

#include <cmath>
#include <vector>

#include "core/random.h"
#include "core/rotation.h"
#include "solver/attitude/gravity_ekf.h"
#include "solver/three_point/three_point.h"
#include "solver/three_point/triangle_angle_filter.h"
#include "solver/three_point/two_point.h"

namespace mavloc {
namespace {

struct Instance {
  ThreePointInput input;  // start roll/pitch perturbed by up to 3 deg
  EulerRpy truth;
  Pose T_W_B;
};

// Random views of the paper's triangle by a down-looking camera; bearing noise in rad (angular,
// per image axis, approximated on normalized coordinates).
std::vector<Instance> MakeInstances(int count, double bearing_noise_rad, uint64_t seed) {
  Rng rng(seed);
  const double D = 0.1;
  const std::array<Eigen::Vector3d, 3> P = {Eigen::Vector3d::Zero(), Eigen::Vector3d(D, 0, 0),
                                            Eigen::Vector3d(0.5 * D, std::sqrt(3.0) / 2 * D, 0)};
  const Eigen::Vector3d centroid = (P[0] + P[1] + P[2]) / 3.0;
  const Pose T_B_C(Eigen::Matrix3d(Eigen::Vector3d(1, -1, -1).asDiagonal()),
                   Eigen::Vector3d(0, 0, -0.03));
  std::vector<Instance> instances;
  while (static_cast<int>(instances.size()) < count) {
    const double h = rng.Uniform(0.2, 1.0);
    const double off = rng.Uniform(15, 50) * kDeg, azimuth = rng.Uniform(-180, 180) * kDeg;
    const Eigen::Vector3d c_W =
        centroid + h * Eigen::Vector3d(std::tan(off) * std::cos(azimuth),
                                       std::tan(off) * std::sin(azimuth), 1.0);
    Instance in;
    in.truth = EulerRpy{rng.Uniform(-10, 10) * kDeg, rng.Uniform(-10, 10) * kDeg,
                        rng.Uniform(-180, 180) * kDeg};
    const Eigen::Matrix3d R_W_B = RotationFromEuler(in.truth);
    in.T_W_B = Pose(R_W_B, Eigen::Vector3d(c_W - R_W_B * T_B_C.p));
    const Pose T_C_W = (in.T_W_B * T_B_C).Inverse();
    bool visible = true;
    for (int i = 0; i < 3; ++i) {
      const Eigen::Vector3d X_C = T_C_W * P[i];
      visible = visible && X_C.z() > 0.05 && std::abs(X_C.x() / X_C.z()) < 1.4 &&
                std::abs(X_C.y() / X_C.z()) < 0.9;
      in.input.xy[i] = X_C.head<2>() / X_C.z() + bearing_noise_rad * rng.GaussianVector<2>();
    }
    if (!visible) continue;
    in.input.roll_rad = in.truth.roll + rng.Uniform(-3, 3) * kDeg;
    in.input.pitch_rad = in.truth.pitch + rng.Uniform(-3, 3) * kDeg;
    in.input.T_B_C = T_B_C;
    in.input.distance_m = D;
    in.input.gamma1_rad = 60 * kDeg;
    in.input.gamma2_rad = 120 * kDeg;
    instances.push_back(in);
  }
  return instances;
}

TwoPointInput TwoPointFor(const Instance& in) {
  TwoPointInput input;
  input.roll_rad = in.truth.roll;  // 2p is given the true roll and pitch here
  input.pitch_rad = in.truth.pitch;
  input.xy1 = in.input.xy[0];
  input.xy2 = in.input.xy[1];
  input.T_B_C = in.input.T_B_C;
  input.distance_m = in.input.distance_m;
  return input;
}

bool Recovered(const Pose& estimate, const Pose& truth) {
  return (estimate.p - truth.p).norm() < 1e-6 && RotationAngleBetween(estimate.q, truth.q) < 1e-6;
}

// Arg: bearing noise in millidegrees.
void BM_TwoPoint(benchmark::State& state) {
  const auto instances = MakeInstances(1000, state.range(0) * 1e-3 * kDeg, 1);
  std::vector<TwoPointInput> inputs;
  for (const auto& in : instances) inputs.push_back(TwoPointFor(in));
  size_t i = 0, solved = 0, calls = 0, found = 0;
  TwoPointSolution solution;
  for (auto _ : state) {
    const size_t k = i++ % inputs.size();
    const bool ok = SolveTwoPoint(inputs[k], &solution) == TwoPointStatus::kOk;
    benchmark::DoNotOptimize(solution);
    ++calls;
    solved += ok;
    found += ok && Recovered(solution.T_W_B, instances[k].T_W_B);
  }
  state.counters["solved_%"] = 100.0 * static_cast<double>(solved) / static_cast<double>(calls);
  state.counters["truth_%"] = 100.0 * static_cast<double>(found) / static_cast<double>(calls);
}
BENCHMARK(BM_TwoPoint)->Arg(0)->Arg(1000)->Unit(benchmark::kNanosecond);

void BM_ThreePoint(benchmark::State& state) {
  const auto instances = MakeInstances(1000, state.range(0) * 1e-3 * kDeg, 2);
  size_t i = 0, solved = 0, calls = 0, found = 0, iterations = 0;
  ThreePointSolution solution;
  for (auto _ : state) {
    const size_t k = i++ % instances.size();
    const bool ok = SolveThreePoint(instances[k].input, &solution).ok();
    benchmark::DoNotOptimize(solution);
    ++calls;
    solved += ok;
    iterations += ok ? static_cast<size_t>(solution.iterations) : 0;
    found += ok && Recovered(solution.pose.T_W_B, instances[k].T_W_B);
  }
  state.counters["solved_%"] = 100.0 * static_cast<double>(solved) / static_cast<double>(calls);
  state.counters["truth_%"] = 100.0 * static_cast<double>(found) / static_cast<double>(calls);
  state.counters["lm_iterations"] =
      static_cast<double>(iterations) / static_cast<double>(std::max<size_t>(solved, 1));
}
BENCHMARK(BM_ThreePoint)->Arg(0)->Arg(1000)->Unit(benchmark::kMicrosecond);

void BM_TriangleAngleMeasurement(benchmark::State& state) {
  const auto instances = MakeInstances(1000, 1 * kDeg, 3);
  size_t i = 0;
  TriangleAngleMeasurement m;
  for (auto _ : state) {
    const Instance& in = instances[i++ % instances.size()];
    TriangleAngleInput input;
    input.roll_rad = in.truth.roll;
    input.pitch_rad = in.truth.pitch;
    input.xy = in.input.xy;
    input.R_B_C = in.input.T_B_C.R();
    input.bearing_sigma_rad = 1 * kDeg;
    benchmark::DoNotOptimize(MeasureTriangleAngles(input, &m));
  }
}
BENCHMARK(BM_TriangleAngleMeasurement)->Unit(benchmark::kNanosecond);

void BM_GravityEkfPerImuSample(benchmark::State& state) {
  Rng rng(4);
  std::vector<ImuSample> imu(1000);
  for (auto& s : imu) {
    s.gyro_rad_s = rng.Gaussian3(0.02);
    s.accel_m_s2 = Eigen::Vector3d(0, 0, 9.81) + rng.Gaussian3(0.01);
  }
  GravityEkf ekf{GravityEkfOptions{}};
  ekf.Initialize(imu[0].accel_m_s2);
  size_t i = 0;
  for (auto _ : state) {
    const ImuSample& s = imu[i++ % imu.size()];
    ekf.Propagate(s.gyro_rad_s, 0.01);
    ekf.Update(s.accel_m_s2, 0.01);
    benchmark::DoNotOptimize(ekf.state());
  }
}
BENCHMARK(BM_GravityEkfPerImuSample)->Unit(benchmark::kNanosecond);

}  // namespace
}  // namespace mavloc
