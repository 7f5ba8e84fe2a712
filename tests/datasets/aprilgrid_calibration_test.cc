// Scenario aprilgrid-calibration: a board map tilted to gravity, a stereo rig with EuRoC's
// cameras, corners seen at stamp + t_d, what the dataset states vs the truth, an IMU consistent
// with the ground truth, and an excited calibration motion.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <string>

#include "core/board_frame.h"
#include "core/errors.h"
#include "core/rotation.h"
#include "core/tag_geometry.h"
#include "datasets/scenarios/aprilgrid_calibration.h"
#include "datasets/scenarios/scenario.h"

namespace mavloc {
namespace {

Dataset Simulate(uint64_t seed, double duration_s, std::map<std::string, std::string> settings) {
  ScenarioOptions options;
  options.seed = seed;
  options.duration_s = duration_s;
  options.settings = std::move(settings);
  return GenerateAprilgridCalibration(options);
}

// The truth pose at an exact ground-truth stamp.
const GroundTruthState* TruthAt(const Dataset& d, TimeNs t_ns) {
  auto it = std::lower_bound(d.ground_truth.begin(), d.ground_truth.end(), t_ns,
                             [](const GroundTruthState& s, TimeNs t) { return s.t_ns < t; });
  return it != d.ground_truth.end() && it->t_ns == t_ns ? &*it : nullptr;
}

TEST(AprilgridCalibrationScenario, BoardMapCamerasAndStatedTruth) {
  const Dataset d = Simulate(1, 5.0, {});
  ASSERT_NE(FindScenario("aprilgrid-calibration"), nullptr);
  EXPECT_EQ(d.map.frame, MapFrame::kBoard);
  EXPECT_EQ(d.map.tags.size(), 36u);
  ASSERT_EQ(d.cameras.size(), 2u);
  EXPECT_EQ(d.cameras[0].name, "cam0");
  EXPECT_EQ(d.cameras[1].name, "cam1");
  EXPECT_DOUBLE_EQ(d.cameras[1].model.fu(), 457.587);
  EXPECT_EQ(d.cameras[0].frames.size(), d.cameras[1].frames.size());
  EXPECT_NEAR(d.cameras[0].rate_hz, 20.0, 1e-12);
  EXPECT_NEAR(d.imu.rate_hz, 200.0, 1e-12);
  EXPECT_FALSE(d.tags.empty());
  EXPECT_FALSE(d.tags1.empty());
  for (const auto& obs : d.tags) EXPECT_EQ(obs.camera, 0);
  for (const auto& obs : d.tags1) EXPECT_EQ(obs.camera, 1);

  const auto truth = AprilgridCalibrationTruthOf(d);
  ASSERT_TRUE(truth.has_value());
  EXPECT_NEAR(truth->time_offset_s, 0.005, 1e-15);
  for (int c = 0; c < 2; ++c) {
    // Without extrinsics_error the dataset states the truth: EuRoC's T_BS.
    EXPECT_LT((truth->T_B_C[c].p - EurocCameraExtrinsic(c).p).norm(), 1e-15);
    EXPECT_LT((d.cameras[c].T_B_C.p - truth->T_B_C[c].p).norm(), 1e-15);
    EXPECT_LT(RotationAngleBetween(d.cameras[c].T_B_C.q, truth->T_B_C[c].q), 1e-12);
  }
  EXPECT_NEAR(EurocCameraExtrinsic(0).p.x(), -0.0216401454975, 1e-15);
  // The board is tilted as set (roll 95 deg, pitch 10 deg), and the truth quantities say so.
  const BoardTilt tilt = BoardTiltFromUp(truth->up_M);
  EXPECT_NEAR(tilt.roll_rad, 95.0 * kDeg, 1e-9);
  EXPECT_NEAR(tilt.pitch_rad, 10.0 * kDeg, 1e-9);
  const int i_roll = d.truth_quantities.Index("board_roll");
  ASSERT_GE(i_roll, 0);
  EXPECT_NEAR(d.truth_quantities.rows.front()[i_roll], tilt.roll_rad, 1e-12);
  // Stated extrinsics can be moved away from the truth by exactly the set amounts.
  const Dataset moved =
      Simulate(1, 5.0, {{"extrinsics_error_m", "0.02"}, {"extrinsics_error_deg", "3"}});
  for (int c = 0; c < 2; ++c) {
    EXPECT_NEAR((moved.cameras[c].T_B_C.p - truth->T_B_C[c].p).norm(), 0.02, 1e-12);
    EXPECT_NEAR(RotationAngleBetween(moved.cameras[c].T_B_C.q, truth->T_B_C[c].q), 3.0 * kDeg,
                1e-9);
  }
}

TEST(AprilgridCalibrationScenario, CornersAreSeenAtStampPlusTimeOffset) {
  const Dataset d = Simulate(2, 4.0, {{"pixel_noise_px", "0"}, {"time_offset_ms", "10"}});
  const auto truth = AprilgridCalibrationTruthOf(d);
  ASSERT_TRUE(truth.has_value());
  const Pose T_W_M = BoardToWorld(truth->up_M);
  double worst_at_exposure = 0.0, mean_at_stamp = 0.0;
  int n = 0;
  for (int c = 0; c < 2; ++c) {
    for (const TagObservation& obs : c == 0 ? d.tags : d.tags1) {
      // Ground truth has a row every 5 ms: the stamp and the exposure (stamp + 10 ms) are rows.
      const GroundTruthState* at_stamp = TruthAt(d, obs.t_ns);
      const GroundTruthState* at_exposure = TruthAt(d, obs.t_ns + SecondsToNs(0.01));
      if (!at_stamp || !at_exposure) continue;
      const auto corners_M = TagCornersInWorld(d.map.tags.at(obs.tag_id));
      for (int k = 0; k < 4; ++k) {
        const Eigen::Vector3d p_W = T_W_M * corners_M[k];
        const auto uv_exposure =
            d.cameras[c].model.Project((at_exposure->T_W_B * truth->T_B_C[c]).Inverse() * p_W);
        const auto uv_stamp =
            d.cameras[c].model.Project((at_stamp->T_W_B * truth->T_B_C[c]).Inverse() * p_W);
        ASSERT_TRUE(uv_exposure && uv_stamp);
        worst_at_exposure = std::max(worst_at_exposure, (*uv_exposure - obs.corners_px[k]).norm());
        mean_at_stamp += (*uv_stamp - obs.corners_px[k]).norm();
        ++n;
      }
    }
  }
  ASSERT_GT(n, 1000);
  EXPECT_LT(worst_at_exposure, 1e-9);
  // At the stamp the corners are off by the image motion over 10 ms: pixels.
  EXPECT_GT(mean_at_stamp / n, 0.5);
}

TEST(AprilgridCalibrationScenario, ImuAgreesWithTheGroundTruthAndTheMotionIsExcited) {
  const Dataset d = Simulate(4, 12.0, {{"imu_noise", "0"}, {"bias", "0"}});
  const auto truth = AprilgridCalibrationTruthOf(d);
  ASSERT_TRUE(truth.has_value());
  ASSERT_EQ(d.imu.samples.size(), d.ground_truth.size());
  const auto& gt = d.ground_truth;
  const double dt = 0.005;
  double worst_gyro = 0.0, worst_accel = 0.0, worst_velocity = 0.0;
  for (size_t k = 1; k + 1 < gt.size(); ++k) {
    // Central differences of the ground truth against the IMU and the velocity column.
    const Eigen::Vector3d w =
        LogQuaternion(gt[k - 1].T_W_B.q.conjugate() * gt[k + 1].T_W_B.q) / (2.0 * dt);
    const Eigen::Vector3d v = (gt[k + 1].T_W_B.p - gt[k - 1].T_W_B.p) / (2.0 * dt);
    const Eigen::Vector3d a = (gt[k + 1].v_W - gt[k - 1].v_W) / (2.0 * dt);
    const Eigen::Vector3d f = gt[k].T_W_B.q.conjugate() * (a - GravityW());
    worst_gyro = std::max(worst_gyro, (w - d.imu.samples[k].gyro_rad_s).norm());
    worst_velocity = std::max(worst_velocity, (v - gt[k].v_W).norm());
    worst_accel = std::max(worst_accel, (f - d.imu.samples[k].accel_m_s2).norm());
  }
  // O(dt^2) differences of motions with rates of a few rad/s and m/s^2.
  EXPECT_LT(worst_gyro, 2e-3);
  EXPECT_LT(worst_velocity, 2e-3);
  EXPECT_LT(worst_accel, 2e-2);

  // Excitation: cam0 between 0.55 and 1.25 m from the board, turned by more than 15 deg about
  // each of its axes, the body turning fast about each axis; most frames see many tags.
  const Pose T_M_W = BoardToWorld(truth->up_M).Inverse();
  double min_distance = 1e9, max_distance = 0.0;
  Eigen::Vector3d max_angle = Eigen::Vector3d::Zero(), max_rate = Eigen::Vector3d::Zero();
  for (size_t k = 0; k < gt.size(); ++k) {
    const Pose T_M_C = T_M_W * gt[k].T_W_B * truth->T_B_C[0];
    min_distance = std::min(min_distance, T_M_C.p.z());
    max_distance = std::max(max_distance, T_M_C.p.z());
    const EulerRpy rpy = EulerFromRotation(Rx(M_PI).transpose() * T_M_C.R());
    max_angle = max_angle.cwiseMax(
        Eigen::Vector3d(std::abs(rpy.roll), std::abs(rpy.pitch), std::abs(rpy.yaw)));
    max_rate = max_rate.cwiseMax(d.imu.samples[k].gyro_rad_s.cwiseAbs());
  }
  EXPECT_GT(min_distance, 0.55);
  EXPECT_LT(max_distance, 1.25);
  for (int i = 0; i < 3; ++i) {
    EXPECT_GT(max_angle[i], 15.0 * kDeg) << i;
    EXPECT_LT(max_angle[i], 31.0 * kDeg) << i;
    EXPECT_GT(max_rate[i], 0.5) << i;
  }
  std::map<TimeNs, int> tags_per_frame;
  for (const auto& obs : d.tags) ++tags_per_frame[obs.t_ns];
  int rich = 0;
  for (const auto& [t, count] : tags_per_frame) rich += count >= 8;
  EXPECT_GT(rich, 0.9 * static_cast<double>(d.cameras[0].frames.size()));
}

TEST(AprilgridCalibrationScenario, DeterministicAndValidated) {
  const Dataset a = Simulate(9, 3.0, {});
  const Dataset b = Simulate(9, 3.0, {});
  ASSERT_EQ(a.tags.size(), b.tags.size());
  for (size_t i = 0; i < a.tags.size(); ++i)
    EXPECT_EQ(a.tags[i].corners_px[2], b.tags[i].corners_px[2]);
  EXPECT_EQ(a.imu.samples.back().accel_m_s2, b.imu.samples.back().accel_m_s2);
  const Dataset mono = Simulate(9, 3.0, {{"stereo", "0"}});
  EXPECT_EQ(mono.cameras.size(), 1u);
  EXPECT_TRUE(mono.tags1.empty());
  EXPECT_THROW(Simulate(1, 3.0, {{"no_such_setting", "1"}}), InputError);
  EXPECT_THROW(Simulate(1, 3.0, {{"time_offset_ms", "80"}}), InputError);
  EXPECT_THROW(Simulate(1, 3.0, {{"distance_m", "0.3"}, {"distance_amplitude_m", "0.2"}}),
               InputError);
  EXPECT_THROW(Simulate(1, 1.0, {}), InputError);
}

}  // namespace
}  // namespace mavloc
