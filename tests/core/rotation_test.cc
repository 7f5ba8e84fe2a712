#include "core/rotation.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/random.h"
#include "tests/test_support.h"

namespace mavloc {
namespace {

TEST(Euler, KnownValues) {
  // Pure yaw of 90 deg maps x_B onto y_W.
  const Eigen::Matrix3d R = RotationFromEuler({0.0, 0.0, 90 * kDeg});
  EXPECT_TRUE((R * Eigen::Vector3d::UnitX()).isApprox(Eigen::Vector3d::UnitY(), 1e-12));
  // Pitch up by 30 deg tips x_B upwards? R = Ry(pitch): x_B -> (cos p, 0, -sin p).
  const Eigen::Matrix3d P = RotationFromEuler({0.0, 30 * kDeg, 0.0});
  EXPECT_TRUE((P * Eigen::Vector3d::UnitX())
                  .isApprox(Eigen::Vector3d(std::cos(30 * kDeg), 0, -std::sin(30 * kDeg)), 1e-12));
  // The order is Rz * Ry * Rx.
  const EulerRpy rpy{0.1, -0.2, 0.3};
  EXPECT_TRUE(RotationFromEuler(rpy).isApprox(Rz(0.3) * Ry(-0.2) * Rx(0.1), 1e-15));
}

TEST(Euler, RoundTripOnRandomAngles) {
  Rng rng(7);
  for (int i = 0; i < 1000; ++i) {
    const EulerRpy rpy{rng.Uniform(-M_PI, M_PI), rng.Uniform(-1.5, 1.5), rng.Uniform(-M_PI, M_PI)};
    const EulerRpy back = EulerFromQuaternion(QuaternionFromEuler(rpy));
    EXPECT_NEAR(WrapAngle(back.roll - rpy.roll), 0.0, 1e-10);
    EXPECT_NEAR(back.pitch, rpy.pitch, 1e-10);
    EXPECT_NEAR(WrapAngle(back.yaw - rpy.yaw), 0.0, 1e-10);
  }
}

TEST(Euler, GimbalLockKeepsTheRotation) {
  const Eigen::Matrix3d R = RotationFromEuler({0.4, M_PI / 2, 1.0});
  EXPECT_TRUE(RotationFromEuler(EulerFromRotation(R)).isApprox(R, 1e-9));
}

TEST(WrapAngle, Range) {
  EXPECT_NEAR(WrapAngle(3 * M_PI), M_PI, 1e-12);
  EXPECT_NEAR(WrapAngle(-3 * M_PI), M_PI, 1e-12);
  EXPECT_NEAR(WrapAngle(2 * M_PI + 0.1), 0.1, 1e-12);
  EXPECT_NEAR(WrapAngle(-0.1), -0.1, 1e-15);
}

TEST(So3, ExpLogRoundTrip) {
  Rng rng(3);
  for (int i = 0; i < 1000; ++i) {
    Eigen::Vector3d phi = rng.Gaussian3(1.0);
    if (phi.norm() > 3.0) phi *= 3.0 / phi.norm();
    if (i % 10 == 0) phi *= 1e-9;  // near identity
    EXPECT_TRUE(LogSO3(ExpSO3(phi)).isApprox(phi, 1e-9) || phi.norm() < 1e-8);
    EXPECT_NEAR((LogSO3(ExpSO3(phi)) - phi).norm(), 0.0, 1e-9);
    EXPECT_TRUE(ExpQuaternion(phi).toRotationMatrix().isApprox(ExpSO3(phi), 1e-12));
  }
}

TEST(So3, RightJacobianMatchesCentralDifferences) {
  // Exp(phi + d) ~= Exp(phi) Exp(Jr(phi) d)  =>  Jr = d Log(Exp(phi)^T Exp(phi + d)) / d d.
  Rng rng(11);
  for (int i = 0; i < 20; ++i) {
    const Eigen::Vector3d phi = rng.Gaussian3(0.8);
    const Eigen::Matrix3d R0 = ExpSO3(phi);
    const auto f = [&](const Eigen::VectorXd& d) -> Eigen::VectorXd {
      return LogSO3(R0.transpose() * ExpSO3(phi + Eigen::Vector3d(d)));
    };
    const Eigen::MatrixXd J = testing::CentralDifferenceJacobian(f, Eigen::VectorXd::Zero(3));
    EXPECT_TRUE(J.isApprox(RightJacobianSO3(phi), 1e-7)) << J << "\n" << RightJacobianSO3(phi);
    EXPECT_TRUE((RightJacobianSO3(phi) * RightJacobianInverseSO3(phi)).isIdentity(1e-10));
  }
}

TEST(Quaternion, ConventionsOnDisk) {
  // EuRoC stores (w, x, y, z); Eigen's constructor takes (w, x, y, z) too, coeffs() are (x, y, z,
  // w).
  const Eigen::Quaterniond q = QuaternionFromWxyz(0.5, 0.5, 0.5, 0.5);
  EXPECT_DOUBLE_EQ(q.w(), 0.5);
  EXPECT_DOUBLE_EQ(q.coeffs()[3], 0.5);
  // Hamilton convention: 120 deg about (1,1,1) maps x -> y.
  EXPECT_TRUE((q * Eigen::Vector3d::UnitX()).isApprox(Eigen::Vector3d::UnitY(), 1e-12));
}

}  // namespace
}  // namespace mavloc
