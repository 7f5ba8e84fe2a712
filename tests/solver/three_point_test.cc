// 3p-algorithm (three-point paper, IV-B, eq. 5-6): exact recovery on random noiseless instances
// from roll and pitch perturbed by a few degrees, the sign convention of constraint (5) on the
// paper's triangle, the residual Jacobian against central differences, degenerate cases.
#include "solver/three_point/three_point.h"

#include <gtest/gtest.h>

#include <Eigen/SVD>

#include <cmath>

#include "core/random.h"
#include "core/rotation.h"
#include "tests/test_support.h"

namespace mavloc {
namespace {

Pose DownLookingCamera() {
  return Pose(Eigen::Matrix3d(Eigen::Vector3d(1, -1, -1).asDiagonal()), Eigen::Vector3d::Zero());
}

Eigen::Vector2d Project(const Pose& T_W_B, const Pose& T_B_C, const Eigen::Vector3d& P_W) {
  const Eigen::Vector3d X_C = (T_W_B * T_B_C).Inverse() * P_W;
  return X_C.head<2>() / X_C.z();
}

struct Instance {
  EulerRpy rpy;
  Pose T_W_B;
  Pose T_B_C;
  std::array<Eigen::Vector3d, 3> P_W;
  double gamma1 = 0.0, gamma2 = 0.0;
};

// Signed triangle angles of P1 = 0, P2 = D e_x, P3 (constraint (5) in mavloc's convention).
void SetGammas(Instance* in) {
  const Eigen::Vector3d d13 = in->P_W[2] - in->P_W[0];
  const Eigen::Vector3d d23 = in->P_W[2] - in->P_W[1];
  in->gamma1 = std::atan2(d13.y(), d13.x());
  in->gamma2 = std::atan2(d23.y(), d23.x());
}

// A random triangle (either orientation) seen from a camera whose line of sight to the centroid
// is 15 to 50 deg off the vertical, at 1 to 4 times D, with a random roll about that line.
Instance RandomInstance(Rng& rng) {
  for (;;) {
    Instance in;
    const double D = rng.Uniform(0.05, 1.0);
    in.P_W[0] = Eigen::Vector3d::Zero();
    in.P_W[1] = Eigen::Vector3d(D, 0, 0);
    in.P_W[2] = Eigen::Vector3d{rng.Uniform(-0.3, 1.3) * D, rng.Uniform(0.3, 1.2) * D, 0};
    if (rng.Uniform() < 0.5) in.P_W[2].y() *= -1.0;  // clockwise triangle
    SetGammas(&in);
    const Eigen::Vector3d centroid = (in.P_W[0] + in.P_W[1] + in.P_W[2]) / 3.0;
    const double off_vertical = rng.Uniform(15, 50) * kDeg;
    const double azimuth = rng.Uniform(-180, 180) * kDeg;
    const double range = rng.Uniform(1.0, 4.0) * D;
    const Eigen::Vector3d c_W =
        centroid + range * Eigen::Vector3d(std::sin(off_vertical) * std::cos(azimuth),
                                           std::sin(off_vertical) * std::sin(azimuth),
                                           std::cos(off_vertical));
    // Camera z toward the centroid (with a little jitter), random roll about it.
    const Eigen::Vector3d z_C = ((centroid - c_W).normalized() + rng.Gaussian3(0.05)).normalized();
    const Eigen::Vector3d x_C = z_C.cross(rng.GaussianVector<3>()).normalized();
    Eigen::Matrix3d R_W_C;
    R_W_C << x_C, z_C.cross(x_C), z_C;
    in.T_B_C = Pose{Eigen::Matrix3d(DownLookingCamera().R() * ExpSO3(rng.Gaussian3(0.1))),
                    rng.Gaussian3(0.02)};
    const Eigen::Matrix3d R_W_B = R_W_C * in.T_B_C.R().transpose();
    in.rpy = EulerFromRotation(R_W_B);
    if (std::abs(in.rpy.pitch) > 75 * kDeg) continue;
    in.T_W_B = Pose(R_W_B, Eigen::Vector3d(c_W - R_W_B * in.T_B_C.p));
    const Pose T_C_W = (in.T_W_B * in.T_B_C).Inverse();
    bool visible = true;
    for (const auto& P : in.P_W) visible = visible && (T_C_W * P).z() > 0.05 * D;
    if (visible) return in;
  }
}

// The smallest singular value of the Jacobian of (6) at the true roll and pitch.
double SmallestSingularValueAtTruth(const Instance& in);

// A random instance on which (6) is well-posed: the Jacobian at the truth has a smallest singular
// value of at least 0.05. Below that, constraint (5) has other exact roots within a few degrees
// of the truth (a fold of the map from roll/pitch to the triangle's angles), and no local solver
// can tell them apart; ThreePoint.NearlySingularGeometryHasNearbyExactRoots shows one.
Instance RandomWellPosedInstance(Rng& rng) {
  for (;;) {
    Instance in = RandomInstance(rng);
    if (SmallestSingularValueAtTruth(in) >= 0.05) return in;
  }
}

ThreePointInput InputFor(const Instance& in, double roll, double pitch) {
  ThreePointInput input;
  input.roll_rad = roll;
  input.pitch_rad = pitch;
  for (int i = 0; i < 3; ++i) input.xy[i] = Project(in.T_W_B, in.T_B_C, in.P_W[i]);
  input.T_B_C = in.T_B_C;
  input.distance_m = (in.P_W[1] - in.P_W[0]).norm();
  input.gamma1_rad = in.gamma1;
  input.gamma2_rad = in.gamma2;
  return input;
}

double SmallestSingularValueAtTruth(const Instance& in) {
  Eigen::Vector2d r;
  Eigen::Matrix2d J;
  if (ThreePointResiduals(InputFor(in, 0, 0), in.rpy.roll, in.rpy.pitch, &r, &J) !=
      TwoPointStatus::kOk)
    return 0.0;
  return Eigen::JacobiSVD<Eigen::Matrix2d>(J).singularValues()(1);
}

TEST(ThreePoint, RecoversThePoseFromPerturbedRollAndPitch) {
  Rng rng(20130902);
  for (int trial = 0; trial < 1000; ++trial) {
    const Instance in = RandomWellPosedInstance(rng);
    const double roll0 = in.rpy.roll + rng.Uniform(-3, 3) * kDeg;
    const double pitch0 = in.rpy.pitch + rng.Uniform(-3, 3) * kDeg;
    ThreePointSolution solution;
    const ThreePointResult result = SolveThreePoint(InputFor(in, roll0, pitch0), &solution);
    ASSERT_TRUE(result.ok()) << "trial " << trial << ": " << result.reason();
    EXPECT_NEAR(WrapAngle(solution.roll_rad - in.rpy.roll), 0.0, 1e-9) << "trial " << trial;
    EXPECT_NEAR(solution.pitch_rad - in.rpy.pitch, 0.0, 1e-9) << "trial " << trial;
    EXPECT_LT((solution.pose.T_W_B.p - in.T_W_B.p).norm(), 1e-9) << "trial " << trial;
    EXPECT_LT(RotationAngleBetween(solution.pose.T_W_B.q, in.T_W_B.q), 1e-9) << "trial " << trial;
    EXPECT_GT(solution.initial_cost, 0.0);
    EXPECT_LT(solution.final_cost, 1e-24);
  }
}

TEST(ThreePoint, NearlySingularGeometryHasNearbyExactRoots) {
  // Where the Jacobian of (6) is nearly singular, constraint (5) holds exactly at roll/pitch
  // values a few degrees from the truth: the refinement then converges (zero cost) elsewhere.
  Rng rng(20130902);
  int found = 0;
  for (int trial = 0; trial < 3000 && found == 0; ++trial) {
    const Instance in = RandomInstance(rng);
    const double roll0 = in.rpy.roll + rng.Uniform(-3, 3) * kDeg;
    const double pitch0 = in.rpy.pitch + rng.Uniform(-3, 3) * kDeg;
    if (SmallestSingularValueAtTruth(in) >= 0.05) continue;
    ThreePointSolution solution;
    if (!SolveThreePoint(InputFor(in, roll0, pitch0), &solution).ok()) continue;
    const double error =
        std::hypot(WrapAngle(solution.roll_rad - in.rpy.roll), solution.pitch_rad - in.rpy.pitch);
    if (solution.final_cost < 1e-24 && error > 0.5 * kDeg) ++found;
  }
  EXPECT_GT(found, 0);
}

TEST(ThreePoint, ThePapersTriangleSatisfiesConstraintFiveWithSixtyAndOneTwentyDegrees) {
  // Fig. 7: P3 = D (0.5, sqrt(3)/2, 0), gamma1 = 60 deg, gamma2 = 120 deg.
  Instance in;
  const double D = 0.1;
  in.P_W = {Eigen::Vector3d::Zero(), Eigen::Vector3d(D, 0, 0),
            Eigen::Vector3d(0.5 * D, std::sqrt(3.0) / 2.0 * D, 0)};
  SetGammas(&in);
  EXPECT_NEAR(in.gamma1, 60 * kDeg, 1e-12);
  EXPECT_NEAR(in.gamma2, 120 * kDeg, 1e-12);
  in.T_B_C = DownLookingCamera();
  in.rpy = EulerRpy{3 * kDeg, -2 * kDeg, 40 * kDeg};
  in.T_W_B = Pose(RotationFromEuler(in.rpy), Eigen::Vector3d(0.2, 0.15, 0.4));
  Eigen::Vector2d r;
  ASSERT_EQ(ThreePointResiduals(InputFor(in, 0, 0), in.rpy.roll, in.rpy.pitch, &r),
            TwoPointStatus::kOk);
  EXPECT_LT(r.norm(), 1e-12);
  ThreePointSolution solution;
  ASSERT_TRUE(SolveThreePoint(InputFor(in, 0.0, 0.0), &solution).ok());
  EXPECT_LT((solution.pose.T_W_B.p - in.T_W_B.p).norm(), 1e-9);
}

TEST(ThreePoint, ResidualJacobianMatchesCentralDifferences) {
  Rng rng(31);
  for (int trial = 0; trial < 100; ++trial) {
    const Instance in = RandomInstance(rng);
    const ThreePointInput input = InputFor(in, 0, 0);
    const double roll = in.rpy.roll + rng.Uniform(-5, 5) * kDeg;
    const double pitch = in.rpy.pitch + rng.Uniform(-5, 5) * kDeg;
    Eigen::Vector2d r;
    Eigen::Matrix2d J;
    ASSERT_EQ(ThreePointResiduals(input, roll, pitch, &r, &J), TwoPointStatus::kOk);
    const Eigen::MatrixXd J_num = testing::CentralDifferenceJacobian(
        [&](const Eigen::VectorXd& zeta) {
          Eigen::Vector2d rr;
          EXPECT_EQ(ThreePointResiduals(input, zeta(0), zeta(1), &rr), TwoPointStatus::kOk);
          return Eigen::VectorXd(rr);
        },
        Eigen::VectorXd(Eigen::Vector2d(roll, pitch)));
    EXPECT_LT((J - J_num).cwiseAbs().maxCoeff(), 1e-6 * (1.0 + J.cwiseAbs().maxCoeff()));
  }
}

TEST(ThreePointDegenerate, ReportsTheReasonAndLeavesTheSolution) {
  Rng rng(41);
  const Instance in = RandomInstance(rng);
  ThreePointSolution solution;
  solution.roll_rad = 42.0;

  ThreePointInput coincident = InputFor(in, in.rpy.roll, in.rpy.pitch);
  coincident.xy[2] = coincident.xy[1];
  ThreePointResult result = SolveThreePoint(coincident, &solution);
  EXPECT_EQ(result.status, ThreePointStatus::kDegenerate);
  EXPECT_EQ(result.reason(), "features coincident in the image");

  // Level vehicle, camera looking along +x_B at the plane's height: every bearing horizontal.
  ThreePointInput in_plane;
  Eigen::Matrix3d R_B_C;
  R_B_C << Eigen::Vector3d(0, -1, 0), Eigen::Vector3d(0, 0, -1), Eigen::Vector3d(1, 0, 0);
  in_plane.T_B_C = Pose(R_B_C, Eigen::Vector3d::Zero());
  in_plane.xy = {Eigen::Vector2d(-0.2, 0.0), Eigen::Vector2d(0.1, 0.0), Eigen::Vector2d(0.3, 0.0)};
  in_plane.distance_m = 0.1;
  result = SolveThreePoint(in_plane, &solution);
  EXPECT_EQ(result.status, ThreePointStatus::kDegenerate);
  EXPECT_EQ(result.reason(), "camera at the plane's height");

  ThreePointInput bad = InputFor(in, in.rpy.roll, in.rpy.pitch);
  bad.distance_m = -1.0;
  EXPECT_EQ(SolveThreePoint(bad, &solution).status, ThreePointStatus::kInvalidInput);
  EXPECT_EQ(solution.roll_rad, 42.0);  // untouched by every failure
}

TEST(ThreePoint, CorrectionGuardRejectsARunawayRefinement) {
  // An instance whose unguarded refinement from a prior 3 deg off in roll and pitch reaches the
  // truth (4.2 deg away). Not every instance does: from the same prior, seed 43's refinement stops
  // at another solution 2.4 / -3.2 deg from the truth, near the prior (the constraints of (6) have
  // several roots, and the refinement finds the nearest).
  Rng rng(44);
  const Instance in = RandomInstance(rng);
  const ThreePointInput off_prior = InputFor(in, in.rpy.roll + 3 * kDeg, in.rpy.pitch - 3 * kDeg);
  ThreePointSolution unguarded;
  ASSERT_EQ(SolveThreePoint(off_prior, &unguarded).status, ThreePointStatus::kOk);
  ASSERT_NEAR(unguarded.roll_rad, in.rpy.roll, 1e-6);
  ASSERT_NEAR(unguarded.pitch_rad, in.rpy.pitch, 1e-6);

  ThreePointOptions options;
  options.max_correction_rad = 1 * kDeg;
  ThreePointSolution solution;
  const ThreePointResult result = SolveThreePoint(off_prior, &solution, options);
  EXPECT_EQ(result.status, ThreePointStatus::kCorrectionTooLarge);
  EXPECT_EQ(result.reason(), "roll/pitch refinement moved beyond max_correction");
}

}  // namespace
}  // namespace mavloc
