// The AprilTag paper's 15-state EKF (solver/tag_ekf/tag_ekf.h): 1-2-3 Euler angles, every analytic
// Jacobian (F, G, H, d rpy / d alpha) against central differences, the delayed-measurement update
// of Fig. 3-4 against the same update applied without delay, and convergence on a circle flight
// with noisy tag poses.
#include "solver/tag_ekf/tag_ekf.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/random.h"
#include "tests/test_support.h"

namespace mavloc {
namespace {

using testing::CentralDifferenceJacobian;

TagEkfVector RandomState(Rng& rng) {
  TagEkfVector x;
  for (int i = 0; i < 15; ++i) x[i] = rng.Uniform(-1.0, 1.0);
  x.segment<3>(kTagEkfAtt) =
      Eigen::Vector3d{rng.Uniform(-0.6, 0.6), rng.Uniform(-0.6, 0.6), rng.Uniform(-3.0, 3.0)};
  x.segment<3>(kTagEkfAccelBias) *= 0.2;
  x.segment<3>(kTagEkfGyroBias) *= 0.05;
  return x;
}

// A down-looking camera: x_C = -y_B, y_C = -x_B, z_C = -z_B, 5 cm ahead of the IMU.
Pose DownCamera() {
  Eigen::Matrix3d R_B_C;
  R_B_C << 0, -1, 0, -1, 0, 0, 0, 0, -1;
  return Pose(R_B_C, Eigen::Vector3d(0.05, 0.01, -0.03));
}

TEST(Euler123, RoundTripAndRateMatrix) {
  Rng rng(11);
  for (int trial = 0; trial < 50; ++trial) {
    const Eigen::Vector3d alpha{rng.Uniform(-3, 3), rng.Uniform(-1.4, 1.4), rng.Uniform(-3, 3)};
    const Eigen::Matrix3d R = RotationFromEuler123(alpha);
    EXPECT_LT((RotationFromEuler123(Euler123FromRotation(R)) - R).norm(), 1e-12);
    // R(alpha + d) = R(alpha) Exp(Gamma d): Gamma's columns from central differences of Log.
    const Eigen::MatrixXd J = CentralDifferenceJacobian(
        [&](const Eigen::VectorXd& d) -> Eigen::VectorXd {
          return LogSO3(R.transpose() * RotationFromEuler123(alpha + d));
        },
        alpha * 0.0 + Eigen::Vector3d::Zero());
    EXPECT_LT((J - Euler123RateMatrix(alpha)).norm(), 1e-7) << alpha.transpose();
    // d(rpy)/d(alpha).
    const Eigen::MatrixXd J_rpy = CentralDifferenceJacobian(
        [&](const Eigen::VectorXd& a) -> Eigen::VectorXd {
          const EulerRpy rpy = RpyFromEuler123(a);
          return Eigen::Vector3d(rpy.roll, rpy.pitch, rpy.yaw);
        },
        alpha);
    // Skip the yaw wrap (finite differences across +-pi).
    const EulerRpy rpy = RpyFromEuler123(alpha);
    if (std::abs(std::abs(rpy.yaw) - M_PI) > 1e-3 && std::abs(std::abs(rpy.roll) - M_PI) > 1e-3) {
      EXPECT_LT((J_rpy - RpyJacobianWrtEuler123(alpha)).norm(), 1e-6) << alpha.transpose();
    }
  }
}

TEST(Euler123, SmallTiltsAreRotatedByYawInRollPitchYaw) {
  // Rx(a1) Ry(a2) Rz(a3) = Rz(a3) (I + [Rz(a3)^T (a1, a2, 0)]x) to first order in a1, a2: the
  // paper's first two angles are tilts about the ground axes, mavloc's roll and pitch tilts about
  // the yawed axes, so the conversion matters as soon as the yaw is not zero.
  const double a1 = 0.01, a2 = -0.02, a3 = 0.9;
  const EulerRpy rpy = RpyFromEuler123(Eigen::Vector3d(a1, a2, a3));
  EXPECT_NEAR(rpy.yaw, a3, 1e-3);
  EXPECT_NEAR(rpy.roll, std::cos(a3) * a1 + std::sin(a3) * a2, 1e-3);
  EXPECT_NEAR(rpy.pitch, -std::sin(a3) * a1 + std::cos(a3) * a2, 1e-3);
  EXPECT_GT(std::abs(rpy.roll - a1), 5e-3);
}

TEST(TagEkfJacobians, DynamicsAndNoiseMatchCentralDifferences) {
  Rng rng(3);
  for (int trial = 0; trial < 30; ++trial) {
    const TagEkfVector x = RandomState(rng);
    TagEkfInput u;
    u.accel_m_s2 = Eigen::Vector3d{rng.Uniform(-3, 3), rng.Uniform(-3, 3), rng.Uniform(5, 13)};
    u.gyro_rad_s = Eigen::Vector3d{rng.Uniform(-2, 2), rng.Uniform(-2, 2), rng.Uniform(-2, 2)};
    const Eigen::MatrixXd F_num = CentralDifferenceJacobian(
        [&](const Eigen::VectorXd& xx) -> Eigen::VectorXd {
          return TagEkfDynamics(TagEkfVector(xx), u);
        },
        x);
    EXPECT_LT((F_num - TagEkfDynamicsJacobian(x, u)).cwiseAbs().maxCoeff(), 1e-6);
    // G: f with the noise w = (n_a, n_g, n_ba, n_bg) entering as in eq. (1).
    const Eigen::MatrixXd G_num = CentralDifferenceJacobian(
        [&](const Eigen::VectorXd& w) -> Eigen::VectorXd {
          TagEkfInput noisy = u;
          noisy.accel_m_s2 -= w.segment<3>(0);
          noisy.gyro_rad_s -= w.segment<3>(3);
          TagEkfVector f = TagEkfDynamics(x, noisy);
          f.segment<3>(kTagEkfAccelBias) += w.segment<3>(6);
          f.segment<3>(kTagEkfGyroBias) += w.segment<3>(9);
          return f;
        },
        Eigen::VectorXd::Zero(12));
    EXPECT_LT((G_num - TagEkfNoiseMatrix(x)).cwiseAbs().maxCoeff(), 1e-6);
  }
}

TEST(TagEkfJacobians, MeasurementMatchesCentralDifferences) {
  Rng rng(5);
  const Pose T_B_C = DownCamera();
  int checked = 0;
  for (int trial = 0; trial < 40; ++trial) {
    const TagEkfVector x = RandomState(rng);
    const Pose T_W_T{RotationFromEuler123(Eigen::Vector3d{
                         rng.Uniform(-0.3, 0.3), rng.Uniform(-0.3, 0.3), rng.Uniform(-3, 3)}),
                     Eigen::Vector3d{rng.Uniform(-2, 2), rng.Uniform(-2, 2), 0.0}};
    const TagMeasurementVector h0 = TagMeasurementModel(x, T_B_C, T_W_T);
    if (std::abs(std::cos(h0[4])) < 0.05) continue;  // gamma near gimbal lock: skip
    const Eigen::MatrixXd H_num = CentralDifferenceJacobian(
        [&](const Eigen::VectorXd& d) -> Eigen::VectorXd {
          return TagMeasurementModel(TagEkfVector(x + d), T_B_C, T_W_T);
        },
        15,
        [](const Eigen::VectorXd& a, const Eigen::VectorXd& b) -> Eigen::VectorXd {
          Eigen::VectorXd diff = a - b;
          for (int i = 3; i < 6; ++i) diff[i] = WrapAngle(diff[i]);
          return diff;
        });
    EXPECT_LT((H_num - TagMeasurementModelJacobian(x, T_B_C, T_W_T)).cwiseAbs().maxCoeff(), 1e-6);
    ++checked;
  }
  EXPECT_GT(checked, 30);
}

TEST(TagEkfModel, MeasurementOfTruthIsTheRelativePose) {
  const Pose T_B_C = DownCamera();
  TagEkfVector x = TagEkfVector::Zero();
  x.segment<3>(kTagEkfPos) = Eigen::Vector3d(0.2, -0.1, 1.0);
  x.segment<3>(kTagEkfAtt) = Eigen::Vector3d(0.05, -0.03, 0.7);
  const Pose T_W_T(Eigen::Matrix3d(Rz(0.4)), Eigen::Vector3d(0.5, 0.3, 0.0));
  const Pose T_W_B(RotationFromEuler123(x.segment<3>(kTagEkfAtt)), Eigen::Vector3d(0.2, -0.1, 1.0));
  const Pose T_C_T = (T_W_B * T_B_C).Inverse() * T_W_T;
  const TagMeasurementVector h = TagMeasurementModel(x, T_B_C, T_W_T);
  EXPECT_LT((h.head<3>() - T_C_T.p).norm(), 1e-12);
  EXPECT_LT((RotationFromEuler123(h.tail<3>()) - T_C_T.R()).norm(), 1e-12);
  EXPECT_GT(T_C_T.p.z(), 0.5);  // the tag is in front of the down-looking camera
}

// A level circle flight with analytic IMU signals (no noise): p = (Rc cos wt, Rc sin wt, h),
// yaw = wt + pi/2 (flying forward), so w_B = (0, 0, w) and a_m = R_W_B^T (a_W - g_W).
struct CircleFlight {
  double radius = 1.0, omega = 0.8, height = 1.0;
  TagEkfVector State(double t) const {
    TagEkfVector x = TagEkfVector::Zero();
    x.segment<3>(kTagEkfPos) =
        Eigen::Vector3d(radius * std::cos(omega * t), radius * std::sin(omega * t), height);
    x.segment<3>(kTagEkfVel) =
        radius * omega * Eigen::Vector3d(-std::sin(omega * t), std::cos(omega * t), 0.0);
    x.segment<3>(kTagEkfAtt) = Eigen::Vector3d(0.0, 0.0, WrapAngle(omega * t + M_PI / 2));
    return x;
  }
  ImuSample Imu(TimeNs t_ns) const {
    const double t = NsToSeconds(t_ns);
    const Eigen::Vector3d a_W =
        -radius * omega * omega * Eigen::Vector3d(std::cos(omega * t), std::sin(omega * t), 0.0);
    const Eigen::Matrix3d R_W_B = RotationFromEuler123(State(t).segment<3>(kTagEkfAtt));
    ImuSample s;
    s.t_ns = t_ns;
    s.accel_m_s2 = R_W_B.transpose() * (a_W - GravityW());
    s.gyro_rad_s = Eigen::Vector3d(0.0, 0.0, omega);
    return s;
  }
};

std::map<int, TagInfo> FloorTags() {
  std::map<int, TagInfo> tags;
  int id = 0;
  for (int i = -2; i <= 2; ++i) {
    for (int j = -2; j <= 2; ++j) {
      TagInfo tag;
      tag.id = id++;
      tag.size_m = 0.16;
      tag.T_W_T = Pose(Eigen::Matrix3d(Rz(0.3 * i)), Eigen::Vector3d(0.6 * i, 0.6 * j, 0.0));
      tags[tag.id] = tag;
    }
  }
  return tags;
}

// Tags within 0.8 m horizontally of the vehicle, as noisy T_C_T (position sigma_p, angle sigma_a).
std::vector<TagPoseMeasurement> MeasureTags(const TagEkfVector& x_true,
                                            const std::map<int, TagInfo>& tags, double sigma_p,
                                            double sigma_a, Rng& rng) {
  const Pose T_W_B(RotationFromEuler123(x_true.segment<3>(kTagEkfAtt)),
                   Eigen::Vector3d(x_true.segment<3>(kTagEkfPos)));
  const Pose T_C_W = (T_W_B * DownCamera()).Inverse();
  std::vector<TagPoseMeasurement> out;
  for (const auto& [id, tag] : tags) {
    if ((tag.T_W_T.p - T_W_B.p).head<2>().norm() > 0.8) continue;
    Pose T_C_T = T_C_W * tag.T_W_T;
    T_C_T.p += rng.Gaussian3(sigma_p);
    T_C_T.q = T_C_T.q * ExpQuaternion(rng.Gaussian3(sigma_a));
    out.push_back({id, T_C_T});
  }
  return out;
}

TEST(TagEkf, NoiselessPredictionFollowsTheCircle) {
  const CircleFlight flight;
  TagEkf ekf(TagEkfOptions{}, DownCamera(), FloorTags());
  ekf.Initialize(flight.Imu(0), flight.State(0.0), TagEkfMatrix::Identity() * 1e-6);
  const TimeNs dt = 10'000'000;
  for (TimeNs t = dt; t <= 5 * kNsPerSecond; t += dt) ekf.Propagate(flight.Imu(t));
  const TagEkfVector truth = flight.State(5.0);
  EXPECT_LT((ekf.state().head<3>() - truth.head<3>()).norm(), 1e-4);
  EXPECT_LT(std::abs(WrapAngle(ekf.state()[kTagEkfAtt + 2] - truth[kTagEkfAtt + 2])), 1e-6);
  // Pure prediction: the covariance grows.
  EXPECT_GT(ekf.covariance()(0, 0), 1e-6);
}

TEST(TagEkf, DelayedUpdateEqualsTheUpdateAppliedAtExposureTime) {
  const CircleFlight flight;
  const auto tags = FloorTags();
  TagEkfVector x0 = flight.State(0.0);
  x0.segment<3>(kTagEkfPos) += Eigen::Vector3d(0.2, -0.1, 0.1);
  TagEkfMatrix P0 = TagEkfMatrix::Identity() * 0.01;
  TagEkf on_time(TagEkfOptions{}, DownCamera(), tags);
  TagEkf delayed(TagEkfOptions{}, DownCamera(), tags);
  TagEkfOptions naive_options;
  naive_options.compensate_delay = false;
  TagEkf naive(naive_options, DownCamera(), tags);
  on_time.Initialize(flight.Imu(0), x0, P0);
  delayed.Initialize(flight.Imu(0), x0, P0);
  naive.Initialize(flight.Imu(0), x0, P0);
  Rng rng(9);
  const TimeNs dt = 10'000'000, delay = 70'000'000, exposure_offset = 3'000'000;
  std::vector<std::pair<TimeNs, std::vector<TagPoseMeasurement>>> pending;
  int applied = 0;
  for (TimeNs t = dt; t <= 3 * kNsPerSecond; t += dt) {
    on_time.Propagate(flight.Imu(t));
    delayed.Propagate(flight.Imu(t));
    naive.Propagate(flight.Imu(t));
    // Images every 100 ms, exposed 3 ms after an IMU sample (between samples).
    if (t % (10 * dt) == 0) {
      const TimeNs t_exp = t + exposure_offset;
      auto meas = MeasureTags(flight.State(NsToSeconds(t_exp)), tags, 0.01, 0.05, rng);
      pending.emplace_back(t_exp, meas);
    }
    for (auto it = pending.begin(); it != pending.end();) {
      if (it->first + delay <= t) {
        applied += delayed.Update(it->first, it->second).applied;
        naive.Update(it->first, it->second);
        it = pending.erase(it);
      } else {
        ++it;
      }
    }
    // The reference filter sees each image at its exposure time: step to t_exp, update, continue.
    // It is emulated by the same delayed machinery with zero delay (updates between samples).
    for (const auto& [t_exp, meas] : pending) {
      if (t_exp > t - dt && t_exp <= t) on_time.Update(t_exp, meas);
    }
  }
  EXPECT_GT(applied, 50);
  // on_time applied each image as soon as its exposure time passed; delayed applied it 70 ms later
  // and re-propagated: the same filter.
  EXPECT_LT((on_time.state() - delayed.state()).norm(), 1e-9);
  EXPECT_LT((on_time.covariance() - delayed.covariance()).norm(), 1e-9);
  // Ignoring the delay is worse: the naive filter is a different (and less accurate) one.
  const TagEkfVector truth = flight.State(3.0);
  const double err_delayed = (delayed.state().head<3>() - truth.head<3>()).norm();
  const double err_naive = (naive.state().head<3>() - truth.head<3>()).norm();
  EXPECT_GT((naive.state() - delayed.state()).norm(), 1e-4);
  EXPECT_LT(err_delayed, err_naive);
}

TEST(TagEkf, TooOldOrFutureMeasurementsAreRefused) {
  const CircleFlight flight;
  TagEkfOptions options;
  options.buffer_s = 0.5;
  TagEkf ekf(options, DownCamera(), FloorTags());
  ekf.Initialize(flight.Imu(0), flight.State(0.0), TagEkfMatrix::Identity() * 0.01);
  for (TimeNs t = 10'000'000; t <= 2 * kNsPerSecond; t += 10'000'000) ekf.Propagate(flight.Imu(t));
  Rng rng(1);
  const auto meas = MeasureTags(flight.State(1.0), FloorTags(), 0.01, 0.05, rng);
  EXPECT_TRUE(ekf.Update(kNsPerSecond, meas).too_old);
  EXPECT_TRUE(ekf.Update(3 * kNsPerSecond, meas).in_future);
  std::vector<TagPoseMeasurement> unknown = {{999, Pose()}};
  EXPECT_EQ(ekf.Update(2 * kNsPerSecond, unknown).unknown_tag, 1);
}

TEST(TagEkf, ConvergesFromHalfAMetreWithNoisyTags) {
  const CircleFlight flight;
  const auto tags = FloorTags();
  Rng rng(21);
  TagEkfVector x0 = flight.State(0.0);
  x0.segment<3>(kTagEkfPos) += Eigen::Vector3d(0.3, -0.3, 0.25);  // 0.49 m
  x0.segment<3>(kTagEkfVel) += Eigen::Vector3d(0.1, 0.1, -0.1);
  x0.segment<3>(kTagEkfAtt) += Eigen::Vector3d(0.03, -0.03, 0.05);
  TagEkfMatrix P0 = TagEkfMatrix::Zero();
  P0.diagonal() << Eigen::Vector3d::Constant(0.1), Eigen::Vector3d::Constant(0.04),
      Eigen::Vector3d::Constant(0.0025), Eigen::Vector3d::Constant(0.01),
      Eigen::Vector3d::Constant(1e-4);
  TagEkf ekf(TagEkfOptions{}, DownCamera(), tags);
  ekf.Initialize(flight.Imu(0), x0, P0);
  const TimeNs dt = 10'000'000;
  for (TimeNs t = dt; t <= 6 * kNsPerSecond; t += dt) {
    ekf.Propagate(flight.Imu(t));
    if (t % (10 * dt) == 0) {
      // Noise as Table I's R: 1 cm, 0.1 rad.
      ekf.Update(t, MeasureTags(flight.State(NsToSeconds(t)), tags, 0.01, 0.1, rng));
    }
  }
  const TagEkfVector truth = flight.State(6.0);
  EXPECT_LT((ekf.state().head<3>() - truth.head<3>()).norm(), 0.03);
  EXPECT_LT((ekf.state().segment<3>(kTagEkfVel) - truth.segment<3>(kTagEkfVel)).norm(), 0.05);
  const Eigen::Vector3d att_err = ekf.state().segment<3>(kTagEkfAtt) - truth.segment<3>(kTagEkfAtt);
  EXPECT_LT(std::abs(WrapAngle(att_err[0])) + std::abs(WrapAngle(att_err[1])) +
                std::abs(WrapAngle(att_err[2])),
            0.05);
}

}  // namespace
}  // namespace mavloc
