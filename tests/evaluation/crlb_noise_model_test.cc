// The noise the tag-arena and marker-board-flight simulations draw against the noise the smoother
// and its Cramér–Rao bound are told: a smoother RMSE below the bound would mean that the simulator
// draws less noise than the shared model states, or that the errors are measured in a way that
// removes error. Measured on one fixed seed per scenario, each statistic against the number
// the smoother reads (SmootherEstimator::ProblemOptionsFor, the same call ComputeSmootherCrlb
// makes):
// - tag corners: observed minus the projection of the TRUE corner (map tag pose, ground-truth
//   T_W_B at the frame stamp, T_B_C, the camera model), the sample standard deviation per image
//   coordinate against pixel_sigma_px;
// - IMU white noise: each sample of the scenario minus the same sample simulated with imu_noise=0
//   (same trajectory, no noise, zero bias) minus the ground-truth bias, against density / sqrt(dt)
//   (datasets/simulation/imu_simulator.h);
// - bias random walk: increments of the ground-truth bias against random_walk * sqrt(dt);
// - initial bias against the smoother's prior on the first biases.
// Tolerances are Monte-Carlo: a sample standard deviation s of N draws of N(0, sigma^2) has
// standard error sigma / sqrt(2 N); the checks allow 4 of those (and 4 sigma / sqrt(N) on means).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/dataset.h"
#include "core/imu.h"
#include "core/tag_geometry.h"
#include "datasets/scenarios/scenario.h"
#include "solver/estimators/smoother_estimator.h"
#include "solver/smoother/smoother_problem.h"

namespace mavloc {
namespace {

constexpr uint64_t kSeed = 5;

Dataset Simulate(const std::string& scenario, std::map<std::string, std::string> settings = {}) {
  const ScenarioEntry* entry = FindScenario(scenario);
  if (!entry) return Dataset{};
  ScenarioOptions options;
  options.seed = kSeed;
  options.settings = std::move(settings);
  return entry->generate(options);
}

// Mean and sample standard deviation.
struct Moments {
  double mean = 0.0;
  double sd = 0.0;
  int n = 0;
};
Moments MomentsOf(const std::vector<double>& x) {
  Moments m;
  m.n = static_cast<int>(x.size());
  if (m.n < 2) return m;
  for (double v : x) m.mean += v;
  m.mean /= m.n;
  double ss = 0.0;
  for (double v : x) ss += (v - m.mean) * (v - m.mean);
  m.sd = std::sqrt(ss / (m.n - 1));
  return m;
}

// Sample sd within 4 standard errors of sigma and mean within 4 sigma / sqrt(n) of zero.
void ExpectMatchesSigma(const std::vector<double>& x, double sigma, const std::string& what) {
  const Moments m = MomentsOf(x);
  ASSERT_GT(m.n, 100) << what;
  ASSERT_GT(sigma, 0.0) << what;
  const double sd_se = sigma / std::sqrt(2.0 * m.n);
  std::printf("%s: n %d, mean %.4g, sample sd %.4g, stated %.4g (ratio %.3f)\n", what.c_str(), m.n,
              m.mean, m.sd, sigma, m.sd / sigma);
  EXPECT_NEAR(m.sd, sigma, 4.0 * sd_se) << what << ": sample sd / stated = " << m.sd / sigma;
  EXPECT_NEAR(m.mean, 0.0, 4.0 * sigma / std::sqrt(static_cast<double>(m.n))) << what;
}

// The ground-truth row at t_ns exactly (camera frames are stamped on IMU samples when
// camera_offset_s = 0), or nullptr.
const GroundTruthState* TruthAt(const Dataset& dataset, TimeNs t_ns) {
  auto it = std::lower_bound(dataset.ground_truth.begin(), dataset.ground_truth.end(), t_ns,
                             [](const GroundTruthState& s, TimeNs t) { return s.t_ns < t; });
  return it != dataset.ground_truth.end() && it->t_ns == t_ns ? &*it : nullptr;
}

// The ground truth interpolated at t_ns (linear, slerp), for scenarios whose camera stamps are
// not on the IMU grid (marker-board-flight: 30 Hz against 200 Hz). Over a 5 ms gap of a smooth
// spline the interpolation error is micrometres, far below a pixel.
std::optional<GroundTruthState> InterpolatedTruthAt(const Dataset& dataset, TimeNs t_ns) {
  const auto& gt = dataset.ground_truth;
  auto it = std::lower_bound(gt.begin(), gt.end(), t_ns,
                             [](const GroundTruthState& s, TimeNs t) { return s.t_ns < t; });
  if (it == gt.end()) return std::nullopt;
  if (it->t_ns == t_ns) return *it;
  if (it == gt.begin()) return std::nullopt;
  const GroundTruthState& a = *std::prev(it);
  const double u = static_cast<double>(t_ns - a.t_ns) / static_cast<double>(it->t_ns - a.t_ns);
  GroundTruthState out = a;
  out.t_ns = t_ns;
  out.T_W_B =
      Pose(a.T_W_B.q.slerp(u, it->T_W_B.q).normalized(), (1.0 - u) * a.T_W_B.p + u * it->T_W_B.p);
  return out;
}

void CheckCornerNoise(const std::string& scenario, bool interpolate = false) {
  const Dataset dataset = Simulate(scenario);
  ASSERT_FALSE(dataset.tags.empty()) << scenario;
  ASSERT_FALSE(dataset.cameras.empty()) << scenario;
  const SmootherProblemOptions stated =
      SmootherEstimator(EstimatorOptions()).ProblemOptionsFor(dataset);
  const CameraSensor& camera = dataset.cameras.front();
  std::vector<double> du, dv;
  int unmatched = 0;
  for (const TagObservation& obs : dataset.tags) {
    const GroundTruthState* exact = TruthAt(dataset, obs.t_ns);
    const std::optional<GroundTruthState> interpolated =
        exact         ? std::optional<GroundTruthState>(*exact)
        : interpolate ? InterpolatedTruthAt(dataset, obs.t_ns)
                      : std::nullopt;
    const GroundTruthState* truth = interpolated ? &*interpolated : nullptr;
    if (!truth) {
      ++unmatched;
      continue;
    }
    const Pose T_C_W = (truth->T_W_B * camera.T_B_C).Inverse();
    const auto corners_W = TagCornersInWorld(dataset.map.tags.at(obs.tag_id));
    for (int k = 0; k < 4; ++k) {
      const auto uv = camera.model.Project(T_C_W * corners_W[k], 0.05);
      ASSERT_TRUE(uv.has_value()) << scenario;
      du.push_back(obs.corners_px[k].x() - uv->x());
      dv.push_back(obs.corners_px[k].y() - uv->y());
    }
  }
  EXPECT_EQ(unmatched, 0) << scenario << ": tag stamps without a ground-truth row";
  ExpectMatchesSigma(du, stated.pixel_sigma_px, scenario + " corner u [px]");
  ExpectMatchesSigma(dv, stated.pixel_sigma_px, scenario + " corner v [px]");
}

void CheckImuNoise(const std::string& scenario,
                   const std::map<std::string, std::string>& clean_settings = {
                       {"imu_noise", "0"}}) {
  const Dataset noisy = Simulate(scenario);
  const Dataset clean = Simulate(scenario, clean_settings);
  ASSERT_EQ(noisy.imu.samples.size(), clean.imu.samples.size()) << scenario;
  ASSERT_EQ(noisy.ground_truth.size(), noisy.imu.samples.size()) << scenario;
  ASSERT_GT(noisy.imu.rate_hz, 0.0);
  const double dt = 1.0 / noisy.imu.rate_hz;
  // The densities as the smoother and the bound use them (the stated ones, floored).
  const SmootherProblemOptions stated =
      SmootherEstimator(EstimatorOptions()).ProblemOptionsFor(noisy);
  const ImuNoise& n = noisy.imu.noise;
  const ImuNoise& f = stated.noise_floor;
  const double sigma_g =
      DiscreteSigma(std::max(n.gyroscope_noise_density, f.gyroscope_noise_density), dt);
  const double sigma_a =
      DiscreteSigma(std::max(n.accelerometer_noise_density, f.accelerometer_noise_density), dt);
  const double walk_g = std::max(n.gyroscope_random_walk, f.gyroscope_random_walk) * std::sqrt(dt);
  const double walk_a =
      std::max(n.accelerometer_random_walk, f.accelerometer_random_walk) * std::sqrt(dt);

  std::vector<double> ng[3], na[3], wg[3], wa[3];
  for (size_t i = 0; i < noisy.imu.samples.size(); ++i) {
    const ImuSample& s = noisy.imu.samples[i];
    const ImuSample& c = clean.imu.samples[i];
    const GroundTruthState& g = noisy.ground_truth[i];
    ASSERT_EQ(s.t_ns, c.t_ns);
    ASSERT_EQ(g.t_ns, s.t_ns);
    ASSERT_EQ(clean.ground_truth[i].b_g.norm() + clean.ground_truth[i].b_a.norm(), 0.0);
    const Eigen::Vector3d e_g = s.gyro_rad_s - c.gyro_rad_s - g.b_g;
    const Eigen::Vector3d e_a = s.accel_m_s2 - c.accel_m_s2 - g.b_a;
    for (int a = 0; a < 3; ++a) {
      ng[a].push_back(e_g[a]);
      na[a].push_back(e_a[a]);
    }
    if (i + 1 < noisy.ground_truth.size()) {
      const GroundTruthState& next = noisy.ground_truth[i + 1];
      for (int a = 0; a < 3; ++a) {
        wg[a].push_back(next.b_g[a] - g.b_g[a]);
        wa[a].push_back(next.b_a[a] - g.b_a[a]);
      }
    }
  }
  for (int a = 0; a < 3; ++a) {
    const std::string axis = std::string(1, "xyz"[a]);
    ExpectMatchesSigma(ng[a], sigma_g, scenario + " gyro noise " + axis + " [rad/s]");
    ExpectMatchesSigma(na[a], sigma_a, scenario + " accel noise " + axis + " [m/s^2]");
    ExpectMatchesSigma(wg[a], walk_g, scenario + " gyro bias step " + axis + " [rad/s]");
    ExpectMatchesSigma(wa[a], walk_a, scenario + " accel bias step " + axis + " [m/s^2]");
  }
  // The initial biases against the smoother's (and the bound's) prior on the first keyframe.
  const GroundTruthState& first = noisy.ground_truth.front();
  for (int a = 0; a < 3; ++a) {
    EXPECT_LE(std::abs(first.b_g[a]), 4.0 * stated.gyro_bias_prior_rad_s) << scenario;
    EXPECT_LE(std::abs(first.b_a[a]), 4.0 * stated.accel_bias_prior_m_s2) << scenario;
  }
}

TEST(CrlbNoiseModel, HoverCornerNoiseIsTheStatedPixelSigma) { CheckCornerNoise("tag-arena-hover"); }

TEST(CrlbNoiseModel, DynamicCornerNoiseIsTheStatedPixelSigma) {
  CheckCornerNoise("tag-arena-dynamic");
}

TEST(CrlbNoiseModel, HoverImuNoiseIsTheStatedModel) { CheckImuNoise("tag-arena-hover"); }

TEST(CrlbNoiseModel, DynamicImuNoiseIsTheStatedModel) { CheckImuNoise("tag-arena-dynamic"); }

// marker-board-flight (its smoother RMSE / bound is 1.14 for position over 20 seeds, Monte-Carlo
// noise: docs/cramer-rao.md): the same checks.
TEST(CrlbNoiseModel, MarkerBoardCornerNoiseIsTheStatedPixelSigma) {
  CheckCornerNoise("marker-board-flight", /*interpolate=*/true);
}

TEST(CrlbNoiseModel, AprilgridImuNoiseIsTheStatedModel) {
  CheckImuNoise("aprilgrid-calibration", {{"imu_noise", "0"}, {"bias", "0"}});
}

TEST(CrlbNoiseModel, MarkerBoardImuNoiseIsTheStatedModel) {
  CheckImuNoise("marker-board-flight", {{"imu_noise", "0"}, {"bias", "0"}});
}

}  // namespace
}  // namespace mavloc
