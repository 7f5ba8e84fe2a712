// Scenario "three-point-hover" (three-point paper, V-A): the features and triangle, the hover
// from start to goal, the sensor rates and noise levels, exact observations without noise,
// determinism per seed, and rejection of bad settings.
#include "datasets/scenarios/three_point_hover.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "core/errors.h"
#include "core/rotation.h"
#include "datasets/scenarios/scenario.h"

namespace mavloc {
namespace {

const GroundTruthState& TruthAt(const Dataset& d, TimeNs t_ns) {
  for (const auto& s : d.ground_truth)
    if (s.t_ns == t_ns) return s;
  throw std::runtime_error("no ground truth at a camera stamp");
}

TEST(ThreePointHover, IsRegisteredAndDocumentsStartAndGoal) {
  const ScenarioEntry* entry = FindScenario("three-point-hover");
  ASSERT_NE(entry, nullptr);
  ScenarioOptions options;
  const Dataset d = entry->generate(options);
  EXPECT_EQ(d.scenario, "three-point-hover");
  ASSERT_TRUE(d.scenario_info.count("start"));
  ASSERT_TRUE(d.scenario_info.count("goal"));
  EXPECT_NE(d.scenario_info.at("goal").find("yaw = 30 deg"), std::string::npos);
}

TEST(ThreePointHover, FeaturesTriangleAndMap) {
  const Dataset d = GenerateThreePointHover(ScenarioOptions{});
  ASSERT_EQ(d.map.landmarks_W.size(), 3u);
  EXPECT_TRUE(d.map.landmarks_W.at(1).isApprox(Eigen::Vector3d(0, 0, 0)));
  EXPECT_TRUE(d.map.landmarks_W.at(2).isApprox(Eigen::Vector3d(0.1, 0, 0)));
  EXPECT_TRUE(d.map.landmarks_W.at(3).isApprox(Eigen::Vector3d(0.05, std::sqrt(3.0) / 20.0, 0)));
  EXPECT_DOUBLE_EQ(d.map.parameters.at("D"), 0.1);
  EXPECT_NEAR(d.map.parameters.at("gamma1_rad"), 60 * kDeg, 1e-12);
  EXPECT_NEAR(d.map.parameters.at("gamma2_rad"), 120 * kDeg, 1e-12);
  ASSERT_TRUE(d.truth_quantities.Has("gamma1"));
  EXPECT_EQ(d.truth_quantities.size(), d.cameras.at(0).frames.size());

  ScenarioOptions other;
  other.settings = {{"D", "0.25"}, {"p3_x", "0.2"}, {"p3_y", "0.6"}};
  const Dataset e = GenerateThreePointHover(other);
  EXPECT_TRUE(e.map.landmarks_W.at(3).isApprox(Eigen::Vector3d(0.05, 0.15, 0)));
  EXPECT_NEAR(e.map.parameters.at("gamma1_rad"), std::atan2(0.6, 0.2), 1e-12);
}

TEST(ThreePointHover, HoversFromStartToGoalAndHolds) {
  const Dataset d = GenerateThreePointHover(ScenarioOptions{});
  ASSERT_FALSE(d.ground_truth.empty());
  const GroundTruthState& first = d.ground_truth.front();
  const GroundTruthState& last = d.ground_truth.back();
  // The spline holds the end points still for a few control intervals beyond the waypoints.
  EXPECT_GE(NsToSeconds(last.t_ns - first.t_ns), 20.0 - 1e-9);
  EXPECT_LT((first.T_W_B.p - Eigen::Vector3d(0.05, std::sqrt(3.0) / 60.0, 0.5)).norm(), 1e-9);
  EXPECT_LT((last.T_W_B.p - Eigen::Vector3d(0.25, std::sqrt(3.0) / 60.0 + 0.12, 0.4)).norm(), 1e-9);
  EXPECT_NEAR(EulerFromQuaternion(last.T_W_B.q).yaw, 30 * kDeg, 1e-9);
  EXPECT_LT(first.v_W.norm(), 1e-9);
  EXPECT_LT(last.v_W.norm(), 1e-9);
  // Level when holding (quadrotor: no acceleration, thrust vertical).
  const EulerRpy rpy = EulerFromQuaternion(last.T_W_B.q);
  EXPECT_LT(std::abs(rpy.roll) + std::abs(rpy.pitch), 1e-9);
  // The move happens between 1 s and 8 s: it is somewhere in between at 4.5 s.
  const GroundTruthState& mid = d.ground_truth.at(450);
  EXPECT_GT(mid.v_W.norm(), 0.005);
}

TEST(ThreePointHover, SensorRatesAndNoise) {
  const Dataset d = GenerateThreePointHover(ScenarioOptions{});
  const double duration_s = NsToSeconds(d.imu.samples.back().t_ns - d.imu.samples.front().t_ns);
  EXPECT_EQ(d.imu.samples.size(), static_cast<size_t>(std::lround(duration_s * 100)) + 1);
  EXPECT_EQ(d.imu.samples[1].t_ns - d.imu.samples[0].t_ns, 10'000'000);
  ASSERT_EQ(d.cameras.size(), 1u);
  const auto& frames = d.cameras[0].frames;
  ASSERT_GE(frames.size(), 60u);
  EXPECT_EQ(frames[1].t_ns - frames[0].t_ns, 300'000'000);
  // Every feature visible in every frame.
  EXPECT_EQ(d.features.size(), 3 * frames.size());

  // Gyro noise while resting during the first second: 1 deg/s per sample.
  double sum2 = 0.0;
  int n = 0;
  for (int k = 0; k < 100; ++k) {
    sum2 += d.imu.samples[k].gyro_rad_s.squaredNorm();
    n += 3;
  }
  EXPECT_NEAR(std::sqrt(sum2 / n) / kDeg, 1.0, 0.1);

  // Bearing noise: 1 deg on each image axis (angle of the normalized coordinates).
  const CameraSensor& cam = d.cameras[0];
  double e2 = 0.0;
  int m = 0;
  for (const auto& f : d.features) {
    const Pose T_C_W = (TruthAt(d, f.t_ns).T_W_B * cam.T_B_C).Inverse();
    const Eigen::Vector3d X_C = T_C_W * d.map.landmarks_W.at(f.landmark_id);
    const Eigen::Vector2d truth = X_C.head<2>() / X_C.z();
    for (int a = 0; a < 2; ++a) {
      const double da = std::atan(f.xy[a]) - std::atan(truth[a]);
      e2 += da * da;
      ++m;
    }
  }
  // The per-axis angle of an off-axis bearing shrinks a little with the other axis: within 15%.
  EXPECT_NEAR(std::sqrt(e2 / m) / kDeg, 1.0, 0.15);
}

TEST(ThreePointHover, NoiselessObservationsAreExactProjections) {
  ScenarioOptions options;
  options.settings = {{"bearing_noise_deg", "0"}};
  const Dataset d = GenerateThreePointHover(options);
  const CameraSensor& cam = d.cameras[0];
  for (const auto& f : d.features) {
    const Pose T_C_W = (TruthAt(d, f.t_ns).T_W_B * cam.T_B_C).Inverse();
    const Eigen::Vector3d X_C = T_C_W * d.map.landmarks_W.at(f.landmark_id);
    EXPECT_LT((f.xy - X_C.head<2>() / X_C.z()).norm(), 1e-12);
  }
}

TEST(ThreePointHover, SameSeedSameDataAndBiases) {
  ScenarioOptions a;
  a.seed = 5;
  a.settings = {{"gyro_bias_deg_s", "0.5"}, {"accel_bias_m_s2", "0.05"}};
  const Dataset d1 = GenerateThreePointHover(a);
  const Dataset d2 = GenerateThreePointHover(a);
  ASSERT_EQ(d1.features.size(), d2.features.size());
  for (size_t i = 0; i < d1.features.size(); ++i) EXPECT_EQ(d1.features[i].xy, d2.features[i].xy);
  EXPECT_EQ(d1.imu.samples.back().accel_m_s2, d2.imu.samples.back().accel_m_s2);
  EXPECT_GT(d1.ground_truth.front().b_g.norm(), 0.0);
  EXPECT_GT(d1.ground_truth.front().b_a.norm(), 0.0);
  a.seed = 6;
  const Dataset d3 = GenerateThreePointHover(a);
  EXPECT_NE(d1.features.front().xy, d3.features.front().xy);
}

TEST(ThreePointHover, RejectsBadSettings) {
  ScenarioOptions options;
  options.settings = {{"hieght", "0.5"}};
  EXPECT_THROW(GenerateThreePointHover(options), InputError);
  options.settings = {{"D", "0"}};
  EXPECT_THROW(GenerateThreePointHover(options), InputError);
  options.settings = {{"goal_z", "-0.1"}};
  EXPECT_THROW(GenerateThreePointHover(options), InputError);
  options.settings = {{"p3_y", "0"}};
  EXPECT_THROW(GenerateThreePointHover(options), InputError);
}

}  // namespace
}  // namespace mavloc
