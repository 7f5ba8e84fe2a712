// Statistics over repeated runs and over sequences for the estimator x sequence matrix
// (matrix_evaluation.h).
//
// Bootstrap confidence interval of a mean (Efron & Tibshirani, An Introduction to the Bootstrap,
// 1993, ch. 13, the percentile interval): B resamples of the n values with replacement, drawn from
// a seeded generator (the same seed gives the same interval), the mean of each; the interval is
// the (1 - level)/2 and (1 + level)/2 quantiles of the B means (linear interpolation between
// order statistics). With one value the interval is that value.
//
// Wilcoxon signed-rank test (Wilcoxon 1945; Hollander, Wolfe & Chicken, Nonparametric Statistical
// Methods, 3rd ed., sec. 3.1) of paired differences d_i = a_i - b_i across sequences: zero
// differences are dropped (Wilcoxon's convention), |d_i| ranked with ties given their average
// rank, W+ = the sum of the ranks of positive differences. Two-sided p-value: exact from the null
// distribution of W+ over the 2^n sign patterns when there are no ties and n <= 30 (counted by
// dynamic programming over the ranks), otherwise the normal approximation with the tie correction
// of the variance and a continuity correction of 0.5.
#pragma once

#include <cstdint>
#include <vector>

namespace mavloc {

struct ConfidenceInterval {
  double low = 0.0, high = 0.0;
  double level = 0.95;
  int resamples = 0;
};

ConfidenceInterval BootstrapMeanInterval(const std::vector<double>& values, uint64_t seed,
                                         int resamples = 2000, double level = 0.95);

struct SignedRankTest {
  int n = 0;             // non-zero differences
  double w_plus = 0.0;   // rank sum of the positive differences
  double w_minus = 0.0;  // of the negative ones
  double p_value = 1.0;  // two-sided
  bool exact = false;    // exact null distribution (no ties, n <= 30) or normal approximation
};

SignedRankTest WilcoxonSignedRank(const std::vector<double>& differences);

}  // namespace mavloc
