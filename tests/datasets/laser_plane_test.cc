// Scenario laser-plane (laser paper 5.1) and its random motion: determinism, analytic derivatives,
// the vehicle staying near the plane with the spot in view, and spots consistent with the truth.
#include "datasets/scenarios/laser_plane.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/errors.h"
#include "core/rotation.h"
#include "datasets/simulation/random_motion_trajectory.h"
#include "tests/test_support.h"

namespace mavloc {
namespace {

ScenarioOptions Options(uint64_t seed, double duration_s = 30.0) {
  ScenarioOptions options;
  options.seed = seed;
  options.duration_s = duration_s;
  return options;
}

TEST(RandomMotionTrajectory, DerivativesAreAnalytic) {
  RandomMotionOptions options;
  options.duration_s = 5.0;
  const RandomMotionTrajectory trajectory(options, 3);
  // The samples are exact derivatives of each other (inside and across the spline's knots).
  for (const TimeNs t : {options.start_ns + 1'234'567'000LL, options.start_ns + 3'005'000'000LL,
                         options.start_ns + 2'000'000'000LL}) {
    const double h = 1e-4;
    const TrajectorySample s = trajectory.At(t);
    const TrajectorySample plus = trajectory.At(t + SecondsToNs(h));
    const TrajectorySample minus = trajectory.At(t - SecondsToNs(h));
    EXPECT_LT(((plus.p_W - minus.p_W) / (2 * h) - s.v_W).norm(), 1e-6);
    EXPECT_LT(((plus.v_W - minus.v_W) / (2 * h) - s.a_W).norm(), 1e-6);
    const Eigen::Vector3d w_numeric = LogQuaternion(minus.q_W_B.conjugate() * plus.q_W_B) / (2 * h);
    EXPECT_LT((w_numeric - s.w_B).norm(), 1e-6);
  }
  // The IMU signal is continuous across knots (the process underneath changes its acceleration
  // and body rate every 0.01 s; the smoothed trajectory does not jump).
  const TimeNs knot = options.start_ns + 2'000'000'000LL;
  EXPECT_LT((trajectory.At(knot - 1).a_W - trajectory.At(knot).a_W).norm(), 1e-6);
  EXPECT_LT((trajectory.At(knot - 1).w_B - trajectory.At(knot).w_B).norm(), 1e-6);
  const TimeNs process_step = options.start_ns + 2'005'000'000LL;
  EXPECT_LT((trajectory.At(process_step - 1).a_W - trajectory.At(process_step).a_W).norm(), 1e-6);
  // It starts where the options say.
  const TrajectorySample start = trajectory.At(options.start_ns);
  EXPECT_LT((start.p_W - options.p0_P).norm(), 1e-12);
  EXPECT_LT(RotationAngleBetween(start.q_W_B, options.q_P_B_ref), 1e-12);
  EXPECT_LT((start.v_W - options.v0_P).norm(), 1e-12);
}

TEST(LaserPlane, SameSeedSameData) {
  const Dataset a = GenerateLaserPlane(Options(5, 5.0));
  const Dataset b = GenerateLaserPlane(Options(5, 5.0));
  const Dataset c = GenerateLaserPlane(Options(6, 5.0));
  ASSERT_EQ(a.laser.size(), b.laser.size());
  for (size_t i = 0; i < a.laser.size(); ++i) EXPECT_EQ(a.laser[i].xy, b.laser[i].xy);
  ASSERT_EQ(a.imu.samples.size(), b.imu.samples.size());
  EXPECT_EQ(a.imu.samples.back().accel_m_s2, b.imu.samples.back().accel_m_s2);
  EXPECT_NE(a.laser.front().xy, c.laser.front().xy);
}

TEST(LaserPlane, PaperSetupAndPhysicallySensibleMotion) {
  for (uint64_t seed = 1; seed <= 5; ++seed) {
    const Dataset d = GenerateLaserPlane(Options(seed, 60.0));
    EXPECT_EQ(d.imu.rate_hz, 100.0);
    EXPECT_NEAR(d.imu.samples.size(), 6001, 1);
    EXPECT_NEAR(d.laser.size(), 601, 1);  // 10 Hz, none missed
    ASSERT_TRUE(d.map.plane.has_value());
    EXPECT_NEAR(std::acos(d.map.plane->n_W.z()), 22.5 * kDeg, 1e-12);
    EXPECT_EQ(d.map.parameters.at("laser_Lx"), 0.3);
    const auto distance = d.truth_quantities.Column("d");
    const auto alpha = d.truth_quantities.Column("alpha");
    EXPECT_NEAR(distance.front(), 1.0, 1e-9);  // start 1 m from the plane
    for (size_t i = 0; i < distance.size(); ++i) {
      EXPECT_GT(distance[i], 0.3) << "seed " << seed;  // stays near the plane, never hits it
      EXPECT_LT(distance[i], 2.5) << "seed " << seed;
      EXPECT_NEAR(alpha[i], 22.5 * kDeg, 1e-12);
    }
    // The spot stays well inside the field of view (|x| < 1, i.e. within 45 deg).
    for (const auto& spot : d.laser) EXPECT_LT(std::abs(spot.xy.x()), 1.0);
    // Initial speed (1, 0, 0) m/s in the plane frame.
    EXPECT_NEAR((d.ground_truth.front().v_W - Eigen::Vector3d(1, 0, 0)).norm(), 0.0, 1e-12);
    // The motion is excited: body rates and accelerations of the order of the paper's sigmas.
    double rate2 = 0.0, accel2 = 0.0;
    for (size_t i = 0; i + 1 < d.ground_truth.size(); ++i) {
      const double dt = NsToSeconds(d.ground_truth[i + 1].t_ns - d.ground_truth[i].t_ns);
      accel2 += ((d.ground_truth[i + 1].v_W - d.ground_truth[i].v_W) / dt).squaredNorm() / 3;
      rate2 += (d.imu.samples[i].gyro_rad_s).squaredNorm() / 3;
    }
    const double n = static_cast<double>(d.ground_truth.size() - 1);
    EXPECT_GT(std::sqrt(accel2 / n), 0.5);
    EXPECT_LT(std::sqrt(accel2 / n), 2.0);
    EXPECT_GT(std::sqrt(rate2 / n), 5 * kDeg);
    EXPECT_LT(std::sqrt(rate2 / n), 20 * kDeg);
  }
}

TEST(LaserPlane, NoiseFreeSpotsFollowEquation11FromTheTruth) {
  ScenarioOptions options = Options(9, 10.0);
  options.settings["bearing_noise_deg"] = "0";
  const Dataset d = GenerateLaserPlane(options);
  const double L = 0.3;
  size_t row = 0;
  for (const auto& spot : d.laser) {
    while (d.truth_quantities.t_ns[row] < spot.t_ns) ++row;
    ASSERT_EQ(d.truth_quantities.t_ns[row], spot.t_ns);
    const auto& q = d.truth_quantities.rows[row];  // d, v_o, roll, pitch, alpha
    const double roll = q[2], pitch = q[3];
    // n_C = (-m4, m3, xi) = third row of R = Rz Ry Rx: (-sin p, cos p sin r, cos p cos r).
    const double m3 = std::cos(pitch) * std::sin(roll), m4 = std::sin(pitch);
    const double xi = std::cos(pitch) * std::cos(roll);
    EXPECT_LT(xi, 0.0);  // looking at the plane from its positive side: decomposition xi < 0
    EXPECT_NEAR(spot.xy.x(), L * xi / (m4 * L - q[0]), 1e-9);
    EXPECT_NEAR(spot.xy.y(), 0.0, 1e-12);
    (void)m3;
  }
}

TEST(LaserPlane, BiasOptionAndBadSettings) {
  ScenarioOptions options = Options(2, 2.0);
  options.settings["bias"] = "true";
  const Dataset d = GenerateLaserPlane(options);
  EXPECT_NEAR((d.ground_truth.front().b_a - Eigen::Vector3d::Constant(0.03)).norm(), 0, 1e-15);
  EXPECT_NEAR((d.ground_truth.front().b_g - Eigen::Vector3d::Constant(0.03 * kDeg)).norm(), 0,
              1e-15);
  ScenarioOptions bad = Options(2, 2.0);
  bad.settings["alpha"] = "10";
  EXPECT_THROW(GenerateLaserPlane(bad), InputError);
  ScenarioOptions bad_l = Options(2, 2.0);
  bad_l.settings["L"] = "-1";
  EXPECT_THROW(GenerateLaserPlane(bad_l), InputError);
}

}  // namespace
}  // namespace mavloc
