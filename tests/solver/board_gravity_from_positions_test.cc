// The position-fit gravity initialisation of board logs
// (solver/board/board_gravity_from_positions.h) on the analytic motion of tests/analytic_motion.h
// re-expressed in a tilted board frame M: noiseless poses give the up direction to 1e-4 rad; an
// accelerometer bias tilts it by about |b_a| / 9.81; noisy PnP-like poses with a few gross attitude
// flips stay within 0.3 deg.
#include "solver/board/board_gravity_from_positions.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/random.h"
#include "core/rotation.h"
#include "solver/imu/imu_integrator.h"
#include "tests/analytic_motion.h"

namespace mavloc {
namespace {

using testing::AnalyticMotion;

struct BoardScene {
  Pose T_M_W;
  ImuSensor imu;
  std::vector<StampedPose> T_M_B;  // 20 Hz over [1, 3] s
  Eigen::Vector3d up_M;
};

BoardScene MakeScene(const ImuBiases& biases) {
  BoardScene s;
  s.T_M_W = Pose(Eigen::Matrix3d(ExpSO3(Eigen::Vector3d(0.7, -0.9, 0.4))),
                 Eigen::Vector3d(0.3, 1.2, -0.8));
  s.imu.samples = testing::SimulateAnalyticImu(200.0, 4.0, biases);
  for (int k = 0; k <= 40; ++k) {
    const double t = 1.0 + 0.05 * k;
    const Pose T_W_B(RotationFromEuler(AnalyticMotion::Angles(t)), AnalyticMotion::Position(t));
    s.T_M_B.push_back({SecondsToNs(t), s.T_M_W * T_W_B});
  }
  s.up_M = s.T_M_W.R() * Eigen::Vector3d::UnitZ();
  return s;
}

double Angle(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

TEST(BoardGravityFromPositions, NoiselessPosesGiveTheUpDirection) {
  const BoardScene s = MakeScene(ImuBiases());
  std::string why;
  const auto up =
      EstimateUpInBoardFromPositions(s.T_M_B, s.imu, SecondsToNs(1.0), SecondsToNs(3.0), &why);
  ASSERT_TRUE(up.has_value()) << why;
  EXPECT_LT(Angle(*up, s.up_M), 1e-4);
  EXPECT_NEAR(up->norm(), 1.0, 1e-12);
}

TEST(BoardGravityFromPositions, AccelerometerBiasTiltsByItsRatioToGravity) {
  ImuBiases biases;
  biases.b_a = Eigen::Vector3d(0.05, 0.0, 0.0);
  const BoardScene s = MakeScene(biases);
  const auto up =
      EstimateUpInBoardFromPositions(s.T_M_B, s.imu, SecondsToNs(1.0), SecondsToNs(3.0), nullptr);
  ASSERT_TRUE(up.has_value());
  const double error = Angle(*up, s.up_M);
  EXPECT_GT(error, 0.2 * 0.05 / 9.81);  // the bias is not (and cannot be) removed
  EXPECT_LT(error, 2.0 * 0.05 / 9.81);
}

TEST(BoardGravityFromPositions, NoisyPosesWithFlipsStayWithinAFewTenthsOfADegree) {
  BoardScene s = MakeScene(ImuBiases());
  Rng rng(17);
  for (size_t k = 0; k < s.T_M_B.size(); ++k) {
    Pose& T = s.T_M_B[k].T_W_B;
    T.p += rng.Gaussian3(0.01);  // 1 cm
    T.q = T.q * ExpQuaternion(rng.Gaussian3(0.5 * kDeg));
    if (k % 13 == 5) T.q = T.q * ExpQuaternion(Eigen::Vector3d(0.2, -0.15, 0.0));  // a flip
  }
  std::string why;
  const auto up =
      EstimateUpInBoardFromPositions(s.T_M_B, s.imu, SecondsToNs(1.0), SecondsToNs(3.0), &why);
  ASSERT_TRUE(up.has_value()) << why;
  EXPECT_LT(Angle(*up, s.up_M), 0.3 * kDeg);
}

TEST(BoardGravityFromPositions, TooFewPosesOrAShortWindowIsRefused) {
  const BoardScene s = MakeScene(ImuBiases());
  std::string why;
  EXPECT_FALSE(EstimateUpInBoardFromPositions({s.T_M_B.begin(), s.T_M_B.begin() + 4}, s.imu,
                                              SecondsToNs(0.0), SecondsToNs(4.0), &why));
  EXPECT_NE(why.find("fewer than 5"), std::string::npos) << why;
  EXPECT_FALSE(
      EstimateUpInBoardFromPositions(s.T_M_B, s.imu, SecondsToNs(1.0), SecondsToNs(1.3), &why));
  EXPECT_NE(why.find("0.5 s"), std::string::npos) << why;
}

}  // namespace
}  // namespace mavloc
