// The comparison's results in the one model: near gimbal lock, roll and yaw differences (which
// wrap and swing by tens of degrees for a small rotation error) are left out with a warning that
// points to the rotation angle; coverage below 90 % of the estimate is warned about.
#include "evaluation/comparison_report.h"

#include <gtest/gtest.h>

#include <cmath>

namespace mavloc {
namespace {

QuantityErrorSeries Series(const std::string& name, double truth, double error) {
  QuantityErrorSeries q;
  q.name = name;
  q.unit = "rad";
  for (int i = 0; i < 10; ++i) {
    q.t_ns.push_back(i);
    q.truth.push_back(truth);
    q.estimate.push_back(truth + error);
    q.error.push_back(error);
  }
  return q;
}

EstimatorEvaluation Evaluation(double pitch_truth_rad) {
  EstimatorEvaluation e;
  e.estimator = "tag-pnp";
  e.ran = true;
  e.quantity_errors = {Series("roll", 0.1, 0.3), Series("pitch", pitch_truth_rad, 0.001),
                       Series("yaw", 1.0, -0.3)};
  return e;
}

TEST(ComparisonReport, RollAndYawAreLeftOutNearGimbalLock) {
  const EstimatorResult far = ResultOfEvaluation(Evaluation(0.2));
  EXPECT_TRUE(far.metrics.count("roll"));
  EXPECT_TRUE(far.metrics.count("yaw"));
  EXPECT_TRUE(far.warnings.empty());
  const EstimatorResult near = ResultOfEvaluation(Evaluation(80.0 * M_PI / 180.0));
  EXPECT_FALSE(near.metrics.count("roll"));
  EXPECT_FALSE(near.metrics.count("yaw"));
  EXPECT_TRUE(near.metrics.count("pitch"));
  ASSERT_EQ(near.warnings.size(), 1u);
  EXPECT_NE(near.warnings[0].find("ate_rotation"), std::string::npos) << near.warnings[0];
}

TEST(ComparisonReport, QuantityMetricsAreRmseOfTheAbsoluteErrorInSi) {
  const EstimatorResult r = ResultOfEvaluation(Evaluation(0.2));
  const Metric& roll = r.metrics.at("roll");
  EXPECT_EQ(roll.unit, "rad");
  ASSERT_TRUE(roll.statistics);
  EXPECT_NEAR(roll.statistics->rmse, 0.3, 1e-12);
  EXPECT_NEAR(r.metrics.at("yaw").statistics->mean, 0.3, 1e-12);  // |error|
}

TEST(ComparisonReport, LowCoverageIsWarned) {
  EstimatorEvaluation e = Evaluation(0.2);
  e.coverage = Coverage{250, 29120, 5.0, 145.6};
  const EstimatorResult r = ResultOfEvaluation(e);
  ASSERT_FALSE(r.warnings.empty());
  EXPECT_NE(r.warnings.back().find("covers only 5.0 of the estimate's 145.6 s"), std::string::npos)
      << r.warnings.back();
}

}  // namespace
}  // namespace mavloc
