#include "evaluation/crlb/pixel_jacobian.h"

#include <gtest/gtest.h>

#include <optional>

#include "core/random.h"
#include "core/rotation.h"

namespace mavloc {
namespace {

using Vector8d = Eigen::Matrix<double, 8, 1>;

// The definition in the header, differentiated numerically: the pixel of the perturbed pose and
// point, central differences over the eight perturbations.
Eigen::Matrix<double, 2, 8> CentralDifferences(const CameraSensor& camera, const Pose& T_W_B,
                                               const Eigen::Vector3d& p_W, double sigma_px) {
  const auto project = [&](const Vector8d& d) {
    const Pose T(T_W_B.q * ExpQuaternion(d.segment<3>(3)), T_W_B.p + d.head<3>());
    const Eigen::Vector3d p_tilted_W = ExpSO3(Eigen::Vector3d(d(6), d(7), 0.0)) * p_W;
    return *camera.model.Project((T * camera.T_B_C).Inverse() * p_tilted_W, 0.01);
  };
  Eigen::Matrix<double, 2, 8> J;
  const double step = 1e-6;
  for (int c = 0; c < 8; ++c) {
    const Vector8d d = step * Vector8d::Unit(c);
    J.col(c) = (project(d) - project(-d)) / (2.0 * step * sigma_px);
  }
  return J;
}

CameraSensor Camera(DistortionModel model, const std::array<double, 4>& coefficients) {
  CameraSensor camera;
  camera.model =
      CameraModel(752, 480, Eigen::Vector4d(458.6, 457.3, 367.2, 248.4), model, coefficients);
  camera.T_B_C =
      Pose(ExpQuaternion(Eigen::Vector3d(0.02, -0.01, 1.57)), Eigen::Vector3d(-0.02, 0.06, 0.01));
  return camera;
}

TEST(CrlbPixelJacobian, MatchesCentralDifferencesOnRandomGeometry) {
  Rng rng(5);
  const CameraSensor cameras[] = {
      Camera(DistortionModel::kRadialTangential, {-0.283, 0.074, 1.9e-4, 1.8e-5}),
      Camera(DistortionModel::kEquidistant, {0.0034, 0.0081, -0.0102, 0.0042}),
      Camera(DistortionModel::kNone, {0, 0, 0, 0})};
  int checked = 0;
  for (const CameraSensor& camera : cameras) {
    for (int trial = 0; trial < 300; ++trial) {
      const Pose T_W_B(ExpQuaternion(Eigen::Vector3d(rng.Uniform(-3, 3), rng.Uniform(-3, 3),
                                                     rng.Uniform(-3, 3))),
                       Eigen::Vector3d(rng.Uniform(-5, 5), rng.Uniform(-5, 5), rng.Uniform(0, 3)));
      // A point 0.5-8 m in front of the camera, inside the image.
      const double z = rng.Uniform(0.5, 8.0);
      const Eigen::Vector3d p_C(rng.Uniform(-0.6, 0.6) * z, rng.Uniform(-0.4, 0.4) * z, z);
      const Eigen::Vector3d p_W = T_W_B * (camera.T_B_C * p_C);
      Eigen::Matrix<double, 2, 8> J;
      ASSERT_TRUE(PixelJacobian(camera, T_W_B, p_W, 0.7, true, &J));
      const Eigen::Matrix<double, 2, 8> J_num = CentralDifferences(camera, T_W_B, p_W, 0.7);
      EXPECT_LT((J - J_num).cwiseAbs().maxCoeff(), 1e-6 * J_num.cwiseAbs().maxCoeff())
          << "trial " << trial << "\n"
          << J << "\n"
          << J_num;
      Eigen::Matrix<double, 2, 8> J_no_tilt;
      ASSERT_TRUE(PixelJacobian(camera, T_W_B, p_W, 0.7, false, &J_no_tilt));
      EXPECT_EQ(J_no_tilt.leftCols<6>(), J.leftCols<6>());
      EXPECT_TRUE(J_no_tilt.rightCols<2>().isZero(0.0));
      ++checked;
    }
  }
  EXPECT_EQ(checked, 900);
}

TEST(CrlbPixelJacobian, PointBehindOrTooCloseHasNoJacobian) {
  const CameraSensor camera = Camera(DistortionModel::kNone, {0, 0, 0, 0});
  const Pose T_W_B;
  Eigen::Matrix<double, 2, 8> J;
  EXPECT_FALSE(PixelJacobian(camera, T_W_B, T_W_B * (camera.T_B_C * Eigen::Vector3d(0.1, 0, -2)),
                             1.0, false, &J));
  EXPECT_FALSE(PixelJacobian(camera, T_W_B, T_W_B * (camera.T_B_C * Eigen::Vector3d(0, 0, 0.005)),
                             1.0, false, &J));
  EXPECT_TRUE(PixelJacobian(camera, T_W_B, T_W_B * (camera.T_B_C * Eigen::Vector3d(0, 0, 0.02)),
                            1.0, false, &J));
}

}  // namespace
}  // namespace mavloc
