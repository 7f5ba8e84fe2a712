// Gravity EKF (three-point paper, sect. IV): analytic Jacobians against central differences, roll
// and pitch on a motionless hover and through a rotation, and covariance consistency (NEES).
#include "solver/attitude/gravity_ekf.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/random.h"
#include "core/rotation.h"
#include "tests/test_support.h"

namespace mavloc {
namespace {

constexpr double kDt = 0.01;  // 100 Hz, as in the paper's simulation

// The paper's IMU: sigma_gyro = 1 deg/s and sigma_acc = 0.01 m/s^2 per sample at 100 Hz.
constexpr double kSigmaGyro = 1.0 * kDeg;
constexpr double kSigmaAcc = 0.01;

GravityEkfOptions PaperOptions() {
  GravityEkfOptions options;
  options.gyro_noise_density_rad_s_sqrt_hz = DensityFromDiscreteSigma(kSigmaGyro, kDt);
  options.accel_noise_density_m_s2_sqrt_hz = DensityFromDiscreteSigma(kSigmaAcc, kDt);
  return options;
}

// IMU samples of a vehicle that does not move (attitude R_W_B), with the paper's noise.
std::vector<ImuSample> StaticImu(const Eigen::Matrix3d& R_W_B, double duration_s,
                                 const Eigen::Vector3d& gyro_bias, uint64_t seed) {
  Rng rng(seed);
  std::vector<ImuSample> imu;
  const int n = static_cast<int>(std::lround(duration_s / kDt)) + 1;
  for (int k = 0; k < n; ++k) {
    ImuSample s;
    s.t_ns = SecondsToNs(k * kDt);
    s.gyro_rad_s = gyro_bias + rng.Gaussian3(kSigmaGyro);
    s.accel_m_s2 = R_W_B.transpose() * (-GravityW()) + rng.Gaussian3(kSigmaAcc);
    imu.push_back(s);
  }
  return imu;
}

TEST(GravityEkfJacobians, PropagationMatchesCentralDifferences) {
  Rng rng(11);
  for (int trial = 0; trial < 20; ++trial) {
    GravityEkf::State x;
    x.head<3>() = rng.Gaussian3(5.0) + Eigen::Vector3d(0, 0, -9.81);
    x.tail<3>() = rng.Gaussian3(0.05);
    const Eigen::Vector3d w_m = rng.Gaussian3(1.5);
    const double dt = rng.Uniform(0.002, 0.05);
    Eigen::Matrix<double, 6, 6> F;
    Eigen::Matrix<double, 6, 3> G;
    GravityEkf::PropagationJacobians(x, w_m, dt, &F, &G);

    const Eigen::MatrixXd F_num = testing::CentralDifferenceJacobian(
        [&](const Eigen::VectorXd& xv) -> Eigen::VectorXd {
          return GravityEkf::PropagateMean(GravityEkf::State(xv), w_m, dt);
        },
        Eigen::VectorXd(x));
    // The gyro noise enters as w = w_m - b_g - n_g.
    const Eigen::MatrixXd G_num = testing::CentralDifferenceJacobian(
        [&](const Eigen::VectorXd& n) -> Eigen::VectorXd {
          return GravityEkf::PropagateMean(x, w_m - Eigen::Vector3d(n), dt);
        },
        Eigen::VectorXd(Eigen::Vector3d::Zero()));
    EXPECT_LT((F - F_num).cwiseAbs().maxCoeff(), 1e-7) << "F\n" << F << "\nnum\n" << F_num;
    EXPECT_LT((G - G_num).cwiseAbs().maxCoeff(), 1e-7) << "G\n" << G << "\nnum\n" << G_num;
  }
}

TEST(GravityEkfJacobians, RollPitchFromGravityMatchesCentralDifferences) {
  Rng rng(12);
  for (int trial = 0; trial < 20; ++trial) {
    const EulerRpy rpy{rng.Uniform(-1.2, 1.2), rng.Uniform(-1.2, 1.2), rng.Uniform(-3, 3)};
    const Eigen::Vector3d g_B = RotationFromEuler(rpy).transpose() * GravityW();
    Eigen::Matrix<double, 2, 3> J;
    const Eigen::Vector2d rp = GravityEkf::RollPitchFromGravity(g_B, &J);
    EXPECT_NEAR(rp.x(), rpy.roll, 1e-12);
    EXPECT_NEAR(rp.y(), rpy.pitch, 1e-12);
    const Eigen::MatrixXd J_num = testing::CentralDifferenceJacobian(
        [](const Eigen::VectorXd& g) -> Eigen::VectorXd {
          return GravityEkf::RollPitchFromGravity(Eigen::Vector3d(g));
        },
        Eigen::VectorXd(g_B));
    EXPECT_LT((J - J_num).cwiseAbs().maxCoeff(), 1e-8);
  }
}

TEST(GravityEkf, MotionlessHoverIsWithinATenthOfADegreeAfterOneSecond) {
  // Several seeds and attitudes: every one must meet the bound (no averaging over seeds).
  for (uint64_t seed = 1; seed <= 8; ++seed) {
    Rng rng(100 + seed);
    const EulerRpy truth{rng.Uniform(-10, 10) * kDeg, rng.Uniform(-10, 10) * kDeg,
                         rng.Uniform(-3, 3)};
    const auto imu = StaticImu(RotationFromEuler(truth), 1.5, Eigen::Vector3d::Zero(), seed);
    const auto estimates = EstimateRollPitch(imu, PaperOptions());
    ASSERT_EQ(estimates.size(), imu.size());
    for (size_t k = 0; k < estimates.size(); ++k) {
      if (NsToSeconds(estimates[k].t_ns) < 1.0) continue;
      EXPECT_LT(std::abs(estimates[k].roll_rad - truth.roll), 0.1 * kDeg) << "seed " << seed;
      EXPECT_LT(std::abs(estimates[k].pitch_rad - truth.pitch), 0.1 * kDeg) << "seed " << seed;
    }
  }
}

TEST(GravityEkf, EstimatesAConstantGyroBiasWhileHovering) {
  const Eigen::Vector3d bias(0.5 * kDeg, -0.8 * kDeg, 0.0);
  const auto imu = StaticImu(RotationFromEuler({2 * kDeg, -3 * kDeg, 0.4}), 30.0, bias, 7);
  GravityEkf ekf(PaperOptions());
  ekf.Initialize(imu[0].accel_m_s2, kDt);
  for (size_t k = 1; k < imu.size(); ++k) {
    ekf.Propagate(imu[k - 1].gyro_rad_s, kDt);
    ekf.Update(imu[k].accel_m_s2, kDt);
  }
  // Level-ish hover: the bias about the vertical is unobservable, the other two converge.
  EXPECT_NEAR(ekf.gyro_bias().x(), bias.x(), 0.1 * kDeg);
  EXPECT_NEAR(ekf.gyro_bias().y(), bias.y(), 0.1 * kDeg);
}

TEST(GravityEkf, TracksRollAndPitchThroughARotation) {
  // The IMU rotates about its own centre (no linear acceleration): roll then pitch sweep 30 deg.
  Rng rng(5);
  std::vector<ImuSample> imu;
  std::vector<EulerRpy> truth;
  const double duration_s = 6.0;
  auto attitude = [](double t) {
    return EulerRpy{0.5 * std::sin(0.8 * t), 0.4 * std::sin(1.1 * t + 0.3), 0.3 * t};
  };
  for (int k = 0; k * kDt <= duration_s; ++k) {
    const double t = k * kDt;
    const Eigen::Matrix3d R = RotationFromEuler(attitude(t));
    // w_B from the derivative of R (central difference of the analytic attitude).
    const double h = 1e-6;
    const Eigen::Matrix3d R_dot =
        (RotationFromEuler(attitude(t + h)) - RotationFromEuler(attitude(t - h))) / (2 * h);
    const Eigen::Vector3d w_B = Vee(R.transpose() * R_dot);
    ImuSample s;
    s.t_ns = SecondsToNs(t);
    s.gyro_rad_s = w_B + rng.Gaussian3(kSigmaGyro);
    s.accel_m_s2 = R.transpose() * (-GravityW()) + rng.Gaussian3(kSigmaAcc);
    imu.push_back(s);
    truth.push_back(attitude(t));
  }
  const auto estimates = EstimateRollPitch(imu, PaperOptions());
  double max_err = 0.0;
  for (size_t k = 100; k < imu.size(); ++k) {
    max_err = std::max({max_err, std::abs(WrapAngle(estimates[k].roll_rad - truth[k].roll)),
                        std::abs(WrapAngle(estimates[k].pitch_rad - truth[k].pitch))});
  }
  EXPECT_LT(max_err, 0.3 * kDeg);
}

TEST(GravityEkf, CovarianceIsConsistentOnAMotionlessHover) {
  // Average NEES of (roll, pitch) at t = 2 s over Monte-Carlo runs: 2 for a consistent filter.
  // With accel_dynamics_sigma = 0 the filter's model is exact for a motionless IMU.
  GravityEkfOptions options = PaperOptions();
  options.accel_dynamics_sigma_m_s2 = 0.0;
  const int runs = 200;
  double nees_sum = 0.0;
  const EulerRpy truth{4 * kDeg, -6 * kDeg, 1.0};
  for (int run = 0; run < runs; ++run) {
    const auto imu = StaticImu(RotationFromEuler(truth), 2.0, Eigen::Vector3d::Zero(), 1000 + run);
    const RollPitchEstimate e = EstimateRollPitch(imu, options).back();
    const Eigen::Vector2d err(e.roll_rad - truth.roll, e.pitch_rad - truth.pitch);
    nees_sum += err.dot(e.covariance_rad2.inverse() * err);
  }
  const double nees = nees_sum / runs;
  // 95% band of the mean of 200 chi-square(2) draws: 2 +- 1.96 * 2 / sqrt(200) = [1.72, 2.28].
  EXPECT_GT(nees, 1.72);
  EXPECT_LT(nees, 2.28);
}

TEST(GravityEkf, OneEstimatePerSampleAndEmptyInput) {
  EXPECT_TRUE(EstimateRollPitch({}, GravityEkfOptions()).empty());
  const auto imu = StaticImu(Eigen::Matrix3d::Identity(), 0.05, Eigen::Vector3d::Zero(), 3);
  const auto estimates = EstimateRollPitch(imu, GravityEkfOptions());
  ASSERT_EQ(estimates.size(), imu.size());
  for (size_t k = 0; k < imu.size(); ++k) EXPECT_EQ(estimates[k].t_ns, imu[k].t_ns);
}

}  // namespace
}  // namespace mavloc
