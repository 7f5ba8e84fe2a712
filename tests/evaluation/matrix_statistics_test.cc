// The statistics of the estimator x sequence matrix: the Wilcoxon signed-rank test against values
// scipy.stats.wilcoxon gives for the same differences, and a bootstrap interval that a seed
// reproduces.
#include "evaluation/matrix/matrix_statistics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace mavloc {
namespace {

TEST(WilcoxonSignedRank, ExactPValuesWithoutTies) {
  // All five differences positive: W- = 0, p = 2 * 1/32 (scipy: statistic 0, p 0.0625).
  SignedRankTest t = WilcoxonSignedRank({1, 2, 3, 4, 5});
  EXPECT_TRUE(t.exact);
  EXPECT_EQ(t.n, 5);
  EXPECT_DOUBLE_EQ(t.w_plus, 15.0);
  EXPECT_DOUBLE_EQ(t.w_minus, 0.0);
  EXPECT_NEAR(t.p_value, 0.0625, 1e-12);
  // scipy.stats.wilcoxon([-1, 2, 3, -4, 5, 6]): statistic 5, p 0.3125.
  t = WilcoxonSignedRank({-1, 2, 3, -4, 5, 6});
  EXPECT_DOUBLE_EQ(t.w_minus, 5.0);
  EXPECT_DOUBLE_EQ(t.w_plus, 16.0);
  EXPECT_NEAR(t.p_value, 0.3125, 1e-12);
  // Zero differences are dropped (Wilcoxon's convention).
  t = WilcoxonSignedRank({0.0, -1, 2, 3, -4, 5, 6});
  EXPECT_EQ(t.n, 6);
  EXPECT_NEAR(t.p_value, 0.3125, 1e-12);
}

TEST(WilcoxonSignedRank, NormalApproximationWithTiesAndDegenerateInput) {
  const SignedRankTest t = WilcoxonSignedRank({1, 1, 2, 2, -3, 4, 5, 6, 7, 8});
  EXPECT_FALSE(t.exact);
  EXPECT_DOUBLE_EQ(t.w_plus + t.w_minus, 55.0);  // the ranks 1..10, ties averaged
  EXPECT_GT(t.p_value, 0.0);
  EXPECT_LT(t.p_value, 0.05);
  EXPECT_EQ(WilcoxonSignedRank({}).n, 0);
  EXPECT_DOUBLE_EQ(WilcoxonSignedRank({0.0, 0.0}).p_value, 1.0);
}

TEST(BootstrapMeanInterval, ReproducibleForASeedAndAroundTheMean) {
  std::mt19937 generator(3);
  std::normal_distribution<double> noise(1.0, 0.2);
  std::vector<double> values;
  for (int i = 0; i < 12; ++i) values.push_back(noise(generator));
  double mean = 0.0;
  for (const double v : values) mean += v / 12.0;
  const ConfidenceInterval a = BootstrapMeanInterval(values, 7);
  const ConfidenceInterval b = BootstrapMeanInterval(values, 7);
  const ConfidenceInterval c = BootstrapMeanInterval(values, 8);
  EXPECT_DOUBLE_EQ(a.low, b.low);
  EXPECT_DOUBLE_EQ(a.high, b.high);
  EXPECT_NE(a.low, c.low);
  EXPECT_LT(a.low, mean);
  EXPECT_GT(a.high, mean);
  // About the mean +- 1.96 sigma / sqrt(n) (+-0.11 for sigma 0.2, n 12); the percentile interval
  // of a small sample is a little narrower.
  EXPECT_GT(a.high - a.low, 0.12);
  EXPECT_LT(a.high - a.low, 0.30);
  const ConfidenceInterval one = BootstrapMeanInterval({0.5}, 1);
  EXPECT_DOUBLE_EQ(one.low, 0.5);
  EXPECT_DOUBLE_EQ(one.high, 0.5);
  EXPECT_TRUE(std::isnan(BootstrapMeanInterval({}, 1).low));
}

}  // namespace
}  // namespace mavloc
