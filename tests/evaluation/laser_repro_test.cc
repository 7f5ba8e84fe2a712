// End to end for the laser-spot paper: laser-ekf against the laser-plane truth (fixed seeds), the
// solver's spot model against the scenario's observations, euroc-laser from the shared real data,
// and `mavloc repro laser` / `mavloc observability laser` through the CLI.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "core/errors.h"
#include "core/rotation.h"
#include "datasets/scenarios/euroc_laser.h"
#include "datasets/scenarios/laser_plane.h"
#include "evaluation/quantity_errors.h"
#include "solver/estimator.h"
#include "solver/laser/laser_spot_model.h"
#include "tests/test_support.h"

namespace mavloc {
namespace {

// Mean |error| of each quantity over the last quarter of the run.
std::map<std::string, double> LateErrors(const Estimate& estimate, const Dataset& dataset) {
  std::map<std::string, double> late;
  for (const auto& series :
       ComputeQuantityErrors(estimate.quantities, dataset.truth_quantities, 0.003)) {
    const TimeNs t0 = series.t_ns.front();
    const TimeNs t_late = t0 + (series.t_ns.back() - t0) * 3 / 4;
    double sum = 0.0;
    int n = 0;
    for (size_t i = 0; i < series.error.size(); ++i) {
      if (series.t_ns[i] < t_late) continue;
      sum += std::abs(series.error[i]);
      ++n;
    }
    late[series.name] = n > 0 ? sum / n : NAN;
  }
  return late;
}

Estimate RunLaserEkf(const Dataset& dataset, std::map<std::string, std::string> options) {
  auto estimator = FindEstimator("laser-ekf")->create(EstimatorOptions(std::move(options)));
  EXPECT_TRUE(estimator->AppliesTo(dataset).applies) << estimator->AppliesTo(dataset).reason;
  return estimator->Run(dataset);
}

TEST(LaserEkfEstimator, ConvergesOnLaserPlaneWithFixedSeeds) {
  for (uint64_t seed : {3, 4}) {
    ScenarioOptions options;
    options.seed = seed;
    const Dataset dataset = GenerateLaserPlane(options);
    const Estimate estimate = RunLaserEkf(dataset, {{"init_seed", std::to_string(seed)}});
    EXPECT_EQ(estimate.FailureCount(), 0);
    EXPECT_EQ(estimate.quantities.size(), dataset.imu.samples.size());
    EXPECT_EQ(estimate.covariances.size(), dataset.laser.size());
    const auto late = LateErrors(estimate, dataset);
    ASSERT_EQ(late.size(), 5u);
    EXPECT_LT(late.at("alpha"), 1.0 * kDeg) << "seed " << seed;
    EXPECT_LT(late.at("roll"), 2.0 * kDeg) << "seed " << seed;
    EXPECT_LT(late.at("pitch"), 2.0 * kDeg) << "seed " << seed;
    EXPECT_LT(late.at("d"), 0.05) << "seed " << seed;
    EXPECT_LT(late.at("v_o"), 0.05) << "seed " << seed;
  }
}

TEST(LaserEkfEstimator, NoiseFreeAndStartedAtTheTruthItStaysThere) {
  // Checks the frame conventions end to end (scenario truth <-> estimator output).
  ScenarioOptions options;
  options.seed = 7;
  options.duration_s = 20.0;
  options.settings = {
      {"bearing_noise_deg", "0"}, {"gyro_sigma_deg_s", "0"}, {"accel_sigma_m_s2", "0"}};
  const Dataset dataset = GenerateLaserPlane(options);
  const Estimate estimate =
      RunLaserEkf(dataset, {{"init_error_min", "0"}, {"init_error_max", "0"}});
  for (const auto& series :
       ComputeQuantityErrors(estimate.quantities, dataset.truth_quantities, 0.003)) {
    const double limit = series.unit == "rad" ? 0.3 * kDeg : 0.01;
    EXPECT_LT(series.max_abs, limit) << series.name;
  }
}

TEST(LaserEkfEstimator, SolverSpotModelMatchesTheScenario) {
  ScenarioOptions options;
  options.seed = 8;
  options.duration_s = 5.0;
  options.settings = {{"bearing_noise_deg", "0"}};
  const Dataset dataset = GenerateLaserPlane(options);
  const LaserBeam beam{Eigen::Vector3d(dataset.map.parameters.at("laser_Lx"), 0, 0),
                       Eigen::Vector3d::UnitZ()};
  size_t row = 0;
  for (const auto& spot : dataset.laser) {
    while (dataset.ground_truth[row].t_ns < spot.t_ns) ++row;
    const Pose T_W_C = dataset.ground_truth[row].T_W_B * dataset.cameras.front().T_B_C;
    LaserSpot model;
    ASSERT_EQ(ProjectLaserSpot(T_W_C, beam, *dataset.map.plane, &model), LaserSpotStatus::kOk);
    EXPECT_NEAR((model.xy - spot.xy).norm(), 0.0, 1e-9);
  }
}

TEST(EurocLaser, RunsEndToEndFromTheSharedData) {
  if (!testing::HasSharedData())
    GTEST_SKIP() << "shared data not found at " << testing::SharedDataDir();
  ScenarioOptions options;
  options.settings["data"] = testing::SharedDataDir() + "/euroc_v1_01_easy";
  const Dataset dataset = GenerateEurocLaser(options);
  EXPECT_EQ(dataset.imu.samples.size(), 29120u);
  EXPECT_GT(dataset.ground_truth.size(), 28000u);
  EXPECT_GT(dataset.laser.size(), 1400u);  // 10 Hz over 143.5 s
  EXPECT_EQ(dataset.scenario_info.at("spots_missed"), "0");
  for (const double d : dataset.truth_quantities.Column("d")) EXPECT_GE(d, 0.5 - 1e-9);
  const Estimate estimate = RunLaserEkf(dataset, {{"bias_from_ground_truth", "true"}});
  EXPECT_GT(estimate.quantities.size(), 28000u);
  // Over the first 10 s the distance and normal speed are tracked (the tilt drifts later with the
  // real IMU's residual gyro bias; see the repro report).
  for (const auto& series :
       ComputeQuantityErrors(estimate.quantities, dataset.truth_quantities, 0.003)) {
    if (series.name != "d" && series.name != "v_o") continue;
    for (size_t i = 0; i < series.error.size(); ++i) {
      if (series.t_ns[i] - series.t_ns.front() > 10 * kNsPerSecond) break;
      EXPECT_LT(std::abs(series.error[i]), 0.25) << series.name;
    }
  }
}

TEST(EurocLaser, MissingDataIsAClearInputError) {
  ScenarioOptions options;
  options.settings["data"] = "/nonexistent/euroc";
  EXPECT_THROW(GenerateEurocLaser(options), InputError);
}

TEST(LaserReproCli, SmallEndToEndRun) {
  const std::string dir = testing::MakeTempDir();
  const bool euroc = testing::HasSharedData();
  const auto result = testing::RunCommand(
      testing::CliPath() + " repro laser --runs 2 --report " + dir +
      " --set duration_s=20 --set euroc_runs=1 --set euroc=" + (euroc ? "true" : "false") +
      (euroc ? " --set data=" + testing::SharedDataDir() + "/euroc_v1_01_easy" : ""));
  ASSERT_EQ(result.exit_code, 0) << result.output;
  std::ifstream in(dir + "/report.json");
  const nlohmann::json json = nlohmann::json::parse(in)["details"];  // the repro's own layout
  EXPECT_EQ(json["tables"]["simulated"]["no_bias"]["runs"], 2);
  EXPECT_EQ(json["tables"]["simulated"]["with_bias"]["runs"], 2);
  const auto& alpha = json["tables"]["simulated"]["no_bias"]["quantities"]["alpha"];
  EXPECT_EQ(alpha["per_run_final_error"].size(), 2u);
  EXPECT_EQ(alpha["unit"], "rad");                                     // report.json is SI
  EXPECT_LT(alpha["mean_abs_final_error"].get<double>(), 2.0 * kDeg);  // after 20 s
  EXPECT_EQ(json["tables"]["simulated"]["with_bias"]["quantities"]["alpha"]["paper"],
            "final error < 1 deg (5.1.3)");
  if (euroc) {
    EXPECT_EQ(json["tables"]["euroc"]["bias_corrected"]["runs"], 1);
    EXPECT_EQ(json["tables"]["euroc"]["raw_imu"]["runs"], 1);
  }
  EXPECT_TRUE(std::filesystem::exists(dir + "/report.md"));
  EXPECT_TRUE(std::filesystem::exists(dir + "/runs.csv"));
  const auto bad = testing::RunCommand(testing::CliPath() + " repro laser --report " + dir +
                                       " --set nonsense=1");
  EXPECT_EQ(bad.exit_code, 2) << bad.output;
}

TEST(ObservabilityCli, PrintsRankSix) {
  const auto result =
      testing::RunCommand(testing::CliPath() + " observability laser --states 2 --seed 3");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_NE(result.output.find("rank 6:"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("singular values"), std::string::npos);
  EXPECT_EQ(testing::RunCommand(testing::CliPath() + " observability nothing").exit_code, 2);
}

}  // namespace
}  // namespace mavloc
