// Residuals of the smoother: each one is zero at a consistent state, non-zero away from it, and
// its Jacobians (analytic or automatic differentiation, in the manifold tangent spaces) agree with
// central differences (tests/test_support.h). The IMU factor's analytic Jacobians are checked more
// widely in imu_factor_jacobian_test.cc.
#include <ceres/manifold.h>
#include <ceres/sphere_manifold.h>
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <vector>

#include "core/random.h"
#include "core/rotation.h"
#include "solver/smoother/imu_preintegration.h"
#include "solver/smoother/imu_time_shift.h"
#include "solver/smoother/residuals/anchored_bearing_factor.h"
#include "solver/smoother/residuals/bias_random_walk_factor.h"
#include "solver/smoother/residuals/calibrated_reprojection_factor.h"
#include "solver/smoother/residuals/feature_bearing_factor.h"
#include "solver/smoother/residuals/imu_factor.h"
#include "solver/smoother/residuals/laser_spot_plane_factor.h"
#include "solver/smoother/residuals/map_point_reprojection_factor.h"
#include "solver/smoother/residuals/marginal_prior_factor.h"
#include "solver/smoother/residuals/pose_prior_factor.h"
#include "solver/smoother/residuals/vector_prior_factor.h"
#include "solver/smoother/tilt_manifold.h"
#include "tests/test_support.h"

namespace mavloc {
namespace {

// Parameter storage for a cost function: quaternion blocks in Eigen order (x, y, z, w).
struct Blocks {
  std::vector<std::vector<double>> values;
  std::vector<const ceres::Manifold*> manifolds;
  std::vector<double*> Pointers() {
    std::vector<double*> p;
    for (auto& v : values) p.push_back(v.data());
    return p;
  }
  void AddQuaternion(const Eigen::Quaterniond& q, const ceres::Manifold* manifold) {
    values.push_back({q.x(), q.y(), q.z(), q.w()});
    manifolds.push_back(manifold);
  }
  void AddVector(const Eigen::VectorXd& v, const ceres::Manifold* manifold = nullptr) {
    values.emplace_back(v.data(), v.data() + v.size());
    manifolds.push_back(manifold);
  }
};

Eigen::VectorXd Evaluate(const ceres::CostFunction& cost, Blocks& blocks) {
  Eigen::VectorXd r(cost.num_residuals());
  const std::vector<double*> p = blocks.Pointers();
  EXPECT_TRUE(cost.Evaluate(p.data(), r.data(), nullptr));
  return r;
}

// Jacobians of the cost function (analytic or autodiff, mapped into each block's tangent
// space with the manifold's PlusJacobian) against central differences of r(x [+] delta) with the
// shared helper.
void ExpectJacobiansCorrect(const ceres::CostFunction& cost, Blocks& blocks,
                            double tolerance = 1e-6) {
  const int num_residuals = cost.num_residuals();
  std::vector<double*> p = blocks.Pointers();
  std::vector<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> ambient;
  std::vector<double*> jacobian_ptrs;
  for (const auto& v : blocks.values) {
    ambient.emplace_back(num_residuals, static_cast<int>(v.size()));
    jacobian_ptrs.push_back(ambient.back().data());
  }
  Eigen::VectorXd r0(num_residuals);
  ASSERT_TRUE(cost.Evaluate(p.data(), r0.data(), jacobian_ptrs.data()));
  double largest = 0.0;
  for (size_t b = 0; b < blocks.values.size(); ++b) {
    const ceres::Manifold* manifold = blocks.manifolds[b];
    const int ambient_size = static_cast<int>(blocks.values[b].size());
    const int tangent_size = manifold ? manifold->TangentSize() : ambient_size;
    Eigen::MatrixXd plus_jacobian = Eigen::MatrixXd::Identity(ambient_size, tangent_size);
    if (manifold) {
      Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> J(ambient_size,
                                                                               tangent_size);
      manifold->PlusJacobian(blocks.values[b].data(), J.data());
      plus_jacobian = J;
    }
    const Eigen::MatrixXd analytic = ambient[b] * plus_jacobian;
    const std::vector<double> x0 = blocks.values[b];
    auto f = [&](const Eigen::VectorXd& delta) -> Eigen::VectorXd {
      std::vector<double> x(x0.size());
      if (manifold) {
        manifold->Plus(x0.data(), delta.data(), x.data());
      } else {
        for (int k = 0; k < ambient_size; ++k) x[k] = x0[k] + delta[k];
      }
      Blocks moved = blocks;
      moved.values[b] = x;
      std::vector<double*> moved_ptrs = moved.Pointers();
      Eigen::VectorXd r(num_residuals);
      EXPECT_TRUE(cost.Evaluate(moved_ptrs.data(), r.data(), nullptr));
      return r;
    };
    auto minus = [](const Eigen::VectorXd& a, const Eigen::VectorXd& c) -> Eigen::VectorXd {
      return a - c;
    };
    const Eigen::MatrixXd numeric =
        testing::CentralDifferenceJacobian(f, tangent_size, minus, 1e-6);
    const double scale = 1.0 + analytic.cwiseAbs().maxCoeff();
    EXPECT_LT((numeric - analytic).cwiseAbs().maxCoeff(), tolerance * scale)
        << "block " << b << "\nanalytic\n"
        << analytic << "\nnumeric\n"
        << numeric;
    largest = std::max(largest, analytic.cwiseAbs().maxCoeff());
  }
  // The check is not vacuous: some Jacobian entry is far from zero.
  EXPECT_GT(largest, 1e-3);
}

// The Jacobian of every block in its tangent space (ambient Jacobian times PlusJacobian), side by
// side: rows = residuals, columns = the blocks' tangent coordinates in order.
Eigen::MatrixXd TangentJacobian(const ceres::CostFunction& cost, Blocks& blocks) {
  const int num_residuals = cost.num_residuals();
  std::vector<double*> p = blocks.Pointers();
  std::vector<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> ambient;
  std::vector<double*> jacobian_ptrs;
  int columns = 0;
  for (size_t b = 0; b < blocks.values.size(); ++b) {
    ambient.emplace_back(num_residuals, static_cast<int>(blocks.values[b].size()));
    jacobian_ptrs.push_back(ambient.back().data());
    columns += blocks.manifolds[b] ? blocks.manifolds[b]->TangentSize()
                                   : static_cast<int>(blocks.values[b].size());
  }
  Eigen::VectorXd r(num_residuals);
  EXPECT_TRUE(cost.Evaluate(p.data(), r.data(), jacobian_ptrs.data()));
  Eigen::MatrixXd out(num_residuals, columns);
  int column = 0;
  for (size_t b = 0; b < blocks.values.size(); ++b) {
    const ceres::Manifold* manifold = blocks.manifolds[b];
    const int ambient_size = static_cast<int>(blocks.values[b].size());
    Eigen::MatrixXd plus = Eigen::MatrixXd::Identity(ambient_size, ambient_size);
    if (manifold) {
      Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> P(
          ambient_size, manifold->TangentSize());
      manifold->PlusJacobian(blocks.values[b].data(), P.data());
      plus = P;
    }
    out.middleCols(column, plus.cols()) = ambient[b] * plus;
    column += static_cast<int>(plus.cols());
  }
  return out;
}

Eigen::Quaterniond RandomRotation(Rng& rng, double scale = 1.0) {
  return ExpQuaternion(rng.Gaussian3(scale));
}

Pose TestExtrinsic() {
  // Camera looking down (z_C = -z_B), x_C = x_B, offset 5 cm.
  return Pose(Eigen::Quaterniond(Rx(M_PI)), Eigen::Vector3d(0.05, 0.0, -0.02));
}

class ResidualTest : public ::testing::Test {
 protected:
  ceres::EigenQuaternionManifold quaternion_manifold_;
  Rng rng_{42};
};

TEST_F(ResidualTest, ImuFactorIsZeroAtThePredictedStateAndHasCorrectJacobians) {
  // A short stream of rotating, accelerating samples.
  std::vector<ImuSample> samples;
  for (int k = 0; k <= 60; ++k) {
    const double t = 0.01 * k;
    ImuSample s;
    s.t_ns = SecondsToNs(t);
    s.gyro_rad_s = Eigen::Vector3d(0.3 * std::sin(3 * t), -0.2, 0.5 * std::cos(2 * t));
    s.accel_m_s2 = Eigen::Vector3d(0.5 * std::cos(t), 0.2, 9.6 + 0.3 * std::sin(4 * t));
    samples.push_back(s);
  }
  ImuNoise noise;
  noise.gyroscope_noise_density = 2e-3;
  noise.accelerometer_noise_density = 2e-2;
  ImuBiases b0;
  b0.b_g = Eigen::Vector3d(0.01, 0.02, -0.01);
  b0.b_a = Eigen::Vector3d(0.05, -0.03, 0.1);
  const ImuPreintegration pre(samples, SecondsToNs(0.055), SecondsToNs(0.455), b0, noise);
  const Eigen::Matrix<double, 9, 9> L = pre.SqrtInformation();
  std::unique_ptr<ceres::CostFunction> cost(ImuFactor::Create(pre, L));

  ImuKeyframeState s_i;
  s_i.q_W_B = RandomRotation(rng_);
  s_i.p_W = Eigen::Vector3d(1, 2, 3);
  s_i.v_W = Eigen::Vector3d(0.3, -0.2, 0.1);
  s_i.biases = b0;
  s_i.biases.b_g += Eigen::Vector3d(1e-3, -2e-3, 5e-4);  // away from the linearization point
  s_i.biases.b_a += Eigen::Vector3d(1e-2, 0.0, -1e-2);
  const ImuKeyframeState s_j = pre.Predict(s_i);

  Blocks blocks;
  blocks.AddQuaternion(s_i.q_W_B, &quaternion_manifold_);
  blocks.AddVector(s_i.p_W);
  blocks.AddVector(s_i.v_W);
  blocks.AddVector(s_i.biases.b_g);
  blocks.AddVector(s_i.biases.b_a);
  blocks.AddQuaternion(s_j.q_W_B, &quaternion_manifold_);
  blocks.AddVector(s_j.p_W);
  blocks.AddVector(s_j.v_W);
  EXPECT_LT(Evaluate(*cost, blocks).norm(), 1e-6);

  blocks.values[6][2] += 0.01;  // move p_j by 1 cm: the whitened residual grows a lot
  EXPECT_GT(Evaluate(*cost, blocks).norm(), 1.0);
  ExpectJacobiansCorrect(*cost, blocks);
}

TEST_F(ResidualTest, BiasRandomWalkFactor) {
  std::unique_ptr<ceres::CostFunction> cost(BiasRandomWalkFactor::Create(2e-5, 3e-3, 0.1));
  Blocks blocks;
  blocks.AddVector(Eigen::Vector3d(0.01, 0.02, 0.03));
  blocks.AddVector(Eigen::Vector3d(0.1, 0.2, 0.3));
  blocks.AddVector(Eigen::Vector3d(0.01, 0.02, 0.03));
  blocks.AddVector(Eigen::Vector3d(0.1, 0.2, 0.3));
  EXPECT_LT(Evaluate(*cost, blocks).norm(), 1e-12);
  blocks.values[3][0] += 1e-3;
  const Eigen::VectorXd r = Evaluate(*cost, blocks);
  EXPECT_NEAR(r[3], 1e-3 / std::sqrt(9e-6 * 0.1 + 1e-10), 1e-6);
  ExpectJacobiansCorrect(*cost, blocks);
}

TEST_F(ResidualTest, MarginalPriorFactorIsLinearInTheTangentAtItsLinearizationPoint) {
  KeyframeMarginalPrior prior;
  prior.linearization.q_W_B = RandomRotation(rng_);
  prior.linearization.p_W = Eigen::Vector3d(1.0, -2.0, 0.5);
  prior.linearization.v_W = Eigen::Vector3d(0.3, 0.1, -0.2);
  prior.linearization.biases.b_g = Eigen::Vector3d(1e-3, -2e-3, 5e-4);
  prior.linearization.biases.b_a = Eigen::Vector3d(0.05, -0.02, 0.01);
  for (int i = 0; i < 15; ++i) {
    for (int j = i; j < 15; ++j) prior.sqrt_information(i, j) = rng_.Uniform(-1.0, 1.0);
    prior.sqrt_information(i, i) = rng_.Uniform(5.0, 50.0);
    prior.offset[i] = rng_.Uniform(-1.0, 1.0);
  }
  const MarginalPriorFactor cost(prior);
  const auto blocks_at = [&](const ImuKeyframeState& x) {
    Blocks blocks;
    blocks.AddQuaternion(x.q_W_B, &quaternion_manifold_);
    for (const Eigen::Vector3d& v : {x.p_W, x.v_W, x.biases.b_g, x.biases.b_a}) blocks.AddVector(v);
    return blocks;
  };
  // At the linearization point: r = e, and the tangent Jacobian is R exactly.
  Blocks at_lin = blocks_at(prior.linearization);
  EXPECT_LT((Evaluate(cost, at_lin) - prior.offset).norm(), 1e-12);
  ExpectJacobiansCorrect(cost, at_lin);
  EXPECT_LT((TangentJacobian(cost, at_lin) - prior.sqrt_information).cwiseAbs().maxCoeff(), 1e-12);
  // Away from it: r = R delta + e with delta Ceres' quaternion difference (a rotation by 2 |delta|
  // about delta's axis, applied on the left).
  ImuKeyframeState moved = prior.linearization;
  const Eigen::Vector3d delta_q(0.01, -0.02, 0.015);
  moved.q_W_B = ExpQuaternion(2.0 * delta_q) * prior.linearization.q_W_B;
  moved.p_W += Eigen::Vector3d(0.1, 0.2, -0.1);
  moved.biases.b_a += Eigen::Vector3d(0.01, 0.0, -0.01);
  Vector15d delta = Vector15d::Zero();
  delta.head<3>() = delta_q;
  delta.segment<3>(3) = Eigen::Vector3d(0.1, 0.2, -0.1);
  delta.segment<3>(12) = Eigen::Vector3d(0.01, 0.0, -0.01);
  Blocks at_moved = blocks_at(moved);
  EXPECT_LT((Evaluate(cost, at_moved) - (prior.sqrt_information * delta + prior.offset)).norm(),
            1e-9);
}

TEST_F(ResidualTest, PosePriorFactor) {
  const Pose prior(RandomRotation(rng_), Eigen::Vector3d(1, -2, 0.5));
  Eigen::Matrix<double, 6, 6> L = Eigen::Matrix<double, 6, 6>::Identity();
  L.topLeftCorner<3, 3>() *= 100.0;
  std::unique_ptr<ceres::CostFunction> cost(PosePriorFactor::Create(prior, L));
  Blocks blocks;
  blocks.AddQuaternion(prior.q, &quaternion_manifold_);
  blocks.AddVector(prior.p);
  EXPECT_LT(Evaluate(*cost, blocks).norm(), 1e-12);
  const Eigen::Vector3d dphi(0.01, -0.02, 0.005);
  const Eigen::Quaterniond q = prior.q * ExpQuaternion(dphi);
  blocks.values[0] = {q.x(), q.y(), q.z(), q.w()};
  EXPECT_LT((Evaluate(*cost, blocks).head<3>() - 100.0 * dphi).norm(), 1e-9);
  ExpectJacobiansCorrect(*cost, blocks);

  std::unique_ptr<ceres::CostFunction> vector_cost(
      VectorPriorFactor::Create(Eigen::Vector3d(1, 2, 3), 0.5));
  Blocks vector_blocks;
  vector_blocks.AddVector(Eigen::Vector3d(1.5, 2, 3));
  EXPECT_NEAR(Evaluate(*vector_cost, vector_blocks)[0], 1.0, 1e-12);
  ExpectJacobiansCorrect(*vector_cost, vector_blocks);
}

TEST_F(ResidualTest, MapPointReprojectionFactorWithDistortion) {
  const CameraModel camera(752, 480, Eigen::Vector4d(458.7, 457.3, 367.2, 248.4),
                           DistortionModel::kRadialTangential, {-0.28, 0.07, 2e-4, 1.8e-5});
  const Pose T_B_C = TestExtrinsic();
  const Pose T_W_B(ExpQuaternion(Eigen::Vector3d(0.1, -0.05, 0.7)), Eigen::Vector3d(0.3, 0.2, 1.5));
  const Eigen::Vector3d p_W(0.5, 0.1, 0.0);  // on the ground, below the camera
  const Eigen::Vector3d p_C = (T_W_B * T_B_C).Inverse() * p_W;
  ASSERT_GT(p_C.z(), 0.0);
  const Eigen::Vector2d uv = *camera.Project(p_C);
  std::unique_ptr<ceres::CostFunction> cost(
      MapPointReprojectionFactor::Create(camera, T_B_C, p_W, uv, 0.5));
  Blocks blocks;
  blocks.AddQuaternion(T_W_B.q, &quaternion_manifold_);
  blocks.AddVector(T_W_B.p);
  EXPECT_LT(Evaluate(*cost, blocks).norm(), 1e-9);
  blocks.values[1][0] += 0.01;
  EXPECT_GT(Evaluate(*cost, blocks).norm(), 1.0);
  ExpectJacobiansCorrect(*cost, blocks);
}

// The analytic map-point Jacobians against central differences and against the autodiff
// reference, on random body poses around points in front of the camera.
TEST_F(ResidualTest, MapPointReprojectionAnalyticMatchesAutoDiffOnRandomPoses) {
  const CameraModel camera(752, 480, Eigen::Vector4d(458.7, 457.3, 367.2, 248.4),
                           DistortionModel::kRadialTangential, {-0.28, 0.07, 2e-4, 1.8e-5});
  const Pose T_B_C = TestExtrinsic();
  for (int trial = 0; trial < 20; ++trial) {
    const Pose T_W_B(RandomRotation(rng_, 0.3), rng_.Gaussian3(2.0));
    // A point 1-4 m in front of the camera, seen off-centre; the measurement a few pixels off.
    const Pose T_W_C = T_W_B * T_B_C;
    const Eigen::Vector3d p_C(rng_.Gaussian() * 0.3, rng_.Gaussian() * 0.2,
                              1.0 + 3.0 * rng_.Uniform());
    const Eigen::Vector3d p_W = T_W_C * p_C;
    const Eigen::Vector2d uv = *camera.Project(p_C) + 2.0 * rng_.GaussianVector<2>();
    std::unique_ptr<ceres::CostFunction> analytic(
        MapPointReprojectionFactor::Create(camera, T_B_C, p_W, uv, 0.7));
    std::unique_ptr<ceres::CostFunction> autodiff(
        MapPointReprojectionFactorAutoDiff::Create(camera, T_B_C, p_W, uv, 0.7));
    Blocks blocks;
    blocks.AddQuaternion(T_W_B.q, &quaternion_manifold_);
    blocks.AddVector(T_W_B.p);
    ExpectJacobiansCorrect(*analytic, blocks);
    const Eigen::MatrixXd J_analytic = TangentJacobian(*analytic, blocks);
    const Eigen::MatrixXd J_autodiff = TangentJacobian(*autodiff, blocks);
    EXPECT_LT((J_analytic - J_autodiff).cwiseAbs().maxCoeff(),
              1e-12 * (1.0 + J_autodiff.cwiseAbs().maxCoeff()))
        << "trial " << trial;
    EXPECT_LT((Evaluate(*analytic, blocks) - Evaluate(*autodiff, blocks)).norm(), 1e-12);
  }
}

TEST_F(ResidualTest, FeatureBearingFactorWithUnknownLandmark) {
  // Camera at the body origin, so that rotating the body rotates the bearing by the same angle.
  const Pose T_B_C(Eigen::Quaterniond(Rx(M_PI)), Eigen::Vector3d::Zero());
  const Pose T_W_B(ExpQuaternion(Eigen::Vector3d(-0.1, 0.15, 2.0)),
                   Eigen::Vector3d(0.1, -0.2, 1.2));
  const Eigen::Vector3d p_W(0.25, 0.1, 0.0);
  const Eigen::Vector3d p_C = (T_W_B * T_B_C).Inverse() * p_W;
  const Eigen::Vector2d xy(p_C.x() / p_C.z(), p_C.y() / p_C.z());
  std::unique_ptr<ceres::CostFunction> cost(FeatureBearingFactor::Create(T_B_C, xy, 0.01));
  Blocks blocks;
  blocks.AddQuaternion(T_W_B.q, &quaternion_manifold_);
  blocks.AddVector(T_W_B.p);
  blocks.AddVector(p_W);
  EXPECT_LT(Evaluate(*cost, blocks).norm(), 1e-9);
  // Rotating the vehicle by a small angle about an axis perpendicular to the bearing moves the
  // residual by that angle / sigma.
  const Eigen::Vector3d bearing_B = T_B_C.q * p_C.normalized();
  const Eigen::Vector3d axis_B = bearing_B.cross(Eigen::Vector3d::UnitZ()).normalized();
  const Eigen::Quaterniond q = T_W_B.q * ExpQuaternion(1e-4 * axis_B);
  blocks.values[0] = {q.x(), q.y(), q.z(), q.w()};
  EXPECT_NEAR(Evaluate(*cost, blocks).norm(), 1e-4 / 0.01, 1e-6);
  blocks.values[2][1] += 0.02;
  ExpectJacobiansCorrect(*cost, blocks);
}

TEST_F(ResidualTest, LaserSpotPlaneFactor) {
  // The paper's geometry: laser at (L, 0, 0) along z_C; a plane tilted 22.5 deg from horizontal.
  const Pose T_B_C = TestExtrinsic();
  const Eigen::Vector3d o_C(0.3, 0.0, 0.0), l_C(0.0, 0.0, 1.0);
  const double alpha = M_PI / 8.0;
  const Eigen::Vector3d n_W(0.0, -std::sin(alpha), std::cos(alpha));
  const double d_m = 0.2;
  const Pose T_W_B(ExpQuaternion(Eigen::Vector3d(0.05, -0.1, 0.4)), Eigen::Vector3d(0.2, 0.4, 2.0));
  // The true spot, for the measurement.
  const Pose T_W_C = T_W_B * T_B_C;
  const Eigen::Vector3d o_W = T_W_C * o_C, l_W = T_W_C.q * l_C;
  const double s = (d_m - n_W.dot(o_W)) / n_W.dot(l_W);
  ASSERT_GT(s, 0.0);
  const Eigen::Vector3d x_C = o_C + s * l_C;
  const Eigen::Vector2d xy(x_C.x() / x_C.z(), x_C.y() / x_C.z());
  std::unique_ptr<ceres::CostFunction> cost(
      LaserSpotPlaneFactor::Create(T_B_C, o_C, l_C, xy, 0.01));
  ceres::SphereManifold<3> sphere;
  Blocks blocks;
  blocks.AddQuaternion(T_W_B.q, &quaternion_manifold_);
  blocks.AddVector(T_W_B.p);
  blocks.AddVector(n_W, &sphere);
  blocks.AddVector(Eigen::VectorXd::Constant(1, d_m));
  EXPECT_LT(Evaluate(*cost, blocks).norm(), 1e-9);
  blocks.values[3][0] += 0.05;  // the plane 5 cm further: the spot moves in the image
  EXPECT_GT(Evaluate(*cost, blocks).norm(), 0.1);
  ExpectJacobiansCorrect(*cost, blocks);

  // Degenerate: the ray parallel to the plane gives no residual (evaluation fails).
  Blocks parallel = blocks;
  const Eigen::Vector3d n_parallel = l_W.cross(Eigen::Vector3d::UnitX()).normalized();
  parallel.values[2] = {n_parallel.x(), n_parallel.y(), n_parallel.z()};
  Eigen::Vector2d r;
  const std::vector<double*> p = parallel.Pointers();
  EXPECT_FALSE(cost->Evaluate(p.data(), r.data(), nullptr));
}

// A rotating, accelerating IMU stream at 200 Hz over 1 s (smooth signals).
std::vector<ImuSample> SmoothImuStream() {
  std::vector<ImuSample> samples;
  for (int k = 0; k <= 200; ++k) {
    const double t = 0.005 * k;
    ImuSample s;
    s.t_ns = SecondsToNs(t);
    s.gyro_rad_s = Eigen::Vector3d(0.8 * std::sin(3 * t), -0.5 + 0.3 * t, 1.2 * std::cos(2 * t));
    s.accel_m_s2 = Eigen::Vector3d(2.0 * std::cos(4 * t), 0.7, 9.6 + 1.5 * std::sin(5 * t));
    samples.push_back(s);
  }
  return samples;
}

TEST_F(ResidualTest, TiltManifoldMovesOnlyTheGravityDirection) {
  const TiltManifold manifold;
  const Eigen::Quaterniond q = RandomRotation(rng_);
  const double x[4] = {q.x(), q.y(), q.z(), q.w()};
  const double delta[2] = {0.03, -0.02};
  double y[4], back[2];
  ASSERT_TRUE(manifold.Plus(x, delta, y));
  ASSERT_TRUE(manifold.Minus(y, x, back));
  EXPECT_NEAR(back[0], delta[0], 1e-12);
  EXPECT_NEAR(back[1], delta[1], 1e-12);
  // y = Exp((d1, d2, 0)) x: the rotation between them has no component about z_W.
  const Eigen::Quaterniond qy(y[3], y[0], y[1], y[2]);
  EXPECT_NEAR(LogQuaternion(qy * q.conjugate()).z(), 0.0, 1e-12);
  // PlusJacobian against central differences of Plus; MinusJacobian is its left inverse.
  Eigen::Matrix<double, 4, 2, Eigen::RowMajor> J_plus;
  Eigen::Matrix<double, 2, 4, Eigen::RowMajor> J_minus;
  ASSERT_TRUE(manifold.PlusJacobian(x, J_plus.data()));
  ASSERT_TRUE(manifold.MinusJacobian(x, J_minus.data()));
  auto plus = [&](const Eigen::VectorXd& d) -> Eigen::VectorXd {
    double out[4];
    manifold.Plus(x, d.data(), out);
    return Eigen::Vector4d(out[0], out[1], out[2], out[3]);
  };
  const Eigen::MatrixXd numeric =
      testing::CentralDifferenceJacobian(plus, Eigen::VectorXd::Zero(2), 1e-6);
  EXPECT_LT((numeric - Eigen::MatrixXd(J_plus)).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_LT((J_minus * J_plus - Eigen::Matrix2d::Identity()).cwiseAbs().maxCoeff(), 1e-12);
  // MinusJacobian against central differences of Minus(x [+] d, x) in the ambient space.
  auto minus = [&](const Eigen::VectorXd& y_ambient) -> Eigen::VectorXd {
    Eigen::Vector4d unit = y_ambient.normalized();
    double out[2];
    manifold.Minus(unit.data(), x, out);
    return Eigen::Vector2d(out[0], out[1]);
  };
  const Eigen::MatrixXd numeric_minus =
      testing::CentralDifferenceJacobian(minus, Eigen::Vector4d(x[0], x[1], x[2], x[3]), 1e-6);
  // Along the tangent directions (what Ceres uses) the two agree.
  EXPECT_LT(((numeric_minus - Eigen::MatrixXd(J_minus)) * J_plus).cwiseAbs().maxCoeff(), 1e-8);
}

TEST_F(ResidualTest, ImuTimeShiftPolynomialMatchesTheIntegratedMotion) {
  const std::vector<ImuSample> samples = SmoothImuStream();
  ImuBiases biases;
  biases.b_g = Eigen::Vector3d(0.01, -0.02, 0.005);
  biases.b_a = Eigen::Vector3d(0.05, 0.0, -0.1);
  const TimeNs t_k = SecondsToNs(0.4321);
  double fit_error = 1.0;
  const ImuTimeShift shift = FitImuTimeShift(samples, t_k, biases, 0.03, &fit_error);
  EXPECT_LT(fit_error, 1e-10);
  for (const double tau : {-0.029, -0.0123, -0.001, 0.0, 0.0005, 0.0077, 0.025}) {
    Eigen::Quaterniond dq;
    Eigen::Vector3d dp;
    IntegrateImuTimeShift(samples, t_k, biases, tau, &dq, &dp);
    Eigen::Vector3d phi, dp_fit;
    shift.Evaluate(tau, phi.data(), dp_fit.data());
    EXPECT_LT(LogQuaternion(ExpQuaternion(phi).conjugate() * dq).norm(), 1e-10) << tau;
    EXPECT_LT((dp_fit - dp).norm(), 1e-10) << tau;
  }
  // The integrated motion itself: to first order R Exp((w - b_g) tau), 1/2 (a - b_a) tau^2.
  Eigen::Quaterniond dq;
  Eigen::Vector3d dp;
  const double tau = -0.004;
  IntegrateImuTimeShift(samples, t_k, biases, tau, &dq, &dp);
  const ImuIntegrator integrator(&samples);
  Eigen::Vector3d w, f;
  integrator.SignalAt(t_k, 0.0, biases, &w, &f);
  EXPECT_LT((LogQuaternion(dq) - w * tau).norm(), 5e-5);
  EXPECT_LT((dp - 0.5 * f * tau * tau).norm(), 1e-6);
}

TEST_F(ResidualTest, CalibratedReprojectionFactorWithTimeOffsetTiltAndExtrinsic) {
  const CameraModel camera(752, 480, Eigen::Vector4d(458.7, 457.3, 367.2, 248.4),
                           DistortionModel::kRadialTangential, {-0.28, 0.07, 2e-4, 1.8e-5});
  const std::vector<ImuSample> samples = SmoothImuStream();
  const TimeNs t_k = SecondsToNs(0.5);
  const double t_d = 0.0042;
  const auto shift =
      std::make_shared<const ImuTimeShift>(FitImuTimeShift(samples, t_k, ImuBiases{}, 0.03));
  // Keyframe state at t_k, the board tilted, the camera looking at the point.
  const Pose T_W_B(ExpQuaternion(Eigen::Vector3d(0.1, -0.05, 0.7)), Eigen::Vector3d(0.3, 0.2, 1.5));
  const Eigen::Vector3d v_W(0.4, -0.3, 0.2);
  const Eigen::Quaterniond q_W_M = ExpQuaternion(Eigen::Vector3d(1.4, 0.2, 0.3));
  const Pose T_B_C = TestExtrinsic();
  // The pose at t_k + t_d by direct integration; a point 1 m in front of that camera.
  Eigen::Quaterniond dq;
  Eigen::Vector3d dp;
  IntegrateImuTimeShift(samples, t_k, ImuBiases{}, t_d, &dq, &dp);
  const Pose T_W_Bt(T_W_B.q * dq,
                    T_W_B.p + v_W * t_d + 0.5 * GravityW() * t_d * t_d + T_W_B.q * dp);
  const Pose T_W_Ct = T_W_Bt * T_B_C;
  const Eigen::Vector3d p_W = T_W_Ct * Eigen::Vector3d(0.1, -0.05, 1.0);
  const Eigen::Vector3d p_M = q_W_M.conjugate() * p_W;
  const Eigen::Vector2d uv = *camera.Project(T_W_Ct.Inverse() * p_W);
  std::unique_ptr<ceres::CostFunction> cost(
      CalibratedReprojectionFactor::Create(camera, shift, p_M, uv, 0.5));
  const TiltManifold tilt;
  Blocks blocks;
  blocks.AddQuaternion(T_W_B.q, &quaternion_manifold_);
  blocks.AddVector(T_W_B.p);
  blocks.AddVector(v_W);
  blocks.AddQuaternion(q_W_M, &tilt);
  blocks.AddQuaternion(T_B_C.q, &quaternion_manifold_);
  blocks.AddVector(T_B_C.p);
  blocks.AddVector(Eigen::VectorXd::Constant(1, t_d));
  EXPECT_LT(Evaluate(*cost, blocks).norm(), 1e-7);
  // A millisecond of time offset moves the corner by about (image speed) x 1 ms.
  Blocks shifted = blocks;
  shifted.values[6][0] += 0.001;
  EXPECT_GT(Evaluate(*cost, shifted).norm(), 0.05);
  ExpectJacobiansCorrect(*cost, blocks);

  // With t_d = 0, the identity tilt and no velocity it is MapPointReprojectionFactor.
  std::unique_ptr<ceres::CostFunction> fixed(
      MapPointReprojectionFactor::Create(camera, T_B_C, p_W, uv, 0.5));
  std::unique_ptr<ceres::CostFunction> general(
      CalibratedReprojectionFactor::Create(camera, shift, p_W, uv, 0.5));
  Blocks a, b;
  a.AddQuaternion(T_W_B.q, &quaternion_manifold_);
  a.AddVector(T_W_B.p);
  b = a;
  b.AddVector(v_W);
  b.AddQuaternion(Eigen::Quaterniond::Identity(), &tilt);
  b.AddQuaternion(T_B_C.q, &quaternion_manifold_);
  b.AddVector(T_B_C.p);
  b.AddVector(Eigen::VectorXd::Zero(1));
  EXPECT_LT((Evaluate(*fixed, a) - Evaluate(*general, b)).norm(), 1e-12);
}

}  // namespace
}  // namespace mavloc

namespace mavloc {
namespace {

// An anchored track seen from two keyframes: zero residual at the truth, a residual that a wrong
// inverse depth makes, and Jacobians against central differences on the manifold.
TEST_F(ResidualTest, AnchoredBearingFactorOverTwoKeyframes) {
  const Pose T_B_C = TestExtrinsic();
  const Pose T_W_Ba(ExpQuaternion(Eigen::Vector3d(0.05, -0.1, 0.3)), Eigen::Vector3d(0, 0, 1));
  const Pose T_W_Bo(ExpQuaternion(Eigen::Vector3d(0.02, 0.08, 0.5)),
                    Eigen::Vector3d(0.4, -0.2, 1.1));
  const Eigen::Vector3d b_Ca = Eigen::Vector3d(0.1, -0.2, 1.0).normalized();
  const double depth_m = 2.5;
  const Eigen::Vector3d p_W = (T_W_Ba * T_B_C) * Eigen::Vector3d(depth_m * b_Ca);
  const Eigen::Vector3d p_Co = (T_W_Bo * T_B_C).Inverse() * p_W;
  const Eigen::Vector2d xy(p_Co.x() / p_Co.z(), p_Co.y() / p_Co.z());
  std::unique_ptr<ceres::CostFunction> cost(
      AnchoredBearingFactor::Create(T_B_C, b_Ca, T_B_C, xy, 0.002));
  Blocks blocks;
  blocks.AddQuaternion(T_W_Ba.q, &quaternion_manifold_);
  blocks.AddVector(T_W_Ba.p);
  blocks.AddQuaternion(T_W_Bo.q, &quaternion_manifold_);
  blocks.AddVector(T_W_Bo.p);
  blocks.AddVector(Eigen::VectorXd::Constant(1, 1.0 / depth_m));
  EXPECT_LT(Evaluate(*cost, blocks).norm(), 1e-9);
  blocks.values[4][0] = 1.0 / 4.0;  // the point placed too far
  EXPECT_GT(Evaluate(*cost, blocks).norm(), 1.0);
  ExpectJacobiansCorrect(*cost, blocks);
  blocks.values[4][0] = 0.0;  // at infinity: a direction, still a finite residual
  EXPECT_TRUE(Evaluate(*cost, blocks).allFinite());
  ExpectJacobiansCorrect(*cost, blocks);
}

// The analytic Jacobians against central differences and the automatic ones on random poses,
// bearings and depths (near, far and at infinity).
TEST_F(ResidualTest, AnchoredBearingFactorAnalyticMatchesAutoDiff) {
  const Pose T_B_Ca = TestExtrinsic();
  const Pose T_B_Co = T_B_Ca * Pose(Eigen::Quaterniond(Rz(0.02)), Eigen::Vector3d(0.11, 0, 0));
  for (int trial = 0; trial < 20; ++trial) {
    const Pose T_W_Ba(RandomRotation(rng_, 0.5), rng_.Gaussian3(1.0));
    const Pose T_W_Bo(RandomRotation(rng_, 0.5), rng_.Gaussian3(1.0));
    const Eigen::Vector3d b_Ca(0.3 * rng_.Gaussian(), 0.3 * rng_.Gaussian(), 1.0);
    const Eigen::Vector2d xy = 0.3 * rng_.GaussianVector<2>();
    const double rho = trial % 5 == 0 ? 0.0 : std::exp(rng_.Gaussian()) / 3.0;
    std::unique_ptr<ceres::CostFunction> analytic(
        AnchoredBearingFactor::Create(T_B_Ca, b_Ca, T_B_Co, xy, 0.002));
    std::unique_ptr<ceres::CostFunction> autodiff(
        AnchoredBearingFactorAutoDiff::Create(T_B_Ca, b_Ca, T_B_Co, xy, 0.002));
    Blocks blocks;
    blocks.AddQuaternion(T_W_Ba.q, &quaternion_manifold_);
    blocks.AddVector(T_W_Ba.p);
    blocks.AddQuaternion(T_W_Bo.q, &quaternion_manifold_);
    blocks.AddVector(T_W_Bo.p);
    blocks.AddVector(Eigen::VectorXd::Constant(1, rho));
    ExpectJacobiansCorrect(*analytic, blocks);
    const Eigen::MatrixXd J_analytic = TangentJacobian(*analytic, blocks);
    const Eigen::MatrixXd J_autodiff = TangentJacobian(*autodiff, blocks);
    EXPECT_LT((J_analytic - J_autodiff).cwiseAbs().maxCoeff(),
              1e-9 * (1.0 + J_autodiff.cwiseAbs().maxCoeff()))
        << "trial " << trial;
    EXPECT_LT((Evaluate(*analytic, blocks) - Evaluate(*autodiff, blocks)).norm(), 1e-9);
  }
}

// The second camera of the anchor keyframe constrains the inverse depth alone (stereo).
TEST_F(ResidualTest, AnchorStereoBearingFactor) {
  const Pose T_B_C0 = TestExtrinsic();
  const Pose T_B_C1 = T_B_C0 * Pose(Eigen::Quaterniond(Rz(0.01)), Eigen::Vector3d(0.11, 0, 0));
  const Eigen::Vector3d b_C0 = Eigen::Vector3d(-0.2, 0.1, 1.0).normalized();
  const double depth_m = 1.8;
  const Eigen::Vector3d p_C1 = (T_B_C1.Inverse() * T_B_C0) * Eigen::Vector3d(depth_m * b_C0);
  const Eigen::Vector2d xy(p_C1.x() / p_C1.z(), p_C1.y() / p_C1.z());
  std::unique_ptr<ceres::CostFunction> cost(
      AnchorStereoBearingFactor::Create(T_B_C0, b_C0, T_B_C1, xy, 0.002));
  Blocks blocks;
  blocks.AddVector(Eigen::VectorXd::Constant(1, 1.0 / depth_m));
  EXPECT_LT(Evaluate(*cost, blocks).norm(), 1e-9);
  blocks.values[0][0] = 1.0 / 3.0;
  EXPECT_GT(Evaluate(*cost, blocks).norm(), 1.0);
  ExpectJacobiansCorrect(*cost, blocks);
}

}  // namespace
}  // namespace mavloc
