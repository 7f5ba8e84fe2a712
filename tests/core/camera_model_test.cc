#include "core/camera_model.h"

#include <gtest/gtest.h>

#include <ceres/jet.h>

#include "core/random.h"
#include "tests/test_support.h"

namespace mavloc {
namespace {

CameraModel EurocCam0() {
  return CameraModel(752, 480, Eigen::Vector4d(458.654, 457.296, 367.215, 248.375),
                     DistortionModel::kRadialTangential,
                     {-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05});
}

CameraModel Equidistant() {
  return CameraModel(640, 480, Eigen::Vector4d(380.0, 381.0, 320.5, 240.2),
                     DistortionModel::kEquidistant, {0.0034, 0.0081, -0.0102, 0.0042});
}

TEST(CameraModel, RadialTangentialKnownValue) {
  const CameraModel cam = EurocCam0();
  const double x = 0.2, y = -0.1, r2 = x * x + y * y;
  const auto& k = cam.distortion();
  const double radial = 1 + k[0] * r2 + k[1] * r2 * r2;
  const double xd = x * radial + 2 * k[2] * x * y + k[3] * (r2 + 2 * x * x);
  const double yd = y * radial + k[2] * (r2 + 2 * y * y) + 2 * k[3] * x * y;
  const Eigen::Vector2d uv = cam.NormalizedToPixel({x, y});
  EXPECT_NEAR(uv.x(), 458.654 * xd + 367.215, 1e-12);
  EXPECT_NEAR(uv.y(), 457.296 * yd + 248.375, 1e-12);
}

TEST(CameraModel, EquidistantKnownValue) {
  const CameraModel cam = Equidistant();
  const double x = 0.3, y = 0.4, r = 0.5, theta = std::atan(r);
  const auto& k = cam.distortion();
  const double t2 = theta * theta;
  const double theta_d =
      theta * (1 + k[0] * t2 + k[1] * t2 * t2 + k[2] * t2 * t2 * t2 + k[3] * t2 * t2 * t2 * t2);
  const Eigen::Vector2d uv = cam.NormalizedToPixel({x, y});
  EXPECT_NEAR(uv.x(), 380.0 * theta_d / r * x + 320.5, 1e-12);
  EXPECT_NEAR(uv.y(), 381.0 * theta_d / r * y + 240.2, 1e-12);
}

TEST(CameraModel, ProjectUnprojectRoundTrip) {
  Rng rng(2);
  for (const CameraModel& cam :
       {EurocCam0(), Equidistant(), CameraModel(640, 480, Eigen::Vector4d(500, 500, 320, 240))}) {
    for (int i = 0; i < 500; ++i) {
      const Eigen::Vector2d uv{rng.Uniform(0, cam.width() - 1), rng.Uniform(0, cam.height() - 1)};
      const auto f = cam.Unproject(uv);
      ASSERT_TRUE(f.has_value());
      EXPECT_NEAR(f->norm(), 1.0, 1e-12);
      const auto back = cam.Project(3.7 * *f);
      ASSERT_TRUE(back.has_value());
      EXPECT_NEAR((*back - uv).norm(), 0.0, 1e-8);
    }
  }
}

TEST(CameraModel, BehindTheCameraIsNotProjected) {
  const CameraModel cam = EurocCam0();
  EXPECT_FALSE(cam.Project({0.1, 0.1, -1.0}).has_value());
  EXPECT_FALSE(cam.Project({0.1, 0.1, 0.0}).has_value());
  EXPECT_TRUE(cam.IsInside({0, 0}));
  EXPECT_FALSE(cam.IsInside({752, 10}));
}

TEST(CameraModel, TemplatedProjectionMatches) {
  const CameraModel cam = Equidistant();
  const Eigen::Vector3d p_C(0.3, -0.2, 1.5);
  Eigen::Vector2d uv;
  cam.ProjectT(p_C.data(), uv.data());
  EXPECT_TRUE(uv.isApprox(*cam.Project(p_C), 1e-14));
}

// The analytic distortion Jacobian against central differences and against Ceres' forward-mode
// differentiation of the templated formula, on random points across the image (and at the
// centre, where the equidistant model switches to its r -> 0 branch); values to the bit.
TEST(CameraModel, DistortionJacobianMatchesDifferentiation) {
  Rng rng(17);
  using Jet2 = ceres::Jet<double, 2>;
  for (const CameraModel& cam :
       {EurocCam0(), Equidistant(), CameraModel(640, 480, Eigen::Vector4d(400, 400, 320, 240))}) {
    const double* k = cam.distortion().data();
    for (int trial = 0; trial < 200; ++trial) {
      const Eigen::Vector2d xy =
          trial == 0 ? Eigen::Vector2d::Zero()
                     : Eigen::Vector2d(rng.Uniform(-0.8, 0.8), rng.Uniform(-0.6, 0.6));
      double xd = 0, yd = 0;
      Eigen::Matrix2d J;
      DistortNormalizedWithJacobian(cam.distortion_model(), k, xy.x(), xy.y(), &xd, &yd, &J);
      const Eigen::Vector2d expected = cam.Distort(xy);
      EXPECT_EQ(xd, expected.x());
      EXPECT_EQ(yd, expected.y());
      Jet2 jx(xy.x(), 0), jy(xy.y(), 1), jxd, jyd;
      DistortNormalized(cam.distortion_model(), k, jx, jy, &jxd, &jyd);
      Eigen::Matrix2d J_jet;
      J_jet << jxd.v.transpose(), jyd.v.transpose();
      EXPECT_LT((J - J_jet).cwiseAbs().maxCoeff(), 1e-12) << "trial " << trial;
      const Eigen::MatrixXd J_num = testing::CentralDifferenceJacobian(
          [&](const Eigen::VectorXd& v) -> Eigen::VectorXd { return cam.Distort(v); }, xy, 1e-6);
      EXPECT_LT((J - J_num).cwiseAbs().maxCoeff(), 1e-8) << "trial " << trial;
    }
  }
}

TEST(CameraModel, ProjectionJacobianMatchesCentralDifferences) {
  Rng rng(18);
  for (const CameraModel& cam : {EurocCam0(), Equidistant()}) {
    for (int trial = 0; trial < 100; ++trial) {
      const double z = rng.Uniform(0.3, 20.0);
      const Eigen::Vector3d p_C(rng.Uniform(-0.7, 0.7) * z, rng.Uniform(-0.5, 0.5) * z, z);
      Eigen::Matrix<double, 2, 3, Eigen::RowMajor> J;
      const Eigen::Vector2d uv = cam.ProjectWithJacobian(p_C, &J);
      Eigen::Vector2d uv_t;
      cam.ProjectT(p_C.data(), uv_t.data());
      EXPECT_EQ(uv.x(), uv_t.x());
      EXPECT_EQ(uv.y(), uv_t.y());
      const Eigen::MatrixXd J_num = testing::CentralDifferenceJacobian(
          [&](const Eigen::VectorXd& p) -> Eigen::VectorXd {
            Eigen::Vector2d out;
            cam.ProjectT(p.data(), out.data());
            return out;
          },
          p_C, 1e-6 * z);
      EXPECT_LT((J - J_num).cwiseAbs().maxCoeff(), 1e-5 * J.cwiseAbs().maxCoeff())
          << "trial " << trial;
    }
  }
}

TEST(CameraModel, ParsesKalibrNames) {
  EXPECT_EQ(ParseDistortionModel("radial-tangential"), DistortionModel::kRadialTangential);
  EXPECT_EQ(ParseDistortionModel("radtan"), DistortionModel::kRadialTangential);
  EXPECT_EQ(ParseDistortionModel("equidistant"), DistortionModel::kEquidistant);
  EXPECT_EQ(ParseDistortionModel("equi"), DistortionModel::kEquidistant);
  EXPECT_FALSE(ParseDistortionModel("fov").has_value());
}

}  // namespace
}  // namespace mavloc
