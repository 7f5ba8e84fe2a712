// The evaluation engine on the default scenario: the dead-reckoning baseline is evaluated on the
// quantities it estimates, and its errors grow with time (it drifts).
#include "evaluation/comparison.h"

#include <gtest/gtest.h>

#include "datasets/scenarios/scenario.h"
#include "evaluation/quantity_errors.h"

namespace mavloc {
namespace {

TEST(Comparison, DeadReckoningOnTheDefaultScenario) {
  ScenarioOptions options;
  options.seed = 3;
  options.duration_s = 10.0;
  const Dataset dataset = FindScenario(DefaultScenarioName())->generate(options);
  EvaluationOptions evaluation_options;
  const auto e = RunAndEvaluate("imu-dead-reckoning", {}, dataset, evaluation_options);
  ASSERT_TRUE(e.ran);
  ASSERT_TRUE(e.ate.has_value());
  std::vector<std::string> names;
  for (const auto& q : e.quantity_errors) names.push_back(q.name);
  EXPECT_EQ(names,
            (std::vector<std::string>{"x", "y", "z", "roll", "pitch", "yaw", "vx", "vy", "vz"}));
  // It starts at the truth and drifts: the error at the end exceeds the error after 1 s.
  const auto& x = e.quantity_errors[0];
  ASSERT_GT(x.error.size(), 100u);
  EXPECT_LT(std::abs(x.error[0]), 1e-9);
  const auto json = EvaluationToJson(e);
  EXPECT_TRUE(json.contains("quantities"));
  EXPECT_EQ(json["quantities"]["roll"]["unit"], "rad");  // report.json is SI
  EXPECT_DOUBLE_EQ(json["quantities"]["roll"]["rmse"].get<double>(), e.quantity_errors[3].rmse);
  EXPECT_EQ(json["ate"]["align"], "none");
  EXPECT_GE(json["runtime_s"].get<double>(), 0.0);
}

TEST(Comparison, NoiselessDeadReckoningStaysOnTheTruth) {
  ScenarioOptions options;
  options.seed = 4;
  options.duration_s = 10.0;
  options.settings = {{"imu_noise", "false"}, {"bias", "true"}};
  const Dataset dataset = FindScenario(DefaultScenarioName())->generate(options);
  const auto e = RunAndEvaluate("imu-dead-reckoning", {}, dataset, {});
  ASSERT_TRUE(e.ate.has_value());
  EXPECT_LT(e.ate->translation_m.max, 1e-3);  // exact biases, no noise: only integration error
}

TEST(Comparison, TwoAndThreePointDoNotApplyToLandmarksOffTheGround) {
  // The figure-eight's landmarks 1..3 sit on walls at different heights: the 2p/3p algorithms
  // (features on a horizontal plane) must say so instead of failing on every frame.
  ScenarioOptions options;
  options.duration_s = 4.0;
  const Dataset dataset = FindScenario(DefaultScenarioName())->generate(options);
  for (const char* name : {"two-point", "three-point"}) {
    const auto e = RunAndEvaluate(name, {}, dataset, {});
    EXPECT_FALSE(e.ran) << name;
    EXPECT_NE(e.skipped_reason.find("horizontal ground plane"), std::string::npos)
        << e.skipped_reason;
  }
}

TEST(Comparison, QuantityErrorsWrapAngles) {
  QuantityTable truth = MakeQuantityTable({"yaw"});
  truth.Append(0, {M_PI - 0.01});
  truth.Append(100, {M_PI - 0.01});
  QuantityTable est = MakeQuantityTable({"yaw"});
  est.Append(50, {-M_PI + 0.01});
  const auto errors = ComputeQuantityErrors(est, truth, 1.0);
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_NEAR(errors[0].error[0], 0.02, 1e-12);
}

}  // namespace
}  // namespace mavloc
