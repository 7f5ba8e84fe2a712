// 4 x 1-D constant-velocity Kalman filters (PIXHAWK section 5.1).
#include "solver/pixhawk/pixhawk_kf.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/random.h"
#include "core/rotation.h"

namespace mavloc {
namespace {

TEST(ConstantVelocityKf1dTest, NoiselessConstantVelocityIsTrackedWithVaryingDt) {
  ConstantVelocityKf1d filter(0.01, 0.01, false);
  Rng rng(std::hash<std::string>{}("ConstantVelocityKf1dTest.Noiseless"));
  double t = 0.0;
  filter.Initialize(1.0, 1.0);
  for (int k = 0; k < 200; ++k) {
    const double dt = rng.Uniform(0.02, 0.08);  // irregular, but measured
    t += dt;
    filter.Predict(dt);
    filter.Update(1.0 + 0.7 * t);
  }
  EXPECT_NEAR(filter.value(), 1.0 + 0.7 * t, 1e-3);
  EXPECT_NEAR(filter.rate(), 0.7, 1e-2);
}

TEST(ConstantVelocityKf1dTest, PredictThenUpdateEqualsOneLongerStep) {
  // A rejected frame only predicts; the next update spans the longer interval. For the white-noise
  // acceleration model, two predictions equal one over the summed interval exactly.
  ConstantVelocityKf1d a(0.3, 0.05, false), b(0.3, 0.05, false);
  a.Initialize(0.2, 0.5);
  b.Initialize(0.2, 0.5);
  a.Update(0.25);
  b.Update(0.25);
  a.Predict(0.033);
  a.Predict(0.041);
  a.Update(0.31);
  b.Predict(0.074);
  b.Update(0.31);
  EXPECT_LT((a.state() - b.state()).norm(), 1e-12);
  EXPECT_LT((a.covariance() - b.covariance()).norm(), 1e-12);
}

TEST(ConstantVelocityKf1dTest, ConsistentOnItsOwnModel) {
  // Truth simulated from the filter's own model (white-noise acceleration q, measurement noise
  // sigma): the time-averaged NEES of [s, s_dot] over Monte-Carlo runs is close to 2.
  const double q = 0.5, sigma = 0.02;
  Rng rng(std::hash<std::string>{}("ConstantVelocityKf1dTest.Consistent"));
  double nees_sum = 0.0;
  int count = 0;
  for (int run = 0; run < 100; ++run) {
    ConstantVelocityKf1d filter(q, sigma, false);
    Eigen::Vector2d x(rng.Gaussian(), 0.0);
    filter.Initialize(x[0] + sigma * rng.Gaussian(), 1.0);
    x[1] = rng.Gaussian();  // within the initial velocity sigma of 1
    for (int k = 0; k < 100; ++k) {
      const double dt = rng.Uniform(0.02, 0.06);
      const Eigen::Matrix2d L = ConstantVelocityKf1d::ProcessNoise(q, dt).llt().matrixL();
      x = ConstantVelocityKf1d::Transition(dt) * x + L * rng.GaussianVector<2>();
      filter.Predict(dt);
      filter.Update(x[0] + sigma * rng.Gaussian());
      if (k >= 20) {
        const Eigen::Vector2d e = filter.state() - x;
        nees_sum += e.dot(filter.covariance().inverse() * e);
        ++count;
      }
    }
  }
  const double nees = nees_sum / count;
  EXPECT_GT(nees, 1.8);
  EXPECT_LT(nees, 2.2);
}

TEST(ConstantVelocityKf1dTest, YawWrapsAroundPi) {
  ConstantVelocityKf1d filter(0.01, 0.01, true);
  double yaw = M_PI - 0.3;
  filter.Initialize(yaw, 1.0);
  double worst = 0.0;
  for (int k = 0; k < 150; ++k) {
    yaw += 0.5 * 0.03;  // 0.5 rad/s through +pi
    filter.Predict(0.03);
    const double innovation = filter.Update(WrapAngle(yaw));
    EXPECT_LT(std::abs(innovation), 0.5);  // never the 2 pi jump
    if (k > 30) worst = std::max(worst, std::abs(WrapAngle(filter.value() - yaw)));
    EXPECT_LE(std::abs(filter.value()), M_PI);
  }
  EXPECT_LT(worst, 0.01);
  EXPECT_NEAR(filter.rate(), 0.5, 0.02);
}

TEST(PixhawkKfTest, FourAxesPredictOnRejectedFramesAndRestartAfterTheCoastLimit) {
  PixhawkKfOptions options;
  options.coast_limit_s = 0.5;
  PixhawkKf kf(options);
  EXPECT_FALSE(kf.initialized());
  const Eigen::Vector3d v(0.4, -0.2, 0.1);
  TimeNs t = 0;
  for (int k = 0; k < 60; ++k) {
    t += 33'000'000;
    kf.Update(t, v * NsToSeconds(t), 3.0);
  }
  EXPECT_TRUE(kf.tracking());
  EXPECT_LT((kf.velocity() - v).norm(), 0.01);
  // Rejected frames: the prediction carries the motion on.
  for (int k = 0; k < 10; ++k) {
    t += 33'000'000;
    kf.Predict(t);
  }
  EXPECT_TRUE(kf.tracking());
  EXPECT_LT((kf.position() - v * NsToSeconds(t)).norm(), 0.01);
  // Beyond the coast limit the filter is lost; the next measurement restarts it.
  t += 400'000'000;
  kf.Predict(t);
  EXPECT_FALSE(kf.tracking());
  const Eigen::Vector3d jump(5.0, 5.0, 1.0);
  kf.Update(t, jump, -3.0);
  EXPECT_TRUE(kf.tracking());
  EXPECT_LT((kf.position() - jump).norm(), 1e-12);
  EXPECT_NEAR(kf.yaw(), -3.0, 1e-12);
  EXPECT_LT(kf.velocity().norm(), 1e-12);
}

}  // namespace
}  // namespace mavloc
