// Tests of the on-manifold IMU preintegration (Forster et al., T-RO 2017): bias Jacobians against
// central differences on the manifold, the propagated covariance against a Monte-Carlo of 1000
// noisy integrations, and noiseless prediction of an analytic trajectory.
#include "solver/smoother/imu_preintegration.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/pose.h"
#include "core/random.h"
#include "core/rotation.h"
#include "tests/analytic_motion.h"
#include "tests/test_support.h"

namespace mavloc {
namespace {

using testing::AnalyticMotion;

ImuKeyframeState StateAt(double t) {
  ImuKeyframeState s;
  s.q_W_B = QuaternionFromEuler(AnalyticMotion::Angles(t));
  s.p_W = AnalyticMotion::Position(t);
  s.v_W = AnalyticMotion::Velocity(t);
  return s;
}

std::vector<ImuSample> SimulateSamples(double rate_hz, double duration_s, const ImuBiases& biases) {
  return testing::SimulateAnalyticImu(rate_hz, duration_s, biases);
}

ImuNoise TestNoise() {
  ImuNoise noise;
  noise.gyroscope_noise_density = 1.7e-3;
  noise.accelerometer_noise_density = 2.0e-2;
  noise.gyroscope_random_walk = 2e-5;
  noise.accelerometer_random_walk = 3e-3;
  return noise;
}

// [Log(dR_ref^T dR); dv - dv_ref; dp - dp_ref]
Eigen::VectorXd PreintegrationMinus(const ImuPreintegration& a, const Eigen::Quaterniond& q_ref,
                                    const Eigen::Vector3d& v_ref, const Eigen::Vector3d& p_ref) {
  Eigen::VectorXd r(9);
  r << LogQuaternion(q_ref.conjugate() * a.delta_q()), a.delta_v() - v_ref, a.delta_p() - p_ref;
  return r;
}

TEST(ImuPreintegration, BiasJacobiansMatchCentralDifferences) {
  const std::vector<ImuSample> samples = SimulateSamples(200.0, 3.0, ImuBiases{});
  ImuBiases b0;
  b0.b_g = Eigen::Vector3d(0.01, -0.02, 0.015);
  b0.b_a = Eigen::Vector3d(-0.1, 0.05, 0.2);
  // Keyframe times off the sample grid.
  const TimeNs t_i = SecondsToNs(0.5123), t_j = SecondsToNs(1.4871);
  const ImuPreintegration pre(samples, t_i, t_j, b0, TestNoise());

  // f(delta) = preintegration at b0 + delta, expressed on the manifold around the b0 result.
  auto f = [&](const Eigen::VectorXd& delta) {
    ImuBiases b = b0;
    b.b_g += delta.head<3>();
    b.b_a += delta.tail<3>();
    const ImuPreintegration other(samples, t_i, t_j, b, TestNoise());
    return PreintegrationMinus(other, pre.delta_q(), pre.delta_v(), pre.delta_p());
  };
  auto minus = [](const Eigen::VectorXd& a, const Eigen::VectorXd& b) -> Eigen::VectorXd {
    return a - b;
  };
  const Eigen::MatrixXd J_numeric = testing::CentralDifferenceJacobian(f, 6, minus, 1e-5);

  Eigen::Matrix<double, 9, 6> J_analytic = Eigen::Matrix<double, 9, 6>::Zero();
  J_analytic.block<3, 3>(0, 0) = pre.J_R_bg();
  J_analytic.block<3, 3>(3, 0) = pre.J_v_bg();
  J_analytic.block<3, 3>(3, 3) = pre.J_v_ba();
  J_analytic.block<3, 3>(6, 0) = pre.J_p_bg();
  J_analytic.block<3, 3>(6, 3) = pre.J_p_ba();
  EXPECT_LT((J_numeric - J_analytic).cwiseAbs().maxCoeff(),
            1e-7 * (1.0 + J_analytic.cwiseAbs().maxCoeff()))
      << "numeric\n"
      << J_numeric << "\nanalytic\n"
      << J_analytic;
  // The Jacobians are not trivial: over ~1 s they are of order dt and dt^2/2.
  EXPECT_GT(pre.J_R_bg().norm(), 0.5);
  EXPECT_GT(pre.J_p_ba().norm(), 0.3);

  // First-order correction: the error of the corrected measurement is quadratic in the bias
  // change (halving the change divides it by ~4) and small next to the change itself.
  auto correction_errors = [&](double scale) {
    ImuBiases b1 = b0;
    b1.b_g += scale * Eigen::Vector3d(2e-3, -1e-3, 1.5e-3);
    b1.b_a += scale * Eigen::Vector3d(2e-2, 1e-2, -3e-2);
    const ImuPreintegration exact(samples, t_i, t_j, b1, TestNoise());
    return Eigen::Vector4d(RotationAngleBetween(pre.CorrectedDeltaQ(b1), exact.delta_q()),
                           (pre.CorrectedDeltaV(b1) - exact.delta_v()).norm(),
                           (pre.CorrectedDeltaP(b1) - exact.delta_p()).norm(),
                           (pre.delta_p() - exact.delta_p()).norm());
  };
  const Eigen::Vector4d full = correction_errors(1.0), half = correction_errors(0.5);
  for (int k = 0; k < 3; ++k) {
    EXPECT_LT(half[k], 0.3 * full[k]) << k;
    EXPECT_GT(half[k], 0.2 * full[k]) << k;
  }
  EXPECT_LT(full[2], 2e-3 * full[3]);
}

TEST(ImuPreintegration, NoiselessPredictionFollowsTheTrajectory) {
  ImuBiases biases;
  biases.b_g = Eigen::Vector3d(0.02, -0.01, 0.005);
  biases.b_a = Eigen::Vector3d(0.1, -0.2, 0.05);
  for (const double rate_hz : {100.0, 200.0}) {
    const std::vector<ImuSample> samples = SimulateSamples(rate_hz, 6.0, biases);
    for (const auto& [t_i_s, t_j_s] :
         {std::pair{0.2037, 0.3037}, std::pair{1.0, 2.0}, std::pair{0.5, 5.5}}) {
      const ImuPreintegration pre(samples, SecondsToNs(t_i_s), SecondsToNs(t_j_s), biases,
                                  ImuNoise{});
      ImuKeyframeState state_i = StateAt(t_i_s);
      state_i.biases = biases;
      const ImuKeyframeState predicted = pre.Predict(state_i);
      const ImuKeyframeState truth = StateAt(t_j_s);
      const double horizon = t_j_s - t_i_s;
      SCOPED_TRACE(::testing::Message() << rate_hz << " Hz, " << t_i_s << " .. " << t_j_s << " s");
      EXPECT_LT(RotationAngleBetween(predicted.q_W_B, truth.q_W_B), 1e-8 * horizon);
      EXPECT_LT((predicted.v_W - truth.v_W).norm(), 1e-7 * horizon);
      EXPECT_LT((predicted.p_W - truth.p_W).norm(), 1e-7 * horizon * horizon);
    }
  }
}

TEST(ImuPreintegration, CovarianceMatchesMonteCarlo) {
  const double rate_hz = 200.0;
  const std::vector<ImuSample> clean = SimulateSamples(rate_hz, 1.2, ImuBiases{});
  const ImuNoise noise = TestNoise();
  const TimeNs t_i = SecondsToNs(0.1), t_j = SecondsToNs(1.1);
  const ImuPreintegration nominal(clean, t_i, t_j, ImuBiases{}, noise);

  const double dt = 1.0 / rate_hz;
  const double sigma_g = DiscreteSigma(noise.gyroscope_noise_density, dt);
  const double sigma_a = DiscreteSigma(noise.accelerometer_noise_density, dt);
  Rng rng(20170101);
  const int runs = 1000;
  std::vector<Eigen::VectorXd> errors;
  Eigen::VectorXd mean = Eigen::VectorXd::Zero(9);
  for (int run = 0; run < runs; ++run) {
    std::vector<ImuSample> noisy = clean;
    for (auto& s : noisy) {
      s.gyro_rad_s += rng.Gaussian3(sigma_g);
      s.accel_m_s2 += rng.Gaussian3(sigma_a);
    }
    const ImuPreintegration pre(noisy, t_i, t_j, ImuBiases{}, noise);
    errors.push_back(
        PreintegrationMinus(pre, nominal.delta_q(), nominal.delta_v(), nominal.delta_p()));
    mean += errors.back() / runs;
  }
  Eigen::MatrixXd sample_cov = Eigen::MatrixXd::Zero(9, 9);
  for (const auto& e : errors) sample_cov += (e - mean) * (e - mean).transpose() / (runs - 1);

  // Whiten the Monte-Carlo covariance with the predicted one: it should be the identity up to the
  // sampling error (standard deviation ~ 1/sqrt(1000) = 0.03 per entry, 0.045 on the diagonal).
  const Eigen::Matrix<double, 9, 9> L = nominal.SqrtInformation(0.0, 0.0, 0.0);
  const Eigen::MatrixXd whitened = L * sample_cov * L.transpose();
  EXPECT_LT((whitened - Eigen::MatrixXd::Identity(9, 9)).cwiseAbs().maxCoeff(), 0.16)
      << "whitened Monte-Carlo covariance\n"
      << whitened;
  // The predicted position variance is of the order of sigma_a^2 T^3 / 3.
  EXPECT_GT(nominal.covariance()(6, 6),
            0.1 * noise.accelerometer_noise_density * noise.accelerometer_noise_density / 3.0);
}

TEST(ImuPreintegration, ZeroNoiseGivesZeroCovarianceAndFiniteFlooredInformation) {
  const std::vector<ImuSample> samples = SimulateSamples(100.0, 1.0, ImuBiases{});
  const ImuPreintegration pre(samples, SecondsToNs(0.1), SecondsToNs(0.2), ImuBiases{}, ImuNoise{});
  EXPECT_EQ(pre.covariance().norm(), 0.0);
  const Eigen::Matrix<double, 9, 9> L = pre.SqrtInformation(1e-6, 1e-6, 1e-6);
  EXPECT_TRUE(L.allFinite());
  EXPECT_NEAR(L(0, 0), 1e6, 1.0);
  EXPECT_EQ(pre.num_steps(), 10);
}

}  // namespace
}  // namespace mavloc
