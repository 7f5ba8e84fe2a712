#include "core/pose.h"

#include <gtest/gtest.h>

#include "core/random.h"
#include "core/rotation.h"

namespace mavloc {
namespace {

Pose RandomPose(Rng& rng) { return Pose{ExpQuaternion(rng.Gaussian3(1.0)), rng.Gaussian3(2.0)}; }

TEST(Pose, ComposeInverseAndAct) {
  Rng rng(5);
  for (int i = 0; i < 100; ++i) {
    const Pose T_A_B = RandomPose(rng), T_B_C = RandomPose(rng);
    const Eigen::Vector3d p_C = rng.Gaussian3(1.0);
    EXPECT_TRUE(((T_A_B * T_B_C) * p_C).isApprox(T_A_B * (T_B_C * p_C), 1e-12));
    EXPECT_TRUE((T_A_B.Inverse() * (T_A_B * p_C)).isApprox(p_C, 1e-12));
    EXPECT_TRUE((T_A_B * T_B_C).Matrix().isApprox(T_A_B.Matrix() * T_B_C.Matrix(), 1e-12));
    EXPECT_TRUE(Pose::FromMatrix(T_A_B.Matrix()).Matrix().isApprox(T_A_B.Matrix(), 1e-12));
  }
}

TEST(Pose, RotationAngleBetween) {
  const Eigen::Quaterniond a = QuaternionFromEuler({0, 0, 0.1});
  const Eigen::Quaterniond b = QuaternionFromEuler({0, 0, 0.4});
  EXPECT_NEAR(RotationAngleBetween(a, b), 0.3, 1e-12);
  EXPECT_NEAR(RotationAngleBetween(a, Eigen::Quaterniond(-a.coeffs())), 0.0, 1e-12);
}

}  // namespace
}  // namespace mavloc
