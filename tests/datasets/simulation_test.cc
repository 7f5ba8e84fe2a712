// The simulator core: spline derivatives, trajectory angular velocity, IMU model, camera
// visibility and noise, and determinism per seed.
#include <gtest/gtest.h>

#include <cmath>

#include "core/random.h"
#include "core/rotation.h"
#include "datasets/simulation/bspline.h"
#include "datasets/simulation/camera_simulator.h"
#include "datasets/simulation/imu_simulator.h"
#include "datasets/simulation/spline_trajectory.h"
#include "tests/test_support.h"

namespace mavloc {
namespace {

std::unique_ptr<SplineTrajectory> RandomTrajectory(uint64_t seed, AttitudeMode mode,
                                                   double duration_s = 10.0) {
  Rng rng(seed);
  std::vector<Waypoint> waypoints;
  for (double t = 0.0; t <= duration_s; t += 1.0) {
    Waypoint w;
    w.t_s = t;
    w.p_W = Eigen::Vector3d{rng.Uniform(-2, 2), rng.Uniform(-2, 2), rng.Uniform(1, 2)};
    w.yaw_rad = rng.Uniform(-M_PI, M_PI);
    w.roll_rad = rng.Uniform(-0.3, 0.3);
    w.pitch_rad = rng.Uniform(-0.3, 0.3);
    waypoints.push_back(w);
  }
  return SplineTrajectory::FromWaypoints(1'000'000'000, waypoints, mode, 0.5);
}

TEST(UniformBSpline, DerivativesMatchCentralDifferences) {
  Rng rng(4);
  Eigen::MatrixXd control(2, 12);
  for (int c = 0; c < control.cols(); ++c) {
    control(0, c) = rng.Gaussian();
    control(1, c) = rng.Gaussian();
  }
  const UniformBSpline spline(5, 0.3, 0.7, control);
  for (double t = 0.5; t < spline.end_time() - 0.2; t += 0.37) {
    for (int r = 1; r <= 4; ++r) {
      const double h = 1e-5;
      const Eigen::VectorXd numeric =
          (spline.Evaluate(t + h, r - 1) - spline.Evaluate(t - h, r - 1)) / (2 * h);
      EXPECT_TRUE(spline.Evaluate(t, r).isApprox(numeric, 1e-5)) << "t=" << t << " r=" << r;
    }
  }
}

TEST(UniformBSpline, RepeatedControlPointsHoldStill) {
  Eigen::MatrixXd control = Eigen::MatrixXd::Constant(3, 6, 2.5);
  const UniformBSpline spline(5, 0.0, 1.0, control);
  EXPECT_TRUE(spline.Evaluate(0.5).isApprox(Eigen::Vector3d::Constant(2.5)));
  EXPECT_NEAR(spline.Evaluate(0.5, 1).norm(), 0.0, 1e-12);
}

class TrajectoryTest : public ::testing::TestWithParam<AttitudeMode> {};

TEST_P(TrajectoryTest, VelocityAndAngularVelocityMatchFiniteDifferences) {
  const auto trajectory = RandomTrajectory(9, GetParam());
  const TimeNs h = 10'000;  // 10 us
  for (TimeNs t = trajectory->start_ns() + 100'000'000; t < trajectory->end_ns() - 100'000'000;
       t += 330'000'000) {
    const auto s = trajectory->At(t);
    const auto sp = trajectory->At(t + h), sm = trajectory->At(t - h);
    const double dt = 2e-9 * h;
    EXPECT_NEAR(((sp.p_W - sm.p_W) / dt - s.v_W).norm(), 0.0, 1e-6);
    EXPECT_NEAR(((sp.v_W - sm.v_W) / dt - s.a_W).norm(), 0.0, 1e-5);
    // w_B = Log(R(t-h)^T R(t+h)) / 2h.
    const Eigen::Vector3d w_numeric = LogQuaternion(sm.q_W_B.conjugate() * sp.q_W_B) / dt;
    EXPECT_NEAR((w_numeric - s.w_B).norm(), 0.0, 1e-6 * std::max(1.0, s.w_B.norm()));
  }
}

TEST_P(TrajectoryTest, QuadrotorThrustAlongBodyZ) {
  if (GetParam() != AttitudeMode::kQuadrotor) GTEST_SKIP() << "flatness holds for kQuadrotor only";
  const auto trajectory = RandomTrajectory(10, GetParam());
  for (TimeNs t = trajectory->start_ns(); t < trajectory->end_ns(); t += 250'000'000) {
    const auto s = trajectory->At(t);
    const Eigen::Vector3d f_B = s.q_W_B.conjugate() * (s.a_W - GravityW());
    EXPECT_NEAR(f_B.x(), 0.0, 1e-9);
    EXPECT_NEAR(f_B.y(), 0.0, 1e-9);
    EXPECT_GT(f_B.z(), 0.0);
  }
}

INSTANTIATE_TEST_SUITE_P(Modes, TrajectoryTest,
                         ::testing::Values(AttitudeMode::kQuadrotor, AttitudeMode::kEuler));

TEST(ImuSimulator, RestingImuReadsPlusG) {
  std::vector<Waypoint> still = {{0.0, {1, 2, 3}, 0.4, 0, 0}, {2.0, {1, 2, 3}, 0.4, 0, 0}};
  const auto trajectory = SplineTrajectory::FromWaypoints(0, still, AttitudeMode::kQuadrotor);
  const auto sim = SimulateImu(*trajectory, {}, 1);
  ASSERT_FALSE(sim.imu.samples.empty());
  for (const auto& s : sim.imu.samples) {
    EXPECT_TRUE(s.accel_m_s2.isApprox(Eigen::Vector3d(0, 0, 9.81), 1e-12));
    EXPECT_NEAR(s.gyro_rad_s.norm(), 0.0, 1e-12);
  }
}

TEST(ImuSimulator, NoiseHasTheStatedDiscreteSigma) {
  std::vector<Waypoint> still = {{0.0, {0, 0, 1}, 0, 0, 0}, {50.0, {0, 0, 1}, 0, 0, 0}};
  const auto trajectory = SplineTrajectory::FromWaypoints(0, still, AttitudeMode::kQuadrotor);
  ImuSimulationOptions options;
  options.rate_hz = 100.0;
  options.noise.gyroscope_noise_density = 0.01;       // sigma_d = 0.1 rad/s
  options.noise.accelerometer_noise_density = 0.002;  // sigma_d = 0.02 m/s^2
  const auto sim = SimulateImu(*trajectory, options, 3);
  double sg = 0, sa = 0;
  for (const auto& s : sim.imu.samples) {
    sg += s.gyro_rad_s.squaredNorm();
    sa += (s.accel_m_s2 - Eigen::Vector3d(0, 0, 9.81)).squaredNorm();
  }
  const double n = 3.0 * sim.imu.samples.size();
  EXPECT_NEAR(std::sqrt(sg / n), 0.1, 0.003);
  EXPECT_NEAR(std::sqrt(sa / n), 0.02, 0.0006);
}

TEST(ImuSimulator, SameSeedSameBytesAndSeedsAreSeparate) {
  const auto trajectory = RandomTrajectory(1, AttitudeMode::kQuadrotor, 3.0);
  ImuSimulationOptions options;
  options.noise = {1e-3, 1e-4, 1e-2, 1e-3};
  options.bias_random_walk = true;
  const auto a = SimulateImu(*trajectory, options, 5);
  const auto b = SimulateImu(*trajectory, options, 5);
  const auto c = SimulateImu(*trajectory, options, 6);
  ASSERT_EQ(a.imu.samples.size(), b.imu.samples.size());
  bool differs = false;
  for (size_t i = 0; i < a.imu.samples.size(); ++i) {
    EXPECT_EQ(a.imu.samples[i].gyro_rad_s, b.imu.samples[i].gyro_rad_s);
    EXPECT_EQ(a.imu.samples[i].accel_m_s2, b.imu.samples[i].accel_m_s2);
    EXPECT_EQ(a.ground_truth[i].b_a, b.ground_truth[i].b_a);
    differs |= a.imu.samples[i].accel_m_s2 != c.imu.samples[i].accel_m_s2;
  }
  EXPECT_TRUE(differs);
}

CameraSensor DownCamera() {
  CameraSensor cam;
  cam.name = "cam0";
  cam.model = CameraModel(640, 480, Eigen::Vector4d(400, 400, 320, 240));
  // Looking down: z_C = -z_B, x_C = x_B, y_C = -y_B.
  Eigen::Matrix3d R_B_C;
  R_B_C << 1, 0, 0, 0, -1, 0, 0, 0, -1;
  cam.T_B_C = Pose(R_B_C, Eigen::Vector3d::Zero());
  return cam;
}

TEST(CameraSimulator, VisibilityAndNoiselessProjection) {
  std::vector<Waypoint> still = {{0.0, {0, 0, 2}, 0, 0, 0}, {1.0, {0, 0, 2}, 0, 0, 0}};
  const auto trajectory = SplineTrajectory::FromWaypoints(0, still, AttitudeMode::kQuadrotor);
  const std::map<int, Eigen::Vector3d> landmarks = {
      {1, {0.5, 0.25, 0.0}},  // below: visible, x_C = 0.5/2, y_C = -0.25/2
      {2, {0.0, 0.0, 3.0}},   // above: behind the camera
      {3, {10.0, 0.0, 0.0}},  // below but outside the image (u = 320 + 400 * 5)
  };
  CameraSimulationOptions options;
  options.rate_hz = 10.0;
  const auto obs = ObservePoints(*trajectory, DownCamera(), landmarks, options, 1);
  ASSERT_FALSE(obs.empty());
  for (const auto& o : obs) {
    EXPECT_EQ(o.landmark_id, 1);
    EXPECT_TRUE(o.xy.isApprox(Eigen::Vector2d(0.25, -0.125), 1e-9));
    EXPECT_TRUE(o.uv.isApprox(Eigen::Vector2d(420.0, 190.0), 1e-6));
  }
}

TEST(CameraSimulator, AngularNoiseHasTheStatedSigma) {
  Rng rng(8);
  const Eigen::Vector3d f = Eigen::Vector3d(0.2, -0.3, 1.0).normalized();
  const double sigma = 1.0 * M_PI / 180.0;
  double sum_sq = 0;
  const int n = 20000;
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d g = PerturbBearing(f, sigma, rng);
    EXPECT_NEAR(g.norm(), 1.0, 1e-12);
    const double angle = std::acos(std::clamp(f.dot(g), -1.0, 1.0));
    sum_sq += angle * angle;
  }
  // The angle is |N(0, sigma)|: its RMS is sigma.
  EXPECT_NEAR(std::sqrt(sum_sq / n), sigma, 0.02 * sigma);
}

TEST(CameraSimulator, PixelNoiseIsSeededSeparately) {
  const auto trajectory = RandomTrajectory(2, AttitudeMode::kQuadrotor, 3.0);
  std::map<int, Eigen::Vector3d> landmarks;
  Rng rng(1);
  for (int i = 0; i < 50; ++i)
    landmarks[i] = Eigen::Vector3d{rng.Uniform(-3, 3), rng.Uniform(-3, 3), 0.0};
  CameraSimulationOptions options;
  options.noise_kind = CameraNoiseKind::kPixel;
  options.noise_sigma = 1.0;
  const auto a = ObservePoints(*trajectory, DownCamera(), landmarks, options, 11);
  const auto b = ObservePoints(*trajectory, DownCamera(), landmarks, options, 11);
  const auto c = ObservePoints(*trajectory, DownCamera(), landmarks, options, 12);
  ASSERT_EQ(a.size(), b.size());
  ASSERT_FALSE(a.empty());
  for (size_t i = 0; i < a.size(); ++i) EXPECT_EQ(a[i].uv, b[i].uv);
  EXPECT_NE(a.front().uv, c.front().uv);
}

}  // namespace
}  // namespace mavloc
