// The general laser-spot model against the paper's special cases, eq. (2)-(3) and (11).
#include "solver/laser/laser_spot_model.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/random.h"
#include "core/rotation.h"

namespace mavloc {
namespace {

Eigen::Quaterniond RandomQuaternion(Rng& rng) {
  return Eigen::Quaterniond(rng.GaussianVector<4>()).normalized();
}

// The paper's global frame: plane z = k y through the origin.
Plane PaperPlane(double k) {
  const double norm = std::sqrt(1.0 + k * k);
  return {Eigen::Vector3d(0.0, -k, 1.0) / norm, 0.0};
}

TEST(LaserSpotModel, MatchesEquations2And3) {
  Rng rng(7);
  const double L = 0.3;
  const LaserBeam beam{Eigen::Vector3d(L, 0, 0), Eigen::Vector3d::UnitZ()};
  int checked = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    const double k = rng.Uniform(-1.5, 1.5);
    const Eigen::Vector3d r{rng.Uniform(-2, 2), rng.Uniform(-2, 2), rng.Uniform(-2, 2)};
    const Eigen::Quaterniond q = RandomQuaternion(rng);
    LaserSpot spot;
    if (ProjectLaserSpot(Pose(q, r), beam, PaperPlane(k), &spot) != LaserSpotStatus::kOk) continue;
    ++checked;
    EXPECT_NEAR(spot.p_C.z(), PaperSpotDepthEq2(r, q, k, L), 1e-9 * (1 + spot.p_C.z()));
    EXPECT_NEAR(spot.p_C.x(), L, 1e-12);
    EXPECT_NEAR(spot.xy.y(), 0.0, 1e-12);
    EXPECT_NEAR(spot.xy.x(), PaperObservationEq3(r, q, k, L), 1e-9 * (1 + std::abs(spot.xy.x())));
  }
  EXPECT_GT(checked, 500);
}

TEST(LaserSpotModel, MatchesEquation11InAnyWorldFrame) {
  Rng rng(11);
  const double L = 0.25;
  const LaserBeam beam{Eigen::Vector3d(L, 0, 0), Eigen::Vector3d::UnitZ()};
  int checked = 0, positive = 0, negative = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    const Plane plane{RandomQuaternion(rng) * Eigen::Vector3d::UnitZ(), rng.Uniform(-1, 1)};
    const Pose T_W_C{RandomQuaternion(rng),
                     Eigen::Vector3d{rng.Uniform(-2, 2), rng.Uniform(-2, 2), rng.Uniform(-2, 2)}};
    LaserSpot spot;
    if (ProjectLaserSpot(T_W_C, beam, plane, &spot) != LaserSpotStatus::kOk) continue;
    ++checked;
    const LaserModes modes = ModesFromPose(T_W_C, Eigen::Vector3d::Zero(), plane, GravityW());
    (modes.xi_sign == XiSign::kPositive ? positive : negative)++;
    EXPECT_NEAR(modes.xi, Xi(modes.m[2], modes.m[3], modes.xi_sign), 1e-12);
    EXPECT_NEAR(spot.xy.x(), PaperObservationEq11(modes.m, L, modes.xi_sign),
                1e-9 * (1 + std::abs(spot.xy.x())));
    // The spot is in front of the laser: (m4 L - m1) / xi > 0 (the decomposition rule).
    EXPECT_GT((modes.m[3] * L - modes.m[0]) / modes.xi, 0.0);
  }
  EXPECT_GT(checked, 500);
  EXPECT_GT(positive, 100);  // both local decompositions (eq. 10) occur
  EXPECT_GT(negative, 100);
}

TEST(LaserSpotModel, DegenerateGeometryIsReported) {
  const LaserBeam beam{Eigen::Vector3d(0.3, 0, 0), Eigen::Vector3d::UnitZ()};
  const Plane floor{Eigen::Vector3d::UnitZ(), 0.0};
  LaserSpot spot;
  // Beam horizontal: parallel to the floor.
  const Pose looking_ahead(Eigen::Quaterniond(Ry(M_PI / 2)), Eigen::Vector3d(0, 0, 1));
  EXPECT_EQ(ProjectLaserSpot(looking_ahead, beam, floor, &spot),
            LaserSpotStatus::kBeamParallelToPlane);
  // Camera above the floor looking up: the plane is behind the laser.
  const Pose looking_up(Eigen::Quaterniond::Identity(), Eigen::Vector3d(0, 0, 1));
  EXPECT_EQ(ProjectLaserSpot(looking_up, beam, floor, &spot), LaserSpotStatus::kPlaneBehindLaser);
  // Camera looking up, beam pointing sideways and backwards: the spot is behind the camera.
  const LaserBeam backwards{Eigen::Vector3d(0.3, 0, 0), Eigen::Vector3d(1, 0, -1).normalized()};
  EXPECT_EQ(ProjectLaserSpot(looking_up, backwards, floor, &spot),
            LaserSpotStatus::kSpotBehindCamera);
  const Pose looking_down(Eigen::Quaterniond(Rx(M_PI)), Eigen::Vector3d(0, 0, 1));
  // Looking down works: the spot is 1 m below at x = 0.3.
  ASSERT_EQ(ProjectLaserSpot(looking_down, beam, floor, &spot), LaserSpotStatus::kOk);
  EXPECT_NEAR(spot.p_W.x(), 0.3, 1e-12);
  EXPECT_NEAR(spot.p_W.z(), 0.0, 1e-12);
  EXPECT_NEAR(spot.xy.x(), 0.3, 1e-12);
}

TEST(LaserSpotModel, QuantitiesAreEulerAnglesRelativeToThePlane) {
  Rng rng(3);
  for (int trial = 0; trial < 200; ++trial) {
    const Eigen::Quaterniond q_W_P = RandomQuaternion(rng);
    const Plane plane{q_W_P * Eigen::Vector3d::UnitZ(), 0.4};
    const Pose T_W_C{RandomQuaternion(rng),
                     Eigen::Vector3d{rng.Uniform(-2, 2), rng.Uniform(-2, 2), rng.Uniform(-2, 2)}};
    const Eigen::Vector3d v_W{rng.Gaussian(), rng.Gaussian(), rng.Gaussian()};
    const LaserModes modes = ModesFromPose(T_W_C, v_W, plane, GravityW());
    const LaserQuantities quantities = QuantitiesFromModes(modes.m, modes.xi_sign, 9.81);
    const EulerRpy rpy = EulerFromRotation(q_W_P.toRotationMatrix().transpose() * T_W_C.R());
    EXPECT_NEAR(WrapAngle(quantities.roll_rad - rpy.roll), 0.0, 1e-9);
    EXPECT_NEAR(quantities.pitch_rad, rpy.pitch, 1e-9);
    EXPECT_NEAR(quantities.d_m, std::abs(plane.n_W.dot(T_W_C.p) - plane.d_m), 1e-12);
    EXPECT_NEAR(quantities.v_o_m_s, plane.n_W.dot(v_W), 1e-12);
    const double normal_to_up = std::acos(plane.n_W.z());
    EXPECT_NEAR(quantities.alpha_rad, normal_to_up, 1e-9);
  }
}

TEST(LaserSpotModel, OrientPlaneTowardsPutsThePointOnThePositiveSide) {
  const Plane plane{Eigen::Vector3d(0, 0, 2.0), 1.0};  // z = 0.5, unnormalized
  const Plane below = OrientPlaneTowards(plane, Eigen::Vector3d(0, 0, -1));
  EXPECT_NEAR(below.n_W.z(), -1.0, 1e-12);
  EXPECT_NEAR(below.n_W.dot(Eigen::Vector3d(0, 0, -1)) - below.d_m, 1.5, 1e-12);
  const Plane above = OrientPlaneTowards(plane, Eigen::Vector3d(0, 0, 2));
  EXPECT_NEAR(above.n_W.z(), 1.0, 1e-12);
  EXPECT_NEAR(above.d_m, 0.5, 1e-12);
}

}  // namespace
}  // namespace mavloc
