// Why the Cramér–Rao bound has no finite value for the bearing scenarios (evaluation/crlb/
// smoother_bound.h): the simulator's angular noise (PerturbBearing: a Gaussian angle about a
// uniformly random perpendicular axis) has a 2-D tangent error with a 1/r density cusp at zero, so
// its Fisher information is infinite. Measured here: the probability of an error below eps grows
// linearly in eps (2 eps / (sqrt(2 pi) sigma)), where a 2-D Gaussian of the same covariance
// (sigma^2 / 2 per axis) gives eps^2 / sigma^2.
#include <gtest/gtest.h>

#include <cmath>

#include "core/random.h"
#include "datasets/simulation/camera_simulator.h"

namespace mavloc {
namespace {

TEST(CrlbAngularNoise, TangentErrorHasADensityCuspAtZero) {
  const double sigma = 0.01;
  const Eigen::Vector3d f = Eigen::Vector3d(0.2, -0.1, 1.0).normalized();
  Rng rng(42);
  const int n = 200000;
  const double eps_small = 0.02 * sigma, eps_large = 0.08 * sigma;
  int below_small = 0, below_large = 0;
  double sum_sq = 0.0;
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d g = PerturbBearing(f, sigma, rng);
    const double angle = std::atan2(f.cross(g).norm(), f.dot(g));
    sum_sq += angle * angle;
    below_small += angle < eps_small ? 1 : 0;
    below_large += angle < eps_large ? 1 : 0;
  }
  // The total variance is sigma^2 (sigma^2 / 2 per tangent axis).
  EXPECT_NEAR(sum_sq / n, sigma * sigma, 0.02 * sigma * sigma);
  // Linear growth: P(r < eps) = 2 eps / (sqrt(2 pi) sigma) to first order.
  const double expected_small = 2.0 * 0.02 / std::sqrt(2.0 * M_PI);
  const double expected_large = 2.0 * 0.08 / std::sqrt(2.0 * M_PI);
  EXPECT_NEAR(1.0 * below_small / n, expected_small, 4.0 * std::sqrt(expected_small / n));
  EXPECT_NEAR(1.0 * below_large / n, expected_large, 4.0 * std::sqrt(expected_large / n));
  // A 2-D Gaussian with the same covariance would put eps^2 / sigma^2 = 4e-4 below eps_small: the
  // measured share is about 40 times that.
  EXPECT_GT(1.0 * below_small / n, 20.0 * 0.02 * 0.02);
}

}  // namespace
}  // namespace mavloc
