// Diagnostics on synthetic trajectories with the fault injected (and without it): a constant
// body-frame rotation offset, a time offset, a wrong scale, and too few associated pairs.
#include "evaluation/trajectory_diagnostics.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/random.h"
#include "core/rotation.h"
#include "evaluation/trajectory_evaluation.h"

namespace mavloc {
namespace {

constexpr double kGyroNoiseDeg = 0.02;

// A smooth flight: a 2 m circle with a bobbing height; yaw, pitch and roll vary so that |omega|
// is not constant (the time-offset search needs a varying rate).
Pose TruthAt(double t) {
  const Eigen::Vector3d p(2.0 * std::cos(0.5 * t), 2.0 * std::sin(0.5 * t),
                          1.0 + 0.3 * std::sin(t));
  EulerRpy rpy;
  rpy.yaw = 0.5 * t + 0.3 * std::sin(1.3 * t);
  rpy.pitch = 0.2 * std::sin(0.7 * t);
  rpy.roll = 0.25 * std::sin(1.1 * t + 0.5);
  return Pose(RotationFromEuler(rpy), p);
}

std::vector<StampedPose> Sample(double rate_hz, double duration_s, double delay_s = 0.0) {
  std::vector<StampedPose> poses;
  const int n = static_cast<int>(duration_s * rate_hz);
  for (int k = 0; k <= n; ++k) {
    const double t = k / rate_hz;
    poses.push_back({SecondsToNs(t), TruthAt(t - delay_s)});
  }
  return poses;
}

// Estimate at 20 Hz: R_est = R_gt R_off, with rotation noise (0.2 deg per axis by default) and
// 1 mm position noise.
std::vector<StampedPose> NoisyEstimate(const Eigen::Matrix3d& R_off, uint64_t seed,
                                       double delay_s = 0.0, double rotation_noise_deg = 0.2) {
  Rng rng(seed);
  std::vector<StampedPose> est = Sample(20.0, 30.0, delay_s);
  for (auto& pose : est) {
    pose.T_W_B.q = Eigen::Quaterniond(pose.T_W_B.R() * R_off *
                                      ExpSO3(rng.Gaussian3(rotation_noise_deg * kDeg)));
    pose.T_W_B.p += rng.Gaussian3(0.001);
  }
  return est;
}

TEST(RotationOffset, CameraFrameMixUpIsFoundAfterSe3Alignment) {
  const Eigen::Vector3d axis = Eigen::Vector3d(1, 1, 0).normalized();
  const Eigen::Matrix3d R_off = ExpSO3(10 * kDeg * axis);
  const auto truth = Sample(200.0, 30.0);
  EvaluationProtocol protocol;  // se3
  const auto r = EvaluateTrajectory(NoisyEstimate(R_off, 1), truth, protocol);
  ASSERT_TRUE(r.has_value());
  const auto& d = r->diagnostics.rotation_offset;
  ASSERT_TRUE(d.evaluated);
  EXPECT_TRUE(d.detected);
  EXPECT_NEAR(d.angle_deg, 10.0, 0.05);
  EXPECT_GT(d.axis.dot(axis), std::cos(1 * kDeg));
  EXPECT_NEAR(d.noise_deg, 0.2 * std::sqrt(3.0), 0.05);  // RMS of a 3-D 0.2 deg noise
  bool said = false;
  for (const auto& m : r->diagnostics.Messages())
    said |= m.find("camera frame") != std::string::npos;
  EXPECT_TRUE(said);
  // The APE rotation shows the 10 deg, which the diagnostic explains.
  EXPECT_NEAR(r->ape_rotation_deg.median, 10.0, 0.5);

  // Without the offset: nothing detected (the mean of the noise is ~0.01 deg).
  const auto clean =
      EvaluateTrajectory(NoisyEstimate(Eigen::Matrix3d::Identity(), 2), truth, protocol);
  ASSERT_TRUE(clean.has_value());
  EXPECT_FALSE(clean->diagnostics.rotation_offset.detected);
  EXPECT_LT(clean->diagnostics.rotation_offset.angle_deg, 0.1);
  EXPECT_TRUE(clean->diagnostics.Messages().empty());
}

TEST(TimeOffset, LateEstimateStampsAreMeasuredFromAngularRates) {
  // Orientation noise 0.02 deg per pose (a VIO's short-term attitude noise): the finite-difference
  // rate noise is then ~0.02 rad/s at 20 Hz, and the shift is resolved to ~2 ms over 30 s.
  // The estimate's pose at stamp t is the truth at t - 0.07 s: its stamps are 70 ms late, so
  // -0.07 s is to be added to them. The estimate period is 50 ms: reported.
  const auto truth = Sample(200.0, 30.0);
  EvaluationProtocol protocol;
  protocol.max_dt_s = 0.01;
  const auto r = EvaluateTrajectory(
      NoisyEstimate(Eigen::Matrix3d::Identity(), 3, 0.07, kGyroNoiseDeg), truth, protocol);
  ASSERT_TRUE(r.has_value());
  const auto& d = r->diagnostics.time_offset;
  ASSERT_TRUE(d.evaluated);
  EXPECT_NEAR(d.estimate_period_s, 0.05, 1e-9);
  EXPECT_NEAR(d.offset_s, -0.07, 0.005);
  EXPECT_GT(d.sigma_s, 0.0);
  EXPECT_LT(d.sigma_s, 0.005);
  EXPECT_TRUE(d.detected);
  EXPECT_LT(d.cost_at_offset, d.cost_at_zero);

  // Corrected by the protocol's offset: the residual is ~0, nothing reported.
  protocol.time_offset_s = -0.07;
  const auto corrected = EvaluateTrajectory(
      NoisyEstimate(Eigen::Matrix3d::Identity(), 3, 0.07, kGyroNoiseDeg), truth, protocol);
  ASSERT_TRUE(corrected.has_value());
  EXPECT_NEAR(corrected->diagnostics.time_offset.offset_s, 0.0, 0.005);
  EXPECT_FALSE(corrected->diagnostics.time_offset.detected);

  // 20 ms late, less than one estimate period: measured but not reported.
  protocol.time_offset_s = 0.0;
  const auto small = EvaluateTrajectory(
      NoisyEstimate(Eigen::Matrix3d::Identity(), 4, 0.02, kGyroNoiseDeg), truth, protocol);
  ASSERT_TRUE(small.has_value());
  EXPECT_NEAR(small->diagnostics.time_offset.offset_s, -0.02, 0.005);
  EXPECT_FALSE(small->diagnostics.time_offset.detected);

  // Ten times the attitude noise (0.2 deg): a 0.3 s offset is still found and reported, with a
  // larger sigma.
  const auto noisy =
      EvaluateTrajectory(NoisyEstimate(Eigen::Matrix3d::Identity(), 6, -0.3), truth, protocol);
  ASSERT_TRUE(noisy.has_value());
  EXPECT_NEAR(noisy->diagnostics.time_offset.offset_s, 0.3, 0.02);
  EXPECT_TRUE(noisy->diagnostics.time_offset.detected);

  // A body-frame rotation offset does not disturb it (|omega| is frame-independent).
  const auto rotated = EvaluateTrajectory(
      NoisyEstimate(ExpSO3(Eigen::Vector3d(0, 0.5, 0)), 5, 0.07, kGyroNoiseDeg), truth, protocol);
  ASSERT_TRUE(rotated.has_value());
  EXPECT_NEAR(rotated->diagnostics.time_offset.offset_s, -0.07, 0.005);
}

TEST(Scale, Sim3ScaleFarFromOneForAMetricEstimator) {
  // Estimate positions 1.3 x the truth: the Sim3 scale is ~1 / 1.3.
  const auto truth = Sample(200.0, 30.0);
  auto est = NoisyEstimate(Eigen::Matrix3d::Identity(), 6);
  for (auto& pose : est) pose.T_W_B.p *= 1.3;
  EvaluationProtocol protocol;
  protocol.alignment = AlignmentMode::kSim3;
  auto r = EvaluateTrajectory(est, truth, protocol);
  ASSERT_TRUE(r.has_value());
  EXPECT_NEAR(r->diagnostics.scale.scale, 1.0 / 1.3, 1e-3);
  EXPECT_TRUE(r->diagnostics.scale.detected);
  protocol.diagnostics.metric_estimator = false;  // monocular: scale is a gauge, not a fault
  EXPECT_FALSE(EvaluateTrajectory(est, truth, protocol)->diagnostics.scale.detected);
  // The same estimate at its true scale: 1 within noise, not reported.
  protocol.diagnostics.metric_estimator = true;
  r = EvaluateTrajectory(NoisyEstimate(Eigen::Matrix3d::Identity(), 6), truth, protocol);
  EXPECT_NEAR(r->diagnostics.scale.scale, 1.0, 1e-3);
  EXPECT_FALSE(r->diagnostics.scale.detected);
  // se3: the scale is not evaluated.
  protocol.alignment = AlignmentMode::kSe3;
  EXPECT_FALSE(EvaluateTrajectory(est, truth, protocol)->diagnostics.scale.evaluated);
}

TEST(PairCount, NoOverlapReportsBothStampRangesAndSpacings) {
  const auto truth = Sample(200.0, 30.0);
  auto est = NoisyEstimate(Eigen::Matrix3d::Identity(), 7);
  for (auto& pose : est) pose.t_ns += 1000 * kNsPerSecond;
  std::string why;
  TrajectoryDiagnostics diagnostics;
  EXPECT_FALSE(
      EvaluateTrajectory(est, truth, EvaluationProtocol{}, &why, &diagnostics).has_value());
  EXPECT_NE(why.find("no estimate stamp"), std::string::npos);
  const auto& d = diagnostics.pair_count;
  EXPECT_TRUE(d.detected);
  EXPECT_EQ(d.pairs, 0u);
  EXPECT_EQ(d.estimate_first_ns, 1000 * kNsPerSecond);
  EXPECT_EQ(d.truth_last_ns, 30 * kNsPerSecond);
  EXPECT_NEAR(d.estimate_median_dt_s, 0.05, 1e-9);
  EXPECT_NEAR(d.truth_median_dt_s, 0.005, 1e-9);
  ASSERT_EQ(diagnostics.Messages().size(), 1u);
  EXPECT_NE(diagnostics.Messages()[0].find("1000.000 .. 1030.000 s"), std::string::npos);
  EXPECT_NE(diagnostics.Messages()[0].find("0.000 .. 30.000 s"), std::string::npos);
}

TEST(PairCount, PartialOverlapIsReportedButEvaluated) {
  // Estimate 20 Hz over 29.5 .. 59.5 s against a truth over 0 .. 30 s: 11 of 601 poses pair.
  const auto truth = Sample(200.0, 30.0);
  auto est = NoisyEstimate(Eigen::Matrix3d::Identity(), 8);
  for (auto& pose : est) pose.t_ns += SecondsToNs(29.5);
  const auto r = EvaluateTrajectory(est, truth, EvaluationProtocol{});
  ASSERT_TRUE(r.has_value());
  EXPECT_EQ(r->pair_count, 11u);
  EXPECT_TRUE(r->diagnostics.pair_count.detected);
  // Full overlap: not reported.
  EXPECT_FALSE(
      EvaluateTrajectory(NoisyEstimate(Eigen::Matrix3d::Identity(), 8), truth, EvaluationProtocol{})
          ->diagnostics.pair_count.detected);
}

}  // namespace
}  // namespace mavloc
