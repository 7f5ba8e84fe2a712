// Camera-laser calibration of appendix A, both directions.
#include "solver/laser/laser_calibration.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/random.h"
#include "core/rotation.h"

namespace mavloc {
namespace {

TEST(LaserCalibration, PaperValuesGiveL0100) {
  // Section 5.3: theta = 47.1 deg, phi = -3.1 deg, Lx = -0.146 m, Ly = -0.005 m -> L = 0.100 m.
  const LaserCalibration paper{-0.146, -0.005, 47.1 * kDeg, -3.1 * kDeg};
  const ChosenLaserFrame frame = ChosenFrameFromCalibration(paper);
  EXPECT_NEAR(frame.L_m, 0.100, 0.0005);
}

TEST(LaserCalibration, ChosenFramePutsTheBeamAtL00AlongZ) {
  Rng rng(5);
  for (int trial = 0; trial < 500; ++trial) {
    const LaserCalibration c{rng.Uniform(-0.3, 0.3), rng.Uniform(-0.3, 0.3),
                             rng.Uniform(0.0, 80.0) * kDeg, rng.Uniform(-180.0, 180.0) * kDeg};
    const ChosenLaserFrame frame = ChosenFrameFromCalibration(c);
    const LaserBeam beam = BeamFromCalibration(c);
    const Eigen::Quaterniond q_Cp_C = frame.q_C_Cp.conjugate();
    // The beam direction becomes z; every beam point has x = L, y = 0 in C'.
    EXPECT_NEAR((q_Cp_C * beam.direction_C - Eigen::Vector3d::UnitZ()).norm(), 0.0, 1e-12);
    for (double s : {0.0, 0.5, 2.0}) {
      const Eigen::Vector3d point_Cp = q_Cp_C * (beam.origin_C + s * beam.direction_C);
      EXPECT_NEAR(point_Cp.x(), frame.L_m, 1e-12);
      EXPECT_NEAR(point_Cp.y(), 0.0, 1e-12);
    }
    EXPECT_GE(frame.L_m, 0.0);
  }
}

TEST(LaserCalibration, LaserAlongTheOpticalAxisIsIdentity) {
  const ChosenLaserFrame frame = ChosenFrameFromCalibration({0.3, 0.0, 0.0, 0.0});
  EXPECT_NEAR(frame.L_m, 0.3, 1e-15);
  EXPECT_NEAR(frame.q_C_Cp.angularDistance(Eigen::Quaterniond::Identity()), 0.0, 1e-12);
}

// The spots of a beam on several known planes (a checkerboard at several poses): the camera sees
// the spot, intersects its ray with the board plane, and the line fit recovers the calibration.
std::vector<Eigen::Vector3d> SpotsOnBoards(const LaserCalibration& truth, int count,
                                           double bearing_noise_rad, Rng& rng) {
  const LaserBeam beam = BeamFromCalibration(truth);
  std::vector<Eigen::Vector3d> spots;
  while (static_cast<int>(spots.size()) < count) {
    // A board 0.5 .. 3 m away, tilted up to 30 deg, with normal roughly facing the camera.
    const double tilt_x_rad = rng.Uniform(-0.5, 0.5), tilt_y_rad = rng.Uniform(-0.5, 0.5);
    const Eigen::Vector3d normal_C = Rx(tilt_x_rad) * Ry(tilt_y_rad) * Eigen::Vector3d(0, 0, -1);
    const Plane board_C{normal_C, normal_C.dot(Eigen::Vector3d(0, 0, rng.Uniform(0.5, 3.0)))};
    LaserSpot spot;
    if (ProjectLaserSpot(Pose(), beam, board_C, &spot) != LaserSpotStatus::kOk) continue;
    // The camera measures the spot's bearing (with noise) and intersects it with the board.
    Eigen::Vector2d xy = spot.xy;
    xy.x() = std::tan(std::atan(xy.x()) + rng.Gaussian(0.0, bearing_noise_rad));
    xy.y() = std::tan(std::atan(xy.y()) + rng.Gaussian(0.0, bearing_noise_rad));
    Eigen::Vector3d spot_C;
    if (!SpotOnKnownPlane(xy, board_C, &spot_C)) continue;
    if (bearing_noise_rad == 0.0) {
      EXPECT_NEAR((spot_C - spot.p_C).norm(), 0.0, 1e-9);
    }
    spots.push_back(spot_C);
  }
  return spots;
}

TEST(LaserCalibration, TwoSpotsRecoverTheParametersExactly) {
  Rng rng(17);
  for (int trial = 0; trial < 100; ++trial) {
    const LaserCalibration truth{rng.Uniform(-0.2, 0.2), rng.Uniform(-0.2, 0.2),
                                 rng.Uniform(5.0, 60.0) * kDeg, rng.Uniform(-170.0, 170.0) * kDeg};
    const auto spots = SpotsOnBoards(truth, 2, 0.0, rng);
    LaserCalibration estimate;
    ASSERT_EQ(EstimateLaserCalibration(spots, &estimate), LaserCalibrationStatus::kOk);
    EXPECT_NEAR(estimate.Lx_m, truth.Lx_m, 1e-8);
    EXPECT_NEAR(estimate.Ly_m, truth.Ly_m, 1e-8);
    EXPECT_NEAR(estimate.theta_rad, truth.theta_rad, 1e-8);
    EXPECT_NEAR(WrapAngle(estimate.phi_rad - truth.phi_rad), 0.0, 1e-8);
  }
}

TEST(LaserCalibration, LineFitOverManyNoisySpotsIsAccurate) {
  Rng rng(23);
  const LaserCalibration truth{-0.146, -0.005, 47.1 * kDeg, -3.1 * kDeg};
  const auto spots = SpotsOnBoards(truth, 40, 0.05 * kDeg, rng);
  LaserCalibration estimate;
  ASSERT_EQ(EstimateLaserCalibration(spots, &estimate), LaserCalibrationStatus::kOk);
  EXPECT_NEAR(estimate.Lx_m, truth.Lx_m, 0.005);
  EXPECT_NEAR(estimate.Ly_m, truth.Ly_m, 0.005);
  EXPECT_NEAR(estimate.theta_rad, truth.theta_rad, 0.5 * kDeg);
  EXPECT_NEAR(estimate.phi_rad, truth.phi_rad, 0.5 * kDeg);
  EXPECT_NEAR(ChosenFrameFromCalibration(estimate).L_m, 0.100, 0.005);
}

TEST(LaserCalibration, DegenerateInputsAreReported) {
  LaserCalibration estimate;
  EXPECT_EQ(EstimateLaserCalibration({}, &estimate), LaserCalibrationStatus::kTooFewSpots);
  EXPECT_EQ(EstimateLaserCalibration({Eigen::Vector3d(0, 0, 1)}, &estimate),
            LaserCalibrationStatus::kTooFewSpots);
  EXPECT_EQ(
      EstimateLaserCalibration({Eigen::Vector3d(0, 0, 1), Eigen::Vector3d(0, 0, 1)}, &estimate),
      LaserCalibrationStatus::kSpotsCoincident);
  EXPECT_EQ(
      EstimateLaserCalibration({Eigen::Vector3d(0, 0, 1), Eigen::Vector3d(1, 0, 1)}, &estimate),
      LaserCalibrationStatus::kBeamParallelToImagePlane);
  Eigen::Vector3d spot;
  EXPECT_FALSE(SpotOnKnownPlane({0, 0}, Plane{Eigen::Vector3d::UnitX(), 1.0}, &spot));   // parallel
  EXPECT_FALSE(SpotOnKnownPlane({0, 0}, Plane{Eigen::Vector3d::UnitZ(), -1.0}, &spot));  // behind
}

TEST(LaserCalibration, ObservationInTheChosenFrameFollowsEquation11) {
  // The general model with the paper's calibrated beam, read in the chosen frame, is eq. (11).
  Rng rng(29);
  const LaserCalibration c{-0.146, -0.005, 47.1 * kDeg, -3.1 * kDeg};
  const ChosenLaserFrame frame = ChosenFrameFromCalibration(c);
  const LaserBeam beam = BeamFromCalibration(c);
  int checked = 0;
  for (int trial = 0; trial < 1000; ++trial) {
    const Plane plane{rng.GaussianVector<3>().normalized(), rng.Uniform(-1, 1)};
    const Eigen::Quaterniond q_W_C = Eigen::Quaterniond(rng.GaussianVector<4>()).normalized();
    const Pose T_W_C{q_W_C, Eigen::Vector3d{rng.Uniform(-1, 1), rng.Uniform(-1, 1), 0}};
    LaserSpot spot;
    if (ProjectLaserSpot(T_W_C, beam, plane, &spot) != LaserSpotStatus::kOk) continue;
    const Eigen::Vector3d bearing_Cp = frame.q_C_Cp.conjugate() * spot.p_C;
    const Pose T_W_Cp(q_W_C * frame.q_C_Cp, T_W_C.p);
    const LaserModes modes = ModesFromPose(T_W_Cp, Eigen::Vector3d::Zero(), plane, GravityW());
    EXPECT_NEAR(bearing_Cp.x() / bearing_Cp.z(),
                PaperObservationEq11(modes.m, frame.L_m, modes.xi_sign), 1e-9);
    EXPECT_NEAR(bearing_Cp.y() / bearing_Cp.z(), 0.0, 1e-9);
    ++checked;
  }
  EXPECT_GT(checked, 100);
}

}  // namespace
}  // namespace mavloc
