// Triangle-angle Kalman filter (three-point paper, IV-C): the law-of-cosines measurement on
// noiseless images (both triangle orientations), its Jacobian against central differences, the
// consistency of its propagated covariance, and convergence of the filter.
#include "solver/three_point/triangle_angle_filter.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/random.h"
#include "core/rotation.h"
#include "tests/test_support.h"

namespace mavloc {
namespace {

struct Scene {
  EulerRpy rpy;
  Eigen::Matrix3d R_B_C;
  std::array<Eigen::Vector2d, 3> xy{};
  Eigen::Vector2d gamma;  // true signed angles
};

// The triangle P1 = 0, P2 = D e_x, P3 seen by a down-looking camera on a tilted vehicle.
Scene MakeScene(const Eigen::Vector3d& P3, const EulerRpy& rpy, const Eigen::Vector3d& c_W) {
  const double D = 0.1;
  const std::array<Eigen::Vector3d, 3> P = {Eigen::Vector3d::Zero(), Eigen::Vector3d(D, 0, 0), P3};
  Scene s;
  s.rpy = rpy;
  s.R_B_C = Eigen::Vector3d(1, -1, -1).asDiagonal();
  const Eigen::Matrix3d R_W_C = RotationFromEuler(rpy) * s.R_B_C;
  for (int i = 0; i < 3; ++i) {
    const Eigen::Vector3d X_C = R_W_C.transpose() * (P[i] - c_W);
    s.xy[i] = X_C.head<2>() / X_C.z();
  }
  s.gamma = Eigen::Vector2d(std::atan2(P3.y(), P3.x()), std::atan2(P3.y(), P3.x() - D));
  return s;
}

TriangleAngleInput InputFor(const Scene& s) {
  TriangleAngleInput input;
  input.roll_rad = s.rpy.roll;
  input.pitch_rad = s.rpy.pitch;
  input.xy = s.xy;
  input.R_B_C = s.R_B_C;
  return input;
}

Scene RandomScene(Rng& rng) {
  Eigen::Vector3d P3{rng.Uniform(-0.03, 0.13), rng.Uniform(0.03, 0.12), 0.0};
  if (rng.Uniform() < 0.5) P3.y() *= -1.0;
  const EulerRpy rpy{rng.Uniform(-15, 15) * kDeg, rng.Uniform(-15, 15) * kDeg,
                     rng.Uniform(-180, 180) * kDeg};
  const Eigen::Vector3d c_W{rng.Uniform(-0.1, 0.2), rng.Uniform(-0.1, 0.2), rng.Uniform(0.2, 1.0)};
  return MakeScene(P3, rpy, c_W);
}

TEST(TriangleAngleMeasurement, ThePapersTriangleGivesSixtyAndOneTwentyDegrees) {
  const Scene s = MakeScene(Eigen::Vector3d(0.05, std::sqrt(3.0) / 2 * 0.1, 0),
                            EulerRpy{4 * kDeg, -3 * kDeg, 1.0}, Eigen::Vector3d(0.1, 0.2, 0.5));
  TriangleAngleMeasurement m;
  ASSERT_TRUE(MeasureTriangleAngles(InputFor(s), &m));
  EXPECT_NEAR(m.gamma_rad.x(), 60 * kDeg, 1e-12);
  EXPECT_NEAR(m.gamma_rad.y(), 120 * kDeg, 1e-12);
}

TEST(TriangleAngleMeasurement, NoiselessImagesGiveTheTrueSignedAngles) {
  Rng rng(51);
  for (int trial = 0; trial < 500; ++trial) {
    const Scene s = RandomScene(rng);
    TriangleAngleMeasurement m;
    ASSERT_TRUE(MeasureTriangleAngles(InputFor(s), &m));
    EXPECT_NEAR(WrapAngle(m.gamma_rad.x() - s.gamma.x()), 0.0, 1e-9) << trial;
    EXPECT_NEAR(WrapAngle(m.gamma_rad.y() - s.gamma.y()), 0.0, 1e-9) << trial;
  }
}

TEST(TriangleAngleMeasurement, JacobianMatchesCentralDifferences) {
  Rng rng(52);
  for (int trial = 0; trial < 50; ++trial) {
    const Scene s = RandomScene(rng);
    TriangleAngleMeasurement m;
    Eigen::Matrix<double, 2, 8> J;
    ASSERT_TRUE(MeasureTriangleAngles(InputFor(s), &m, &J));
    Eigen::VectorXd v(8);
    v << s.xy[0], s.xy[1], s.xy[2], s.rpy.roll, s.rpy.pitch;
    const Eigen::MatrixXd J_num = testing::CentralDifferenceJacobian(
        [&](const Eigen::VectorXd& w) {
          TriangleAngleInput input = InputFor(s);
          for (int i = 0; i < 3; ++i) input.xy[i] = w.segment<2>(2 * i);
          input.roll_rad = w(6);
          input.pitch_rad = w(7);
          TriangleAngleMeasurement mm;
          EXPECT_TRUE(MeasureTriangleAngles(input, &mm));
          return Eigen::VectorXd(mm.gamma_rad);
        },
        v);
    EXPECT_LT((J - J_num).cwiseAbs().maxCoeff(), 1e-6 * (1.0 + J.cwiseAbs().maxCoeff()));
  }
}

TEST(TriangleAngleMeasurement, DegenerateTrianglesAreRejected) {
  Scene s = MakeScene(Eigen::Vector3d(0.05, 0.08, 0), EulerRpy{}, Eigen::Vector3d(0, 0, 0.5));
  s.xy[2] = s.xy[0];
  TriangleAngleMeasurement m;
  EXPECT_FALSE(MeasureTriangleAngles(InputFor(s), &m));
}

// Noisy image points: per-axis sigma * (1 + |xy|^2), as the measurement model assumes, and
// roll/pitch drawn from their covariance.
TriangleAngleInput NoisyInput(const Scene& s, double sigma, double sigma_rp, Rng& rng) {
  TriangleAngleInput input = InputFor(s);
  for (auto& xy : input.xy) {
    const double scale = sigma * (1.0 + xy.squaredNorm());
    xy += scale * rng.GaussianVector<2>();
  }
  input.roll_rad += sigma_rp * rng.Gaussian();
  input.pitch_rad += sigma_rp * rng.Gaussian();
  input.bearing_sigma_rad = sigma;
  input.roll_pitch_covariance_rad2 = sigma_rp * sigma_rp * Eigen::Matrix2d::Identity();
  return input;
}

TEST(TriangleAngleMeasurement, PropagatedCovarianceIsConsistent) {
  Rng rng(53);
  const Scene s = MakeScene(Eigen::Vector3d(0.05, std::sqrt(3.0) / 2 * 0.1, 0),
                            EulerRpy{5 * kDeg, 2 * kDeg, 0.3}, Eigen::Vector3d(0.15, 0.1, 0.4));
  const int draws = 1000;
  double nees = 0.0;
  for (int k = 0; k < draws; ++k) {
    TriangleAngleMeasurement m;
    ASSERT_TRUE(MeasureTriangleAngles(NoisyInput(s, 0.01 * kDeg, 0.05 * kDeg, rng), &m));
    const Eigen::Vector2d e(WrapAngle(m.gamma_rad.x() - s.gamma.x()),
                            WrapAngle(m.gamma_rad.y() - s.gamma.y()));
    nees += e.dot(m.covariance_rad2.inverse() * e);
  }
  nees /= draws;
  // 95% band of the mean of 1000 chi-square(2) draws: 2 +- 1.96 * 2 / sqrt(1000).
  EXPECT_GT(nees, 1.876);
  EXPECT_LT(nees, 2.124);
}

TEST(TriangleAngleFilter, ConvergesToTheTrueAnglesOverImages) {
  Rng rng(54);
  const Eigen::Vector3d P3(0.05, std::sqrt(3.0) / 2 * 0.1, 0);
  TriangleAngleFilter filter;
  EXPECT_FALSE(filter.has_estimate());
  const double sigma = 1.0 * kDeg;  // the paper's bearing noise
  double first_sigma = 0.0;
  for (int k = 0; k < 200; ++k) {
    const EulerRpy rpy{rng.Uniform(-3, 3) * kDeg, rng.Uniform(-3, 3) * kDeg, 0.5};
    const Eigen::Vector3d c_W{0.05 + rng.Uniform(-0.05, 0.05), 0.03 + rng.Uniform(-0.05, 0.05),
                              0.3};
    const Scene s = MakeScene(P3, rpy, c_W);
    TriangleAngleMeasurement m;
    ASSERT_TRUE(MeasureTriangleAngles(NoisyInput(s, sigma, 0.05 * kDeg, rng), &m));
    filter.Update(m);
    if (k == 0) first_sigma = std::sqrt(filter.covariance_rad2()(0, 0));
  }
  ASSERT_TRUE(filter.has_estimate());
  EXPECT_EQ(filter.num_updates(), 200);
  const Eigen::Matrix2d& P = filter.covariance_rad2();
  // A constant state observed 200 times: the standard deviation shrinks by about sqrt(200).
  EXPECT_LT(std::sqrt(P(0, 0)), first_sigma / 8.0);
  EXPECT_LT(std::abs(filter.gamma_rad().x() - 60 * kDeg), 4.0 * std::sqrt(P(0, 0)));
  EXPECT_LT(std::abs(filter.gamma_rad().y() - 120 * kDeg), 4.0 * std::sqrt(P(1, 1)));
  EXPECT_LT(std::abs(filter.gamma_rad().x() - 60 * kDeg), 1.0 * kDeg);
  EXPECT_LT(std::abs(filter.gamma_rad().y() - 120 * kDeg), 1.0 * kDeg);
}

}  // namespace
}  // namespace mavloc
