// 2p-algorithm (three-point paper, IV-A, eq. 1-4): exact recovery on random noiseless instances
// given the true roll and pitch, the sign of the height from the camera, every degenerate case
// with its reason, and the level-projection Jacobians against central differences.
#include "solver/three_point/two_point.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "core/random.h"
#include "core/rotation.h"
#include "tests/test_support.h"

namespace mavloc {
namespace {

// A camera looking down along -z_B: x_C = x_B, y_C = -y_B, z_C = -z_B.
Pose DownLookingCamera(const Eigen::Vector3d& p_B_C = Eigen::Vector3d::Zero()) {
  return Pose(Eigen::Matrix3d(Eigen::Vector3d(1, -1, -1).asDiagonal()), p_B_C);
}

Eigen::Vector2d Project(const Pose& T_W_B, const Pose& T_B_C, const Eigen::Vector3d& P_W) {
  const Eigen::Vector3d X_C = (T_W_B * T_B_C).Inverse() * P_W;
  return X_C.head<2>() / X_C.z();
}

struct Instance {
  EulerRpy rpy;
  Pose T_W_B;
  Pose T_B_C;
  double D = 0.0;
  Eigen::Vector3d P1_W, P2_W;
};

// A random vehicle above (or below) the pair frame's plane that sees P1 = 0 and P2 = D e_x with
// depth > 0.05 D. The extrinsic is a random tilt of the down-looking camera with an offset.
Instance RandomInstance(Rng& rng, bool below_plane = false) {
  for (;;) {
    Instance in;
    in.D = rng.Uniform(0.05, 2.0);
    in.P1_W = Eigen::Vector3d::Zero();
    in.P2_W = Eigen::Vector3d(in.D, 0, 0);
    const Eigen::Matrix3d R_tilt = ExpSO3(rng.Gaussian3(0.2));
    in.T_B_C = Pose(Eigen::Matrix3d(DownLookingCamera().R() * R_tilt), rng.Gaussian3(0.05));
    in.rpy = EulerRpy{rng.Uniform(-30, 30) * kDeg, rng.Uniform(-30, 30) * kDeg,
                      rng.Uniform(-180, 180) * kDeg};
    if (below_plane) in.rpy.roll += std::numbers::pi;  // upside down: the camera looks up
    const double height = rng.Uniform(0.3, 4.0) * in.D * (below_plane ? -1.0 : 1.0);
    const Eigen::Vector3d c_W{rng.Uniform(-1, 1) * in.D, rng.Uniform(-1, 1) * in.D, height};
    const Eigen::Matrix3d R_W_B = RotationFromEuler(in.rpy);
    in.T_W_B = Pose(R_W_B, Eigen::Vector3d(c_W - R_W_B * in.T_B_C.p));
    const Pose T_C_W = (in.T_W_B * in.T_B_C).Inverse();
    if ((T_C_W * in.P1_W).z() > 0.05 * in.D && (T_C_W * in.P2_W).z() > 0.05 * in.D) return in;
  }
}

TwoPointInput InputFor(const Instance& in) {
  TwoPointInput input;
  input.roll_rad = in.rpy.roll;
  input.pitch_rad = in.rpy.pitch;
  input.xy1 = Project(in.T_W_B, in.T_B_C, in.P1_W);
  input.xy2 = Project(in.T_W_B, in.T_B_C, in.P2_W);
  input.T_B_C = in.T_B_C;
  input.distance_m = in.D;
  return input;
}

void ExpectPoseNear(const Pose& estimate, const Pose& truth, double tolerance) {
  EXPECT_LT((estimate.p - truth.p).norm(), tolerance)
      << estimate.p.transpose() << " vs " << truth.p.transpose();
  EXPECT_LT(RotationAngleBetween(estimate.q, truth.q), tolerance);
}

TEST(TwoPoint, RecoversThePoseOnRandomNoiselessInstances) {
  Rng rng(20130901);
  for (int trial = 0; trial < 1000; ++trial) {
    const Instance in = RandomInstance(rng);
    TwoPointSolution solution;
    ASSERT_EQ(SolveTwoPoint(InputFor(in), &solution), TwoPointStatus::kOk) << "trial " << trial;
    ExpectPoseNear(solution.T_W_B, in.T_W_B, 1e-9);
    EXPECT_NEAR(WrapAngle(solution.yaw_rad - in.rpy.yaw), 0.0, 1e-9);
    const Eigen::Vector3d c_W = in.T_W_B * in.T_B_C.p;
    EXPECT_NEAR(solution.height_m, c_W.z(), 1e-9);
    EXPECT_LT((solution.p_W_C - c_W).norm(), 1e-9);
  }
}

TEST(TwoPoint, HeightSignComesFromTheCameraBelowThePlane) {
  // The sign ambiguity of eq. 2 is resolved by the camera: the features are in front of it.
  Rng rng(7);
  for (int trial = 0; trial < 200; ++trial) {
    const Instance in = RandomInstance(rng, /*below_plane=*/true);
    TwoPointSolution solution;
    ASSERT_EQ(SolveTwoPoint(InputFor(in), &solution), TwoPointStatus::kOk);
    EXPECT_LT(solution.height_m, 0.0);
    ExpectPoseNear(solution.T_W_B, in.T_W_B, 1e-9);
  }
}

TEST(TwoPoint, ThePaperFrameExample) {
  // Level camera 0.5 m above the midpoint of P1 P2, yaw 30 deg: eq. 1-4 by hand.
  Instance in;
  in.D = 0.1;
  in.P1_W = Eigen::Vector3d::Zero();
  in.P2_W = Eigen::Vector3d(0.1, 0, 0);
  in.T_B_C = DownLookingCamera();
  in.rpy = EulerRpy{0, 0, 30 * kDeg};
  in.T_W_B = Pose(RotationFromEuler(in.rpy), Eigen::Vector3d(0.05, 0, 0.5));
  TwoPointSolution solution;
  ASSERT_EQ(SolveTwoPoint(InputFor(in), &solution), TwoPointStatus::kOk);
  // Level coordinates of P1: X_L = Rz(-30 deg) (P1 - c) = -z (mu1, nu1, 1).
  const Eigen::Vector3d X_L1 = Rz(-30 * kDeg) * (in.P1_W - Eigen::Vector3d(0.05, 0, 0.5));
  EXPECT_NEAR(solution.mu_nu1.x(), X_L1.x() / -0.5, 1e-12);
  EXPECT_NEAR(solution.mu_nu1.y(), X_L1.y() / -0.5, 1e-12);
  EXPECT_NEAR(solution.height_m, 0.5, 1e-12);
  EXPECT_NEAR(solution.yaw_rad, 30 * kDeg, 1e-12);
  ExpectPoseNear(solution.T_W_B, in.T_W_B, 1e-12);
}

TEST(TwoPointDegenerate, FeaturesCoincidentInTheImage) {
  Rng rng(3);
  TwoPointInput input = InputFor(RandomInstance(rng));
  input.xy2 = input.xy1;
  TwoPointSolution solution;
  solution.height_m = 123.0;
  const TwoPointStatus status = SolveTwoPoint(input, &solution);
  EXPECT_EQ(status, TwoPointStatus::kFeaturesCoincident);
  EXPECT_EQ(TwoPointStatusReason(status), "features coincident in the image");
  EXPECT_EQ(solution.height_m, 123.0);  // untouched
}

// A level vehicle whose camera looks horizontally along +x_B (z_C = x_B, x_C = -y_B, y_C = -z_B).
Pose ForwardLookingCamera() {
  Eigen::Matrix3d R_B_C;
  R_B_C.col(0) = -Eigen::Vector3d::UnitY();
  R_B_C.col(1) = -Eigen::Vector3d::UnitZ();
  R_B_C.col(2) = Eigen::Vector3d::UnitX();
  return Pose(R_B_C, Eigen::Vector3d::Zero());
}

TEST(TwoPointDegenerate, CameraAtThePlanesHeight) {
  // The camera is in the plane z = 0: every feature's bearing is horizontal.
  Instance in;
  in.D = 0.1;
  in.P1_W = Eigen::Vector3d::Zero();
  in.P2_W = Eigen::Vector3d(0.1, 0, 0);
  in.T_B_C = ForwardLookingCamera();
  in.rpy = EulerRpy{0, 0, 20 * kDeg};
  in.T_W_B = Pose(RotationFromEuler(in.rpy), Eigen::Vector3d(-1.0, -0.3, 0.0));
  const TwoPointInput input = InputFor(in);
  ASSERT_GT((input.xy1 - input.xy2).norm(), 1e-3);  // distinct in the image
  TwoPointSolution solution;
  const TwoPointStatus status = SolveTwoPoint(input, &solution);
  EXPECT_EQ(status, TwoPointStatus::kCameraAtPlaneHeight);
  EXPECT_EQ(TwoPointStatusReason(status), "camera at the plane's height");
}

TEST(TwoPointDegenerate, ABearingParallelToThePlane) {
  // Level forward-looking camera 0.5 m up: P1 below the horizon, the second image point on it.
  TwoPointInput input;
  input.T_B_C = ForwardLookingCamera();
  input.xy1 = Eigen::Vector2d(0.1, 0.4);   // below the horizon (y_C down)
  input.xy2 = Eigen::Vector2d(-0.2, 0.0);  // on the horizon: parallel to the plane
  input.distance_m = 0.1;
  TwoPointSolution solution;
  TwoPointStatus status = SolveTwoPoint(input, &solution);
  EXPECT_EQ(status, TwoPointStatus::kBearingParallelToPlane);
  EXPECT_EQ(TwoPointStatusReason(status), "a bearing parallel to the plane");
  std::swap(input.xy1, input.xy2);
  EXPECT_EQ(SolveTwoPoint(input, &solution), TwoPointStatus::kBearingParallelToPlane);
  // Nose up by atan(0.4) (negative pitch) puts both rays y_C = 0.4 (atan(0.4) below the optical
  // axis) on the horizon, as if the camera were in the plane.
  input.xy1 = Eigen::Vector2d(0.1, 0.4);
  input.xy2 = Eigen::Vector2d(0.3, 0.4);
  input.pitch_rad = -std::atan(0.4);
  EXPECT_EQ(SolveTwoPoint(input, &solution), TwoPointStatus::kCameraAtPlaneHeight);
}

TEST(TwoPointDegenerate, FeaturesOnOppositeSidesAndInvalidInput) {
  TwoPointInput input;
  input.T_B_C = ForwardLookingCamera();
  input.xy1 = Eigen::Vector2d(0.1, 0.4);   // below the horizon
  input.xy2 = Eigen::Vector2d(0.1, -0.4);  // above the horizon
  input.distance_m = 0.1;
  TwoPointSolution solution;
  EXPECT_EQ(SolveTwoPoint(input, &solution), TwoPointStatus::kFeaturesOnOppositeSides);
  input.xy2 = Eigen::Vector2d(0.3, 0.5);
  EXPECT_EQ(SolveTwoPoint(input, &solution), TwoPointStatus::kOk);
  input.distance_m = 0.0;
  EXPECT_EQ(SolveTwoPoint(input, &solution), TwoPointStatus::kInvalidInput);
  input.distance_m = 0.1;
  input.roll_rad = std::nan("");
  EXPECT_EQ(SolveTwoPoint(input, &solution), TwoPointStatus::kInvalidInput);
}

TEST(TwoPointJacobians, LevelProjectionMatchesCentralDifferences) {
  Rng rng(17);
  for (int trial = 0; trial < 50; ++trial) {
    const Instance in = RandomInstance(rng);
    const Eigen::Vector2d xy{rng.Uniform(-0.8, 0.8), rng.Uniform(-0.8, 0.8)};
    const Eigen::Matrix3d R_B_C = in.T_B_C.R();
    LevelPoint p;
    ASSERT_TRUE(ProjectToLevel(in.rpy.roll, in.rpy.pitch, R_B_C, xy, &p));
    auto mu_nu = [&](double roll, double pitch, const Eigen::Vector2d& xy_in) {
      LevelPoint q;
      EXPECT_TRUE(ProjectToLevel(roll, pitch, R_B_C, xy_in, &q));
      return Eigen::VectorXd(q.mu_nu);
    };
    const Eigen::MatrixXd J_xy = testing::CentralDifferenceJacobian(
        [&](const Eigen::VectorXd& v) { return mu_nu(in.rpy.roll, in.rpy.pitch, v); },
        Eigen::VectorXd(xy));
    const Eigen::MatrixXd J_rp = testing::CentralDifferenceJacobian(
        [&](const Eigen::VectorXd& v) { return mu_nu(v(0), v(1), xy); },
        Eigen::VectorXd(Eigen::Vector2d(in.rpy.roll, in.rpy.pitch)));
    const double scale = 1.0 + p.mu_nu.squaredNorm();
    EXPECT_LT((p.d_mu_nu_d_xy - J_xy).cwiseAbs().maxCoeff(), 1e-6 * scale * scale);
    EXPECT_LT((p.d_mu_nu_d_roll_pitch - J_rp).cwiseAbs().maxCoeff(), 1e-6 * scale * scale);
  }
}

TEST(TwoPointJacobians, SegmentHeadingMatchesCentralDifferences) {
  Rng rng(19);
  for (int trial = 0; trial < 50; ++trial) {
    const Eigen::Vector4d v{rng.Gaussian(), rng.Gaussian(), rng.Gaussian(), rng.Gaussian()};
    const double sign = trial % 2 == 0 ? 1.0 : -1.0;
    Eigen::Matrix<double, 1, 4> d_alpha;
    const double alpha = LevelSegmentHeading(v.head<2>(), v.tail<2>(), sign, &d_alpha);
    const Eigen::MatrixXd J = testing::CentralDifferenceJacobian(
        [&](const Eigen::VectorXd& w) {
          // Unwrap around alpha so that the difference quotient does not straddle +-pi.
          const double a = LevelSegmentHeading(w.head<2>(), w.tail<2>(), sign);
          return Eigen::VectorXd::Constant(1, alpha + WrapAngle(a - alpha));
        },
        Eigen::VectorXd(v));
    EXPECT_LT((d_alpha - J).cwiseAbs().maxCoeff(), 1e-6 * (1.0 + d_alpha.cwiseAbs().maxCoeff()));
  }
}

}  // namespace
}  // namespace mavloc
