// The smoother's calibration on the aprilgrid-calibration scenario:
// a stereo rig waved before a board map tilted to gravity, with a known T_B_C per camera and a
// known camera-IMU time offset.
// - noiseless data (no pixel noise, no IMU noise, no biases), the dataset's T_B_C moved by 2 cm
//   and 2 deg, t_d started at 0 (truth 5 ms): T_B_C of both cameras, t_d, the board tilt and the
//   trajectory return to 1e-6 (m, rad, s);
// - noisy data, 5 seeds of 8 s here (the 20-seed check is the same code with
//   MAVLOC_CALIBRATION_SEEDS=20, see docs/smoother-and-calibration.md): each of the 6 components of
//   each T_B_C and t_d lie within their 3-sigma bounds in at least 90 % of the runs (all but
//   ceil(10 %): 18 of 20, 4 of 5), and the counts are printed;
// - the board tilt alone (no calibration options) on a board map, cam1-only data seeded by the
//   built-in tags1 PnP, and the reported statistics (reprojection RMS, down-weighted corners).
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>

#include "core/board_frame.h"
#include "core/rotation.h"
#include "datasets/scenarios/aprilgrid_calibration.h"
#include "datasets/scenarios/scenario.h"
#include "solver/estimators/smoother_estimator.h"

namespace mavloc {
namespace {

Dataset Simulate(uint64_t seed, double duration_s, std::map<std::string, std::string> settings) {
  ScenarioOptions options;
  options.seed = seed;
  options.duration_s = duration_s;
  options.settings = std::move(settings);
  return GenerateAprilgridCalibration(options);
}

// The ground-truth row nearest to t.
const GroundTruthState& TruthAt(const Dataset& dataset, TimeNs t_ns) {
  auto it = std::lower_bound(dataset.ground_truth.begin(), dataset.ground_truth.end(), t_ns,
                             [](const GroundTruthState& s, TimeNs t) { return s.t_ns < t; });
  if (it == dataset.ground_truth.end()) return dataset.ground_truth.back();
  if (it != dataset.ground_truth.begin() &&
      std::abs(std::prev(it)->t_ns - t_ns) < std::abs(it->t_ns - t_ns))
    return *std::prev(it);
  return *it;
}

// [p_est - p_true; Log(R_true^T R_est)]: the error in the convention of the covariance.
Eigen::Matrix<double, 6, 1> ExtrinsicError(const Pose& estimate, const Pose& truth) {
  Eigen::Matrix<double, 6, 1> e;
  e.head<3>() = estimate.p - truth.p;
  e.tail<3>() = LogQuaternion(truth.q.conjugate() * estimate.q);
  return e;
}

struct PoseErrors {
  double max_position_m = 0.0;
  double max_rotation_rad = 0.0;
};

PoseErrors TrajectoryErrors(const Dataset& dataset, const Estimate& estimate) {
  PoseErrors e;
  for (const auto& pose : estimate.poses) {
    const GroundTruthState& gt = TruthAt(dataset, pose.t_ns);
    if (std::abs(gt.t_ns - pose.t_ns) > 1000) continue;
    e.max_position_m = std::max(e.max_position_m, (pose.T_W_B.p - gt.T_W_B.p).norm());
    e.max_rotation_rad =
        std::max(e.max_rotation_rad, RotationAngleBetween(pose.T_W_B.q, gt.T_W_B.q));
  }
  return e;
}

TEST(SmootherCalibration, NoiselessDataReturnTheTruth) {
  const Dataset dataset = Simulate(3, 8.0,
                                   {{"pixel_noise_px", "0"},
                                    {"imu_noise", "0"},
                                    {"bias", "0"},
                                    {"extrinsics_error_m", "0.02"},
                                    {"extrinsics_error_deg", "2"}});
  const auto truth = AprilgridCalibrationTruthOf(dataset);
  ASSERT_TRUE(truth.has_value());
  ASSERT_EQ(dataset.cameras.size(), 2u);
  // What the dataset states is 2 cm and 2 deg off.
  EXPECT_NEAR(ExtrinsicError(dataset.cameras[0].T_B_C, truth->T_B_C[0]).head<3>().norm(), 0.02,
              1e-12);

  SmootherEstimator smoother(EstimatorOptions(
      {{"estimate_extrinsics", "1"}, {"estimate_time_offset", "1"}, {"max_iterations", "100"}}));
  const auto t0 = std::chrono::steady_clock::now();
  const Estimate estimate = smoother.Run(dataset);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  ASSERT_FALSE(estimate.poses.empty()) << smoother.last_result().message;
  const SmootherStatistics& st = smoother.last_result().statistics;
  std::printf(
      "noiseless 8 s: %zu keyframes, %d corner residuals, %d iterations in %d solves, %.2f s "
      "(Ceres %.2f s, of which linear solver %.2f s, Jacobians %.2f s; covariance %.2f s; "
      "preintegration %.2f s)\n",
      estimate.poses.size(), st.num_visual_residuals, st.iterations, st.solves, seconds, st.solve_s,
      st.linear_solver_s, st.jacobian_evaluation_s, st.covariance_s, st.preintegration_s);
  for (int c = 0; c < 2; ++c) {
    const std::string name = "cam" + std::to_string(c);
    ASSERT_TRUE(estimate.extrinsics.count(name)) << name;
    const auto e = ExtrinsicError(estimate.extrinsics.at(name).T_B_C, truth->T_B_C[c]);
    std::printf("%s T_B_C error: %.3g m, %.3g rad\n", name.c_str(), e.head<3>().norm(),
                e.tail<3>().norm());
    EXPECT_LT(e.head<3>().norm(), 1e-6) << name;
    EXPECT_LT(e.tail<3>().norm(), 1e-6) << name;
  }
  ASSERT_TRUE(estimate.parameters.count("time_offset"));
  const double t_d = estimate.parameters.at("time_offset").value;
  std::printf("t_d error: %.3g s\n", t_d - truth->time_offset_s);
  EXPECT_NEAR(t_d, truth->time_offset_s, 1e-6);

  ASSERT_TRUE(estimate.T_W_M.has_value());
  const Eigen::Vector3d up = UpInBoard(estimate.T_W_M->R());
  const Eigen::Vector3d up_true = truth->up_M.normalized();
  const double tilt_error = std::atan2(up.cross(up_true).norm(), up.dot(up_true));
  std::printf("tilt error: %.3g rad\n", tilt_error);
  EXPECT_LT(tilt_error, 1e-6);
  // T_W_M is the canonical W of that tilt, so the trajectory compares with the truth directly.
  EXPECT_LT(RotationAngleBetween(estimate.T_W_M->q,
                                 Eigen::Quaterniond(BoardToWorldRotation(truth->up_M))),
            1e-6);
  const PoseErrors errors = TrajectoryErrors(dataset, estimate);
  std::printf("trajectory: max %.3g m, %.3g rad\n", errors.max_position_m, errors.max_rotation_rad);
  EXPECT_LT(errors.max_position_m, 1e-6);
  EXPECT_LT(errors.max_rotation_rad, 1e-6);
  ASSERT_TRUE(estimate.parameters.count("reprojection_rms"));
  EXPECT_LT(estimate.parameters.at("reprojection_rms").value, 1e-4);
  EXPECT_EQ(estimate.parameters.at("downweighted_corners").value, 0.0);
}

int CoverageSeeds() {
  const char* text = std::getenv("MAVLOC_CALIBRATION_SEEDS");
  const int n = text ? std::atoi(text) : 5;
  return std::clamp(n, 1, 200);
}

TEST(SmootherCalibration, EstimatesLieWithinTheirThreeSigmaBounds) {
  const int runs = CoverageSeeds();
  const double duration_s = 8.0;
  // inside[c][k]: runs where component k of cam c's T_B_C is within 3 sigma; offset likewise.
  int inside[2][6] = {};
  int offset_inside = 0;
  double total_s = 0.0;
  for (int run = 0; run < runs; ++run) {
    const Dataset dataset = Simulate(
        100 + run, duration_s, {{"extrinsics_error_m", "0.01"}, {"extrinsics_error_deg", "1"}});
    const auto truth = AprilgridCalibrationTruthOf(dataset);
    ASSERT_TRUE(truth.has_value());
    SmootherEstimator smoother(
        EstimatorOptions({{"estimate_extrinsics", "1"}, {"estimate_time_offset", "1"}}));
    const auto t0 = std::chrono::steady_clock::now();
    const Estimate estimate = smoother.Run(dataset);
    const double run_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    total_s += run_s;
    const SmootherStatistics& st = smoother.last_result().statistics;
    std::printf("seed %d: %.2f s (Ceres %.2f s, %d iterations; covariance %.2f s)\n", 100 + run,
                run_s, st.solve_s, st.iterations, st.covariance_s);
    ASSERT_FALSE(estimate.poses.empty()) << "seed " << 100 + run;
    for (int c = 0; c < 2; ++c) {
      const auto& extrinsic = estimate.extrinsics.at("cam" + std::to_string(c));
      ASSERT_TRUE(extrinsic.covariance.has_value());
      const auto e = ExtrinsicError(extrinsic.T_B_C, truth->T_B_C[c]);
      std::printf("  cam%d error / sigma:", c);
      for (int k = 0; k < 6; ++k) {
        const double normalized = e[k] / std::sqrt((*extrinsic.covariance)(k, k));
        std::printf(" %+.2f", normalized);
        if (std::abs(normalized) <= 3.0) ++inside[c][k];
      }
      std::printf("\n");
    }
    const EstimatedParameter& t_d = estimate.parameters.at("time_offset");
    ASSERT_TRUE(t_d.sigma.has_value());
    if (std::abs(t_d.value - truth->time_offset_s) <= 3.0 * *t_d.sigma) ++offset_inside;
    if (run == 0) {
      const auto& cov0 = *estimate.extrinsics.at("cam0").covariance;
      std::printf(
          "seed 100: sigma cam0 p %.2g %.2g %.2g m, theta %.2g %.2g %.2g rad; t_d %.4g +- "
          "%.2g s; reprojection RMS %.3f px, %g corners down-weighted\n",
          std::sqrt(cov0(0, 0)), std::sqrt(cov0(1, 1)), std::sqrt(cov0(2, 2)),
          std::sqrt(cov0(3, 3)), std::sqrt(cov0(4, 4)), std::sqrt(cov0(5, 5)), t_d.value,
          *t_d.sigma, estimate.parameters.at("reprojection_rms").value,
          estimate.parameters.at("downweighted_corners").value);
    }
  }
  // At most 10 % of the runs outside, rounded up to whole runs: 18 of 20, 4 of 5.
  const int needed = runs - static_cast<int>(std::ceil(0.1 * runs));
  for (int c = 0; c < 2; ++c) {
    std::printf("cam%d T_B_C within 3 sigma (px py pz tx ty tz) of %d runs:", c, runs);
    for (int k = 0; k < 6; ++k) std::printf(" %d", inside[c][k]);
    std::printf("\n");
    for (int k = 0; k < 6; ++k) EXPECT_GE(inside[c][k], needed) << "cam" << c << " component " << k;
  }
  std::printf("t_d within 3 sigma: %d of %d runs; smoother %.2f s per %.0f s run\n", offset_inside,
              runs, total_s / runs, duration_s);
  EXPECT_GE(offset_inside, needed);
}

TEST(SmootherCalibration, BoardTiltWithoutCalibrationOptions) {
  // No time offset here: an unmodelled offset biases the tilt (5 ms: 0.16 deg of roll, 7 sigma).
  const Dataset dataset = Simulate(7, 6.0, {{"time_offset_ms", "0"}});
  const auto truth = AprilgridCalibrationTruthOf(dataset);
  ASSERT_TRUE(truth.has_value());
  SmootherEstimator smoother(EstimatorOptions{});
  const Estimate estimate = smoother.Run(dataset);
  ASSERT_FALSE(estimate.poses.empty()) << smoother.last_result().message;
  // Tilt reported three ways: T_W_M, the parameters with sigmas, the constant quantities.
  ASSERT_TRUE(estimate.T_W_M.has_value());
  ASSERT_TRUE(estimate.parameters.count("board_roll") && estimate.parameters.count("board_pitch"));
  const BoardTilt true_tilt = BoardTiltFromUp(truth->up_M);
  const EstimatedParameter& roll = estimate.parameters.at("board_roll");
  const EstimatedParameter& pitch = estimate.parameters.at("board_pitch");
  ASSERT_TRUE(roll.sigma && pitch.sigma);
  std::printf("board roll %.4f +- %.4f deg (truth %.4f), pitch %.4f +- %.4f deg (truth %.4f)\n",
              roll.value / kDeg, *roll.sigma / kDeg, true_tilt.roll_rad / kDeg, pitch.value / kDeg,
              *pitch.sigma / kDeg, true_tilt.pitch_rad / kDeg);
  EXPECT_LT(std::abs(roll.value - true_tilt.roll_rad), 4.0 * *roll.sigma + 1e-4);
  EXPECT_LT(std::abs(pitch.value - true_tilt.pitch_rad), 4.0 * *pitch.sigma + 1e-4);
  EXPECT_LT(*roll.sigma, 0.05 * kDeg);
  const int i_roll = estimate.quantities.Index("board_roll");
  ASSERT_GE(i_roll, 0);
  EXPECT_DOUBLE_EQ(estimate.quantities.rows.front()[i_roll], roll.value);
  EXPECT_DOUBLE_EQ(estimate.quantities.rows.back()[i_roll], roll.value);
  // Without the calibration options nothing else is reported as estimated.
  EXPECT_TRUE(estimate.extrinsics.empty());
  EXPECT_FALSE(estimate.parameters.count("time_offset"));
  // Millimetres and hundredths of a degree; the corners' RMS is the noise's (0.3 px per axis:
  // 0.42 px in norm).
  const PoseErrors errors = TrajectoryErrors(dataset, estimate);
  EXPECT_LT(errors.max_position_m, 0.005);
  EXPECT_LT(errors.max_rotation_rad, 0.1 * kDeg);
  ASSERT_TRUE(estimate.parameters.count("reprojection_rms"));
  EXPECT_NEAR(estimate.parameters.at("reprojection_rms").value, 0.3 * std::sqrt(2.0), 0.03);
}

TEST(SmootherCalibration, Cam1OnlyIsSeededFromTags1) {
  const Dataset dataset = Simulate(11, 6.0, {{"time_offset_ms", "0"}});
  SmootherEstimator smoother(EstimatorOptions({{"cameras", "cam1"}, {"estimate_extrinsics", "1"}}));
  EXPECT_EQ(smoother.SeedEstimatorFor(dataset), "tag-pnp-cam1");
  const Estimate estimate = smoother.Run(dataset);
  ASSERT_FALSE(estimate.poses.empty()) << smoother.last_result().message;
  EXPECT_TRUE(estimate.extrinsics.count("cam1"));
  EXPECT_FALSE(estimate.extrinsics.count("cam0"));
  const auto truth = AprilgridCalibrationTruthOf(dataset);
  const auto e = ExtrinsicError(estimate.extrinsics.at("cam1").T_B_C, truth->T_B_C[1]);
  EXPECT_LT(e.head<3>().norm(), 0.01);
  EXPECT_LT(e.tail<3>().norm(), 0.5 * kDeg);
  const PoseErrors errors = TrajectoryErrors(dataset, estimate);
  EXPECT_LT(errors.max_position_m, 0.01);
  EXPECT_LT(errors.max_rotation_rad, 0.2 * kDeg);
  // Bad option text is an input error.
  EXPECT_THROW(
      SmootherEstimator(EstimatorOptions(std::map<std::string, std::string>{{"cameras", "cam2"}})),
      std::exception);
  EXPECT_THROW(SmootherEstimator(EstimatorOptions(
                   std::map<std::string, std::string>{{"max_time_offset_ms", "0"}})),
               std::exception);
}

}  // namespace
}  // namespace mavloc
