// The known-vertical 2-point solver (Kukelova et al. ACCV 2010) on random noiseless instances and
// on degenerate and near-degenerate configurations.
#include "solver/pixhawk/upright_p2p.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/random.h"
#include "core/rotation.h"

namespace mavloc {
namespace {

struct Instance {
  std::array<Eigen::Vector3d, 2> v_L;
  std::array<Eigen::Vector3d, 2> X_W;
  double yaw = 0.0;
  Eigen::Vector3d p_W = Eigen::Vector3d::Zero();
};

Eigen::Vector3d RandomUnit(Rng& rng) {
  Eigen::Vector3d d;
  do {
    d = rng.GaussianVector<3>();
  } while (d.norm() < 1e-3);
  return d.normalized();
}

// Points X_i = p_W + Rz(yaw) lambda_i d_i, with the levelled bearing v_i = d_i scaled randomly.
Instance MakeInstance(Rng& rng, const std::array<Eigen::Vector3d, 2>& directions_L) {
  Instance instance;
  instance.yaw = rng.Uniform(-M_PI, M_PI);
  instance.p_W = Eigen::Vector3d{rng.Uniform(-5, 5), rng.Uniform(-5, 5), rng.Uniform(-5, 5)};
  for (int i = 0; i < 2; ++i) {
    const double depth = rng.Uniform(0.5, 10.0);
    instance.X_W[i] = instance.p_W + Rz(instance.yaw) * (depth * directions_L[i]);
    instance.v_L[i] = rng.Uniform(0.2, 3.0) * directions_L[i];
  }
  return instance;
}

// Smallest error (max of position error in m and yaw error in rad) over the solutions.
double BestError(const Instance& instance, const std::vector<UprightPose>& solutions) {
  double best = std::numeric_limits<double>::infinity();
  for (const auto& s : solutions) {
    const double e_p = (s.p_W - instance.p_W).norm();
    const double e_yaw = std::abs(WrapAngle(s.yaw_rad() - instance.yaw));
    best = std::min(best, std::max(e_p, e_yaw));
  }
  return best;
}

// Every solution satisfies the model it claims to solve.
void ExpectSolutionsConsistent(const Instance& instance, const std::vector<UprightPose>& solutions,
                               double tolerance) {
  for (const auto& s : solutions) {
    ASSERT_TRUE(s.p_W.allFinite());
    EXPECT_NEAR(s.cos_yaw * s.cos_yaw + s.sin_yaw * s.sin_yaw, 1.0, 1e-9);
    for (int i = 0; i < 2; ++i) {
      const Eigen::Vector3d X_L = s.R_W_L().transpose() * (instance.X_W[i] - s.p_W);
      const double sine = X_L.normalized().cross(instance.v_L[i].normalized()).norm();
      EXPECT_LT(sine, tolerance);
    }
  }
}

TEST(UprightP2pTest, RandomNoiselessInstancesContainTruth) {
  Rng rng(std::hash<std::string>{}("UprightP2pTest.RandomNoiselessInstancesContainTruth"));
  const int kInstances = 10000;
  int found = 0;
  int total_solutions = 0;
  std::vector<UprightPose> solutions;
  for (int n = 0; n < kInstances; ++n) {
    const Instance instance = MakeInstance(rng, {RandomUnit(rng), RandomUnit(rng)});
    total_solutions += upright_p2p(instance.v_L, instance.X_W, &solutions);
    EXPECT_LE(solutions.size(), 2u);
    if (BestError(instance, solutions) < 1e-8) ++found;
  }
  EXPECT_GE(found, static_cast<int>(0.999 * kInstances)) << "found " << found;
  // Two points give two solutions in general.
  EXPECT_GT(total_solutions, static_cast<int>(1.9 * kInstances));
}

TEST(UprightP2pTest, DownLookingCameraWithVerticalOnTheOpticalAxis) {
  // A camera looking straight down: the vertical is its optical axis, the levelled bearings are
  // near (0, 0, -1), and one point lies exactly on the axis.
  Rng rng(std::hash<std::string>{}("UprightP2pTest.DownLookingCamera"));
  std::vector<UprightPose> solutions;
  for (int n = 0; n < 500; ++n) {
    const double spread = n < 250 ? 0.05 : 0.5;  // half-angle of the visible cone, rad
    const Eigen::Vector3d d0 =
        n % 2 == 0 ? Eigen::Vector3d(0, 0, -1)
                   : Eigen::Vector3d{rng.Uniform(-spread, spread), rng.Uniform(-spread, spread), -1}
                         .normalized();
    const Eigen::Vector3d d1 =
        Eigen::Vector3d{rng.Uniform(-spread, spread), rng.Uniform(-spread, spread), -1}
            .normalized();
    if (d0.cross(d1).norm() < 1e-3) continue;
    const Instance instance = MakeInstance(rng, {d0, d1});
    upright_p2p(instance.v_L, instance.X_W, &solutions);
    EXPECT_LT(BestError(instance, solutions), 1e-8) << "instance " << n;
    ExpectSolutionsConsistent(instance, solutions, 1e-9);
  }
}

TEST(UprightP2pTest, PointsAtTheCameraHeightAreDegenerate) {
  // Camera and both points in one horizontal plane: the camera may slide along the circle that
  // sees the pair under the same angle (inscribed angle theorem) while turning, so any returned
  // solution must satisfy the model, but the truth is not determined.
  Rng rng(std::hash<std::string>{}("UprightP2pTest.HorizontalRays"));
  std::vector<UprightPose> solutions;
  for (int n = 0; n < 200; ++n) {
    const double a0 = rng.Uniform(-M_PI, M_PI);
    const double a1 = a0 + rng.Uniform(0.2, 2.5);
    const Instance instance = MakeInstance(rng, {Eigen::Vector3d(std::cos(a0), std::sin(a0), 0),
                                                 Eigen::Vector3d(std::cos(a1), std::sin(a1), 0)});
    upright_p2p(instance.v_L, instance.X_W, &solutions);
    ExpectSolutionsConsistent(instance, solutions, 1e-6);
  }
}

TEST(UprightP2pTest, ParallelRaysGiveNoSolution) {
  std::vector<UprightPose> solutions;
  const Eigen::Vector3d d = Eigen::Vector3d(0.1, -0.2, -1.0).normalized();
  // Two different points on one ray.
  EXPECT_EQ(upright_p2p({d, 2.0 * d},
                        {Eigen::Vector3d(1, 2, 0), Eigen::Vector3d(1, 2, 0) + 0.5 * d}, &solutions),
            0);
  EXPECT_TRUE(solutions.empty());
  // A zero bearing.
  EXPECT_EQ(upright_p2p({Eigen::Vector3d::Zero(), d},
                        {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0, 0)}, &solutions),
            0);
}

TEST(UprightP2pTest, PointsOnOneVerticalLineGiveNoSolution) {
  // The two points and the camera centre span a vertical plane that may turn about the vertical
  // line: yaw is not determined.
  const Eigen::Vector3d p_W(0.3, -0.2, 1.5);
  const Eigen::Vector3d X0(1.0, 0.5, 0.0), X1(1.0, 0.5, 0.8);
  const double yaw = 0.7;
  std::vector<UprightPose> solutions;
  const int n = upright_p2p({Rz(yaw).transpose() * (X0 - p_W), Rz(yaw).transpose() * (X1 - p_W)},
                            {X0, X1}, &solutions);
  EXPECT_EQ(n, 0);
}

TEST(UprightP2pTest, NearDegeneratePairsStayFiniteAndAccurate) {
  Rng rng(std::hash<std::string>{}("UprightP2pTest.NearDegenerate"));
  std::vector<UprightPose> solutions;
  for (int n = 0; n < 200; ++n) {
    // (a) Two rays 1e-4 rad apart.
    const Eigen::Vector3d d0 = RandomUnit(rng);
    const Eigen::Vector3d axis = d0.cross(RandomUnit(rng)).normalized();
    const Eigen::Vector3d d1 = ExpSO3(1e-4 * axis) * d0;
    const Instance close = MakeInstance(rng, {d0, d1});
    upright_p2p(close.v_L, close.X_W, &solutions);
    for (const auto& s : solutions) ASSERT_TRUE(s.p_W.allFinite());
    // The conditioning degrades like 1/angle; the truth is still found to ~1e-16/1e-4 * depth.
    EXPECT_LT(BestError(close, solutions), 1e-6) << "instance " << n;

    // (b) Two points 1 mm off a common vertical line.
    Instance vertical;
    vertical.yaw = rng.Uniform(-M_PI, M_PI);
    vertical.p_W = Eigen::Vector3d{rng.Uniform(-2, 2), rng.Uniform(-2, 2), 2.0};
    const Eigen::Vector3d base{rng.Uniform(-2, 2), rng.Uniform(-2, 2), 0.0};
    const double a = rng.Uniform(-M_PI, M_PI);
    vertical.X_W = {base, base + Eigen::Vector3d(1e-3 * std::cos(a), 1e-3 * std::sin(a), 0.7)};
    for (int i = 0; i < 2; ++i)
      vertical.v_L[i] = Rz(vertical.yaw).transpose() * (vertical.X_W[i] - vertical.p_W);
    upright_p2p(vertical.v_L, vertical.X_W, &solutions);
    for (const auto& s : solutions) ASSERT_TRUE(s.p_W.allFinite());
    EXPECT_LT(BestError(vertical, solutions), 1e-6) << "instance " << n;
  }
}

TEST(UprightP2pTest, NoisyBearingsGiveNearbySolutions) {
  // With 1e-3 rad of bearing noise the solutions move by about depth * 1e-3 / baseline angle.
  Rng rng(std::hash<std::string>{}("UprightP2pTest.Noisy"));
  std::vector<UprightPose> solutions;
  int found = 0, tried = 0;
  for (int n = 0; n < 500; ++n) {
    const Eigen::Vector3d d0 =
        Eigen::Vector3d{rng.Uniform(-0.5, 0.5), rng.Uniform(-0.5, 0.5), -1}.normalized();
    const Eigen::Vector3d d1 =
        Eigen::Vector3d{rng.Uniform(-0.5, 0.5), rng.Uniform(-0.5, 0.5), -1}.normalized();
    if (d0.cross(d1).norm() < 0.3) continue;
    Instance instance = MakeInstance(rng, {d0, d1});
    ++tried;
    for (auto& v : instance.v_L) v = ExpSO3(rng.Gaussian3(1e-3)) * v;
    upright_p2p(instance.v_L, instance.X_W, &solutions);
    for (const auto& s : solutions) ASSERT_TRUE(s.p_W.allFinite());
    if (!solutions.empty() && BestError(instance, solutions) < 0.2)
      ++found;
    else if (solutions.empty())
      ADD_FAILURE() << "no solution for a well-conditioned noisy pair";
  }
  EXPECT_GE(found, 0.95 * tried) << found << " of " << tried;
}

}  // namespace
}  // namespace mavloc
