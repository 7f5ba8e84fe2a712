// The observable-mode EKF: eq. (9) against rigid-body kinematics, the Jacobians of appendix C
// against central differences (both local decompositions, eq. 10), and convergence on a
// fixed-seed simulated flight near a plane at 22.5 deg.
#include "solver/laser/laser_ekf.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/imu.h"
#include "core/random.h"
#include "core/rotation.h"
#include "tests/test_support.h"

namespace mavloc {
namespace {

LaserState RandomModes(Rng& rng) {
  LaserState m;
  const double tilt = rng.Uniform(0.0, 0.8), heading = rng.Uniform(-M_PI, M_PI);
  m << rng.Uniform(0.3, 2.0), rng.Uniform(-1, 1), tilt * std::cos(heading),
      tilt * std::sin(heading), rng.Uniform(-9.81, -5.0);
  return m;
}

LaserInput RandomInput(Rng& rng) {
  LaserInput u;
  u << rng.Gaussian(0, 3), rng.Gaussian(0, 3), rng.Gaussian(9.81, 3), rng.Gaussian(0, 1),
      rng.Gaussian(0, 1), rng.Gaussian(0, 1);
  return u;
}

TEST(LaserEkf, DynamicsEquation9MatchesRigidBodyKinematics) {
  // d/dt of the modes of a moving camera (exact kinematics) equals f(m, u) of eq. (9) with
  // A = R^T (a - g) and Omega = the body rate, in both decompositions.
  Rng rng(1);
  int positive = 0, negative = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const Plane plane{rng.GaussianVector<3>().normalized(), rng.Uniform(-1, 1)};
    const Eigen::Quaterniond q = Eigen::Quaterniond(rng.GaussianVector<4>()).normalized();
    const Eigen::Vector3d p{rng.Gaussian(), rng.Gaussian(), rng.Gaussian()};
    const Eigen::Vector3d v{rng.Gaussian(), rng.Gaussian(), rng.Gaussian()};
    const Eigen::Vector3d a{rng.Gaussian(), rng.Gaussian(), rng.Gaussian()};
    const Eigen::Vector3d w{rng.Gaussian(), rng.Gaussian(), rng.Gaussian()};
    auto modes_at = [&](double t) {
      const Pose T_W_C(q * ExpQuaternion(w * t), p + v * t + 0.5 * a * t * t);
      return ModesFromPose(T_W_C, v + a * t, plane, GravityW());
    };
    const LaserModes now = modes_at(0.0);
    (now.xi_sign == XiSign::kPositive ? positive : negative)++;
    const double h = 1e-5;
    const LaserState numeric = (modes_at(h).m - modes_at(-h).m) / (2 * h);
    LaserInput u;
    u << q.conjugate() * (a - GravityW()), w;
    const LaserState rate = LaserDynamicsRate(now.m, u, now.xi_sign);
    EXPECT_LT((rate - numeric).norm(), 1e-6 * (1 + rate.norm())) << "trial " << trial;
  }
  EXPECT_GT(positive, 50);
  EXPECT_GT(negative, 50);
}

TEST(LaserEkf, DynamicsJacobiansMatchCentralDifferences) {
  Rng rng(2);
  for (XiSign sign : {XiSign::kPositive, XiSign::kNegative}) {
    for (int trial = 0; trial < 50; ++trial) {
      const LaserState m = RandomModes(rng);
      const LaserInput u = RandomInput(rng);
      const double dt = 0.01;
      LaserCovariance F_m;
      Eigen::Matrix<double, 5, 6> F_u;
      PropagateLaserState(m, u, dt, sign, &F_m, &F_u);
      const Eigen::MatrixXd numeric_m = testing::CentralDifferenceJacobian(
          [&](const Eigen::VectorXd& x) -> Eigen::VectorXd {
            return PropagateLaserState(x, u, dt, sign);
          },
          m);
      const Eigen::MatrixXd numeric_u = testing::CentralDifferenceJacobian(
          [&](const Eigen::VectorXd& x) -> Eigen::VectorXd {
            return PropagateLaserState(m, x, dt, sign);
          },
          u);
      EXPECT_LT((F_m - numeric_m).cwiseAbs().maxCoeff(), 1e-8) << F_m << "\n\n" << numeric_m;
      EXPECT_LT((F_u - numeric_u).cwiseAbs().maxCoeff(), 1e-8) << F_u << "\n\n" << numeric_u;
    }
  }
}

TEST(LaserEkf, ObservationJacobianMatchesCentralDifferences) {
  Rng rng(3);
  for (XiSign sign : {XiSign::kPositive, XiSign::kNegative}) {
    for (int trial = 0; trial < 100; ++trial) {
      const LaserState m = RandomModes(rng);
      const double L = rng.Uniform(0.05, 0.5);
      Eigen::Matrix<double, 1, 5> H;
      const double h = PredictLaserObservation(m, L, sign, &H);
      EXPECT_NEAR(h, PaperObservationEq11(m, L, sign), 1e-15);
      const Eigen::MatrixXd numeric = testing::CentralDifferenceJacobian(
          [&](const Eigen::VectorXd& x) -> Eigen::VectorXd {
            return Eigen::VectorXd::Constant(1, PredictLaserObservation(x, L, sign));
          },
          m);
      EXPECT_LT((H - numeric).cwiseAbs().maxCoeff(), 1e-7 * (1 + H.norm())) << H << "\n" << numeric;
    }
  }
}

// A self-contained flight (the scenario generator lives in datasets/, which solver tests do not
// link): 60 s of piecewise-constant accelerations and body rates at 100 Hz, mean-reverting random
// processes with the sigmas of 5.1.1, IMU noise of 5.1.2 (and optionally the biases of 5.1.3),
// spot bearings at 10 Hz with 1 deg noise, the filter started 10-20 % off.
struct FlightResult {
  std::vector<LaserState> truth;     // at each camera update
  std::vector<LaserState> estimate;  // after each update
  int rejected = 0;
};

FlightResult FlyAndFilter(uint64_t seed, bool with_bias, bool mirror_normal) {
  Rng rng(seed);
  const double dt = 0.01, L = 0.3, alpha = 22.5 * kDeg, duration = 60.0;
  const Eigen::Matrix3d R_W_P = Rx(alpha);
  const Plane plane{(mirror_normal ? -1.0 : 1.0) * R_W_P.col(2), 0.0};
  Eigen::Vector3d p = R_W_P * Eigen::Vector3d(0, 0, 1), v = R_W_P * Eigen::Vector3d(1, 0, 0);
  const Eigen::Matrix3d R_ref = R_W_P * Rx(M_PI) * Rx(0.1) * Ry(-0.15);  // looking at the plane
  Eigen::Quaterniond q(R_ref);
  const Eigen::Vector3d gyro_bias =
      with_bias ? Eigen::Vector3d::Constant(0.03 * kDeg) : Eigen::Vector3d::Zero();
  const Eigen::Vector3d accel_bias =
      with_bias ? Eigen::Vector3d::Constant(0.03) : Eigen::Vector3d::Zero();

  LaserEkfOptions options;
  options.L_m = L;
  options.accel_noise_density = 0.01 * std::sqrt(dt);
  options.gyro_noise_density = 1.0 * kDeg * std::sqrt(dt);
  options.bearing_sigma_rad = 1.0 * kDeg;
  LaserEkf ekf(options);
  // The truth in the convention of the physical plane (normal towards the vehicle, xi < 0), then
  // 10-20 % off (5.1.3); components near zero are offset relative to a typical magnitude.
  const Plane physical{R_W_P.col(2), 0.0};
  const LaserModes start = ModesFromPose(Pose(q, p), v, physical, GravityW());
  LaserState m0 = start.m;
  const double typical[4] = {1.0, 0.5, 0.5, 0.5};
  for (int i = 0; i < 4; ++i) {
    const double sign = rng.Uniform() < 0.5 ? -1.0 : 1.0;
    m0[i] += sign * rng.Uniform(0.1, 0.2) * std::max(std::abs(m0[i]), typical[i]);
  }
  // alpha via k = tan(alpha), 10-20 % off.
  const double k_sign = rng.Uniform() < 0.5 ? -1.0 : 1.0;
  const double k0 = std::tan(alpha) * (1.0 + k_sign * rng.Uniform(0.1, 0.2));
  m0[4] = -9.81 / std::sqrt(1.0 + k0 * k0);
  LaserCovariance P0 = LaserCovariance::Zero();
  for (int i = 0; i < 4; ++i)
    P0(i, i) = std::pow(0.2 * std::max(std::abs(start.m[i]), typical[i]), 2);
  P0(4, 4) = std::pow(0.5, 2);
  XiSign sign = start.xi_sign;
  if (mirror_normal) {
    m0 = -m0;
    sign = XiSign::kPositive;
  }
  ekf.Initialize(m0, P0, sign);

  FlightResult result;
  Eigen::Vector3d random_accel_P = Eigen::Vector3d::Zero(), random_rate_C = Eigen::Vector3d::Zero();
  const int steps = static_cast<int>(duration / dt);
  for (int k = 0; k < steps; ++k) {
    const Eigen::Vector3d p_P = R_W_P.transpose() * p, v_P = R_W_P.transpose() * v;
    // Mean-reverting (Ornstein-Uhlenbeck) accelerations and body rates with the stationary sigmas
    // of 5.1.1 and a 0.5 s correlation time; the height is pulled back to 1 m, the lateral velocity
    // to (1, 0) m/s and the attitude to looking at the plane.
    const double rho = std::exp(-dt / 0.5), spread = std::sqrt(1.0 - rho * rho);
    random_accel_P = rho * random_accel_P + spread * rng.Gaussian3(1.0);
    random_rate_C = rho * random_rate_C + spread * rng.Gaussian3(10.0 * kDeg);
    const Eigen::Vector3d pull(-0.5 * (v_P.x() - 1.0), -0.5 * v_P.y(),
                               -4.0 * (p_P.z() - 1.0) - 2.8 * v_P.z());
    const Eigen::Vector3d a_P = pull + random_accel_P;
    const Eigen::Vector3d a = R_W_P * a_P;
    const Eigen::Vector3d w =
        -0.5 * LogSO3(R_ref.transpose() * q.toRotationMatrix()) + random_rate_C;
    LaserInput u;
    u << q.conjugate() * (a - GravityW()) + accel_bias + rng.Gaussian3(0.01),
        w + gyro_bias + rng.Gaussian3(1.0 * kDeg);
    ekf.Propagate(u, dt);
    p += v * dt + 0.5 * a * dt * dt;
    v += a * dt;
    q = (q * ExpQuaternion(w * dt)).normalized();
    if ((k + 1) % 10 != 0) continue;
    LaserSpot spot;
    const LaserBeam beam{Eigen::Vector3d(L, 0, 0), Eigen::Vector3d::UnitZ()};
    if (ProjectLaserSpot(Pose(q, p), beam, physical, &spot) != LaserSpotStatus::kOk) {
      ADD_FAILURE() << "spot lost at step " << k;
      break;
    }
    const double h = std::tan(std::atan(spot.xy.x()) + rng.Gaussian(0.0, 1.0 * kDeg));
    if (ekf.Update(h) != LaserUpdateStatus::kOk) ++result.rejected;
    result.truth.push_back(ModesFromPose(Pose(q, p), v, plane, GravityW()).m);
    result.estimate.push_back(ekf.state());
  }
  EXPECT_EQ(ekf.decomposition_switches(), 0);
  return result;
}

void ExpectConverged(const FlightResult& flight) {
  ASSERT_FALSE(flight.truth.empty());
  const LaserState& truth = flight.truth.back();
  const LaserState& estimate = flight.estimate.back();
  const XiSign sign = truth[0] > 0 ? XiSign::kNegative : XiSign::kPositive;
  const LaserQuantities t = QuantitiesFromModes(truth, sign, 9.81);
  const LaserQuantities e = QuantitiesFromModes(estimate, sign, 9.81);
  EXPECT_LT(std::abs(e.v_o_m_s - t.v_o_m_s), 0.05);
  EXPECT_LT(std::abs(WrapAngle(e.roll_rad - t.roll_rad)), 2.0 * kDeg);
  EXPECT_LT(std::abs(e.pitch_rad - t.pitch_rad), 2.0 * kDeg);
  EXPECT_LT(std::abs(e.d_m - t.d_m), 0.05);
  // The paper's claim (5.1.3): the alpha error is below 1 deg, also with bias.
  EXPECT_LT(std::abs(e.alpha_rad - t.alpha_rad), 1.0 * kDeg);
  std::printf(
      "final errors: d %.4f m, v_o %.4f m/s, roll %.3f deg, pitch %.3f deg, alpha %.3f deg\n",
      e.d_m - t.d_m, e.v_o_m_s - t.v_o_m_s, WrapAngle(e.roll_rad - t.roll_rad) / kDeg,
      (e.pitch_rad - t.pitch_rad) / kDeg, (e.alpha_rad - t.alpha_rad) / kDeg);
}

TEST(LaserEkf, ConvergesOnAFixedSeedFlight) {
  const FlightResult flight = FlyAndFilter(42, /*with_bias=*/false, /*mirror_normal=*/false);
  ExpectConverged(flight);
  EXPECT_EQ(flight.rejected, 0);
}

TEST(LaserEkf, ConvergesWithTheBiasesOf513) {
  const FlightResult flight = FlyAndFilter(43, /*with_bias=*/true, /*mirror_normal=*/false);
  ExpectConverged(flight);
}

TEST(LaserEkf, BothDecompositionsGiveMirroredEstimates) {
  // With the plane normal flipped the same flight is described by -m and xi > 0 (eq. 10); the
  // filter's estimates are exactly the mirror image.
  const FlightResult negative = FlyAndFilter(44, false, false);
  const FlightResult positive = FlyAndFilter(44, false, true);
  ASSERT_EQ(negative.estimate.size(), positive.estimate.size());
  for (size_t i = 0; i < negative.estimate.size(); ++i) {
    EXPECT_LT((negative.estimate[i] + positive.estimate[i]).norm(), 1e-9);
  }
  ExpectConverged(positive);
}

TEST(LaserEkf, ConstraintAndDegenerateUpdate) {
  LaserEkf ekf(LaserEkfOptions{});
  LaserState m;
  m << 1.0, 0.0, 0.9, 0.9, -9.0;  // m3^2 + m4^2 > 1 is projected back inside the unit disk
  ekf.Initialize(m, LaserCovariance::Identity(), XiSign::kNegative);
  EXPECT_LT(ekf.state()[2] * ekf.state()[2] + ekf.state()[3] * ekf.state()[3], 1.0);
  m << 0.3, 0.0, 0.0, 1.0 - 1e-9, -9.0;  // the laser origin on the plane: m4 L - m1 = 0
  LaserEkfOptions options;
  options.L_m = 0.3;
  LaserEkf degenerate(options);
  degenerate.Initialize(m, LaserCovariance::Identity(), XiSign::kNegative);
  EXPECT_EQ(degenerate.Update(0.1), LaserUpdateStatus::kDegenerate);
}

}  // namespace
}  // namespace mavloc
