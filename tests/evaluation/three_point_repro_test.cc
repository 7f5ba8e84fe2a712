// End to end for the three-point paper: gravity-ekf, two-point and three-point against the truth
// of the three-point-hover scenario (fixed seeds), frame accounting, and a small
// `mavloc repro three-point` run (library and CLI).
#include "evaluation/repro/three_point_repro.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "core/errors.h"
#include "core/rotation.h"
#include "datasets/scenarios/three_point_hover.h"
#include "evaluation/comparison.h"
#include "tests/test_support.h"

namespace mavloc {
namespace {

Dataset Hover(uint64_t seed, std::map<std::string, std::string> settings = {}) {
  ScenarioOptions options;
  options.seed = seed;
  options.settings = std::move(settings);
  return GenerateThreePointHover(options);
}

const QuantityErrorSeries& Series(const EstimatorEvaluation& e, const std::string& name) {
  for (const auto& s : e.quantity_errors)
    if (s.name == name) return s;
  throw std::runtime_error("no series " + name);
}

EstimatorEvaluation RunEstimator(const std::string& estimator, const Dataset& d,
                                 std::map<std::string, std::string> options = {}) {
  const EstimatorEvaluation e =
      RunAndEvaluate(estimator, EstimatorOptions(options), d, EvaluationOptions{});
  EXPECT_TRUE(e.ran) << e.skipped_reason;
  return e;
}

TEST(ThreePointEstimators, GravityEkfRollPitchOnTheHover) {
  const EstimatorEvaluation e = RunEstimator("gravity-ekf", Hover(3));
  EXPECT_EQ(Series(e, "roll").error.size(), Hover(3).imu.samples.size());
  EXPECT_LT(Series(e, "roll").mean_abs, 0.1 * kDeg);
  EXPECT_LT(Series(e, "pitch").mean_abs, 0.1 * kDeg);
  EXPECT_FALSE(e.estimate.covariances.empty());
}

TEST(ThreePointEstimators, TwoPointWithExactBearingsIsLimitedOnlyByTheImuTilt) {
  const Dataset d = Hover(4, {{"bearing_noise_deg", "0"}});
  const EstimatorEvaluation e = RunEstimator("two-point", d);
  EXPECT_EQ(e.estimate.FailureCount(), 0);
  EXPECT_EQ(e.estimate.quantities.size(), d.cameras[0].frames.size());
  // 2p takes roll and pitch from the gravity EKF unchanged.
  const EstimatorEvaluation ekf = RunEstimator("gravity-ekf", d);
  const auto& ekf_roll = Series(ekf, "roll");
  const auto& roll = Series(e, "roll");
  ASSERT_FALSE(roll.t_ns.empty());
  for (size_t i = 0; i < roll.t_ns.size(); ++i) {
    const auto it = std::find(ekf_roll.t_ns.begin(), ekf_roll.t_ns.end(), roll.t_ns[i]);
    ASSERT_NE(it, ekf_roll.t_ns.end());
    EXPECT_NEAR(roll.estimate[i], ekf_roll.estimate[it - ekf_roll.t_ns.begin()], 1e-12);
  }
  // The EKF's mean tilt error (~0.04 deg) at a range of ~0.5 m is ~0.35 mm of position error.
  for (const char* q : {"x", "y", "z"}) EXPECT_LT(Series(e, q).mean_abs, 1e-3) << q;
  EXPECT_LT(Series(e, "yaw").mean_abs, 0.05 * kDeg);
}

TEST(ThreePointEstimators, ThreePointWithExactBearingsRecoversTheTruth) {
  // Without bearing noise the triangle's angles pin roll and pitch, whatever the IMU's error
  // (here a biased accelerometer, 0.3 deg of EKF tilt error).
  const Dataset d = Hover(5, {{"bearing_noise_deg", "0"}, {"accel_bias_m_s2", "0.05"}});
  const EstimatorEvaluation ekf = RunEstimator("gravity-ekf", d);
  EXPECT_GT(Series(ekf, "roll").mean_abs + Series(ekf, "pitch").mean_abs, 0.1 * kDeg);
  const EstimatorEvaluation e = RunEstimator("three-point", d, {{"true_angles", "true"}});
  EXPECT_EQ(e.estimate.FailureCount(), 0);
  for (const char* q : {"roll", "pitch", "yaw"}) EXPECT_LT(Series(e, q).max_abs, 1e-6) << q;
  for (const char* q : {"x", "y", "z"}) EXPECT_LT(Series(e, q).max_abs, 1e-6) << q;
}

TEST(ThreePointEstimators, ThreePointFilterEstimatesTheTriangleAngles) {
  // Bearing noise 0.01 deg: one frame measures each angle to ~0.1 deg (the segments subtend
  // ~12 deg); ~77 frames average that to ~0.012 deg, plus the EKF's tilt error during the move.
  const Dataset d = Hover(6, {{"bearing_noise_deg", "0.01"}});
  const EstimatorEvaluation e = RunEstimator("three-point", d, {{"bearing_sigma_deg", "0.01"}});
  const QuantityErrorSeries& g1 = Series(e, "gamma1");
  const QuantityErrorSeries& g2 = Series(e, "gamma2");
  ASSERT_GT(g1.error.size(), 50u);
  EXPECT_LT(std::abs(g1.error.back()), 0.1 * kDeg);
  EXPECT_LT(std::abs(g2.error.back()), 0.1 * kDeg);
}

TEST(ThreePointEstimators, ApplicabilityAndFrameAccounting) {
  Dataset d = Hover(7);
  Dataset no_features = d;
  no_features.features.clear();
  for (const char* name : {"two-point", "three-point"}) {
    const EstimatorEvaluation e =
        RunAndEvaluate(name, EstimatorOptions(), no_features, EvaluationOptions{});
    EXPECT_FALSE(e.ran);
    EXPECT_NE(e.skipped_reason.find("landmarks 1"), std::string::npos) << e.skipped_reason;
  }
  // Drop P2 from the first five frames: two-point counts them, with the reason.
  const TimeNs t5 = d.cameras[0].frames.at(5).t_ns;
  std::erase_if(d.features,
                [&](const FeatureObservation& f) { return f.landmark_id == 2 && f.t_ns < t5; });
  const EstimatorEvaluation e = RunEstimator("two-point", d);
  EXPECT_EQ(e.estimate.failures.at("P1 or P2 not seen"), 5);
  EXPECT_EQ(e.estimate.quantities.size() + 5, d.cameras[0].frames.size());
}

// The reproduction's own layout: the details of the one report schema.
nlohmann::json ReadJson(const std::string& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in)["details"];
}

TEST(ThreePointRepro, SmallRunWritesBothTablesWithThePapersValues) {
  const std::string dir = testing::MakeTempDir();
  ReproOptions options;
  options.runs = 2;
  options.seed = 11;
  options.report_dir = dir;
  options.settings = {{"noise_levels_deg", "0.01,1"}, {"heights_m", "0.4"}};
  ASSERT_EQ(RunRepro(ThreePointRepro(), options), 0);
  const nlohmann::json j = ReadJson(dir + "/report.json");
  const auto& t1 = j.at("tables").at("table1").at("estimators");
  EXPECT_DOUBLE_EQ(t1.at("two-point").at("quantities").at("x").at("paper").get<double>(), 4.08);
  EXPECT_NEAR(t1.at("three-point").at("quantities").at("yaw").at("paper").get<double>(),
              0.01 * kDeg,
              1e-15);  // report.json is SI
  EXPECT_EQ(t1.at("two-point").at("quantities").at("z").at("unit"), "%");
  EXPECT_EQ(t1.at("three-point").at("quantities").at("roll").at("unit"), "rad");
  for (const char* q : {"x", "y", "z", "roll", "pitch", "yaw"}) {
    const double v = t1.at("three-point").at("quantities").at(q).at("mean_abs").get<double>();
    EXPECT_TRUE(std::isfinite(v) && v > 0.0) << q;
  }
  // 2 noise levels x 1 height, plus the biased-accelerometer rows at each noise level.
  const auto& rows = j.at("tables").at("sensitivity").at("rows");
  EXPECT_EQ(rows.size(), 4u);
  EXPECT_TRUE(rows[0].at("estimators").contains("gravity-ekf"));
  std::ifstream md_file(dir + "/report.md");
  const std::string md((std::istreambuf_iterator<char>(md_file)), std::istreambuf_iterator<char>());
  EXPECT_NE(md.find("Error definition"), std::string::npos);
  EXPECT_NE(md.find("Regime where 3p beats 2p on every column"), std::string::npos);
  EXPECT_NE(md.find("| 2pAlgo (paper) | 4.08 | 5.41 | 5.23 | 1.63 | 1.72 | 1.36"),
            std::string::npos);
}

TEST(ThreePointRepro, BadSettingsAreInputErrors) {
  ReproOptions options;
  options.runs = 1;
  options.report_dir = testing::MakeTempDir();
  options.settings = {{"noise_levels_deg", "0.1,abc"}};
  EXPECT_THROW(RunRepro(ThreePointRepro(), options), InputError);
  options.settings = {{"no_such_key", "1"}};
  EXPECT_THROW(RunRepro(ThreePointRepro(), options), InputError);
}

TEST(ThreePointRepro, CommandLine) {
  if (!std::filesystem::exists(testing::CliPath()))
    GTEST_SKIP() << "the mavloc executable is not built: " << testing::CliPath();
  const std::string dir = testing::MakeTempDir();
  const auto ok = testing::RunCommand(testing::CliPath() + " repro three-point --runs 2 --report " +
                                      dir + " --set noise_levels_deg=1 --set heights_m=0.4");
  ASSERT_EQ(ok.exit_code, 0) << ok.output;
  EXPECT_TRUE(ReadJson(dir + "/report.json").at("tables").contains("sensitivity"));
  const auto bad =
      testing::RunCommand(testing::CliPath() + " repro three-point --runs 1 --report " + dir +
                          "/bad --set heights_m=-1");
  EXPECT_EQ(bad.exit_code, 2) << bad.output;
  EXPECT_FALSE(std::filesystem::exists(dir + "/bad/report.json"));
}

}  // namespace
}  // namespace mavloc
