// RANSAC + least-squares known-vertical pose (PIXHAWK section 3.2) on synthetic marker corners.
#include "solver/pixhawk/upright_pose.h"

#include <gtest/gtest.h>

#include "core/random.h"
#include "core/rotation.h"
#include "tests/test_support.h"

namespace mavloc {
namespace {

const Pose kT_B_C(Eigen::Matrix3d(Eigen::Vector3d(1, -1, -1).asDiagonal()),
                  Eigen::Vector3d(0.05, 0.0, -0.03));  // down-looking camera
constexpr double kFocalPx = 420.0;

struct Scene {
  Pose T_W_B;
  EulerRpy rpy;
  std::vector<Eigen::Vector3d> X_W;
  std::vector<Eigen::Vector2d> xy_C;
};

// Corners of a floor grid seen from about 1.2 m; pixel noise sigma_px on the normalized
// coordinates (sigma_px / f).
Scene MakeScene(Rng& rng, double sigma_px, int max_points = 1000) {
  Scene scene;
  scene.rpy = {rng.Uniform(-0.1, 0.1), rng.Uniform(-0.1, 0.1), rng.Uniform(-M_PI, M_PI)};
  scene.T_W_B =
      Pose{RotationFromEuler(scene.rpy),
           Eigen::Vector3d{rng.Uniform(-1, 1), rng.Uniform(-1, 1), rng.Uniform(0.8, 1.6)}};
  const Pose T_C_W = (scene.T_W_B * kT_B_C).Inverse();
  for (int gx = -6; gx <= 6; ++gx) {
    for (int gy = -6; gy <= 6; ++gy) {
      const Eigen::Vector3d X{0.25 * gx + rng.Uniform(-0.05, 0.05),
                              0.25 * gy + rng.Uniform(-0.05, 0.05), 0.0};
      const Eigen::Vector3d q = T_C_W * X;
      if (q.z() < 0.1) continue;
      const Eigen::Vector2d xy = q.head<2>() / q.z();
      if (std::abs(xy.x()) > 0.7 || std::abs(xy.y()) > 0.55) continue;
      if (static_cast<int>(scene.X_W.size()) >= max_points) continue;
      scene.X_W.push_back(X);
      scene.xy_C.push_back(xy + rng.GaussianVector<2>() * sigma_px / kFocalPx);
    }
  }
  return scene;
}

TEST(UprightPoseTest, JacobianMatchesCentralDifferences) {
  Rng rng(std::hash<std::string>{}("UprightPoseTest.Jacobian"));
  const Scene scene = MakeScene(rng, 1.0, 10);
  const Eigen::Matrix3d R_L_C = LevelledCameraRotation(0.05, -0.03, kT_B_C.R());
  const Eigen::Vector4d theta(0.2, -0.1, 1.3, 0.8);
  Eigen::VectorXd r;
  Eigen::MatrixXd J;
  UprightResiduals(scene.X_W, scene.xy_C, R_L_C, kFocalPx, theta.head<3>(), theta[3], &r, &J);
  const Eigen::MatrixXd J_num = testing::CentralDifferenceJacobian(
      [&](const Eigen::VectorXd& x) {
        Eigen::VectorXd out;
        UprightResiduals(scene.X_W, scene.xy_C, R_L_C, kFocalPx, x.head<3>(), x[3], &out, nullptr);
        return out;
      },
      theta);
  ASSERT_EQ(J.rows(), J_num.rows());
  EXPECT_LT((J - J_num).cwiseAbs().maxCoeff(), 1e-5 * std::max(1.0, J.cwiseAbs().maxCoeff()));
}

TEST(UprightPoseTest, NoiselessCornersGiveTheExactPose) {
  Rng rng(std::hash<std::string>{}("UprightPoseTest.Noiseless"));
  for (int n = 0; n < 50; ++n) {
    const Scene scene = MakeScene(rng, 0.0);
    ASSERT_GE(scene.X_W.size(), 8u);
    UprightPoseOptions options;
    options.seed = n + 1;
    const auto result = EstimateUprightPose(scene.X_W, scene.xy_C, scene.rpy.roll, scene.rpy.pitch,
                                            kT_B_C, kFocalPx, options);
    ASSERT_TRUE(result.ok) << result.reason;
    EXPECT_LT((result.T_W_B.p - scene.T_W_B.p).norm(), 1e-8);
    EXPECT_LT(RotationAngleBetween(result.T_W_B.q, scene.T_W_B.q), 1e-8);
    EXPECT_EQ(result.num_inliers, static_cast<int>(scene.X_W.size()));
  }
}

TEST(UprightPoseTest, NoisyCornersGivePositionToMillimetres) {
  Rng rng(std::hash<std::string>{}("UprightPoseTest.Noisy"));
  double sum_sq = 0.0;
  int count = 0;
  for (int n = 0; n < 100; ++n) {
    const Scene scene = MakeScene(rng, 1.0, 40);
    UprightPoseOptions options;
    options.seed = n + 1;
    const auto result = EstimateUprightPose(scene.X_W, scene.xy_C, scene.rpy.roll, scene.rpy.pitch,
                                            kT_B_C, kFocalPx, options);
    ASSERT_TRUE(result.ok) << result.reason;
    sum_sq += (result.T_W_B.p - scene.T_W_B.p).squaredNorm();
    ++count;
    EXPECT_LT(result.rms_px, 2.0);
  }
  // With 1 px noise at ~1.2 m and f = 420 px a single corner is worth ~3 mm; 40 corners give
  // the position to a few mm.
  EXPECT_LT(std::sqrt(sum_sq / count), 0.01);
}

TEST(UprightPoseTest, RansacRejectsGrossOutliers) {
  Rng rng(std::hash<std::string>{}("UprightPoseTest.Outliers"));
  double worst_ransac = 0.0, worst_plain = 0.0;
  for (int n = 0; n < 50; ++n) {
    Scene scene = MakeScene(rng, 1.0, 40);
    std::vector<char> is_outlier(scene.X_W.size(), 0);
    for (size_t i = 0; i < scene.X_W.size(); ++i) {
      if (rng.Uniform() < 0.25) {
        const double a = rng.Uniform(-M_PI, M_PI), m = rng.Uniform(20.0, 60.0) / kFocalPx;
        scene.xy_C[i] += m * Eigen::Vector2d(std::cos(a), std::sin(a));
        is_outlier[i] = 1;
      }
    }
    UprightPoseOptions options;
    options.seed = n + 1;
    const auto result = EstimateUprightPose(scene.X_W, scene.xy_C, scene.rpy.roll, scene.rpy.pitch,
                                            kT_B_C, kFocalPx, options);
    ASSERT_TRUE(result.ok) << result.reason;
    worst_ransac = std::max(worst_ransac, (result.T_W_B.p - scene.T_W_B.p).norm());
    for (size_t i = 0; i < is_outlier.size(); ++i) {
      if (is_outlier[i]) {
        EXPECT_FALSE(result.inliers[i]) << "outlier " << i << " kept";
      }
    }
    options.ransac = false;
    const auto plain = EstimateUprightPose(scene.X_W, scene.xy_C, scene.rpy.roll, scene.rpy.pitch,
                                           kT_B_C, kFocalPx, options);
    if (plain.ok) worst_plain = std::max(worst_plain, (plain.T_W_B.p - scene.T_W_B.p).norm());
  }
  EXPECT_LT(worst_ransac, 0.02);
  EXPECT_GT(worst_plain, 3.0 * worst_ransac);
}

TEST(UprightPoseTest, DegenerateInputsReportAReason) {
  const auto none = EstimateUprightPose({Eigen::Vector3d::Zero()}, {Eigen::Vector2d::Zero()}, 0, 0,
                                        kT_B_C, kFocalPx);
  EXPECT_FALSE(none.ok);
  EXPECT_FALSE(none.reason.empty());
  // Two corners on the same ray.
  const auto same = EstimateUprightPose({Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0, 0, 0)},
                                        {Eigen::Vector2d(0.1, 0.1), Eigen::Vector2d(0.1, 0.1)}, 0,
                                        0, kT_B_C, kFocalPx);
  EXPECT_FALSE(same.ok);
  EXPECT_FALSE(same.reason.empty());
}

}  // namespace
}  // namespace mavloc
