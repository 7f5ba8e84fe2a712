#include "evaluation/matrix/matrix_statistics.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>

namespace mavloc {
namespace {

double Quantile(const std::vector<double>& sorted, double q) {
  const double position = q * static_cast<double>(sorted.size() - 1);
  const size_t below = static_cast<size_t>(std::floor(position));
  const size_t above = std::min(below + 1, sorted.size() - 1);
  const double fraction = position - static_cast<double>(below);
  return sorted[below] + fraction * (sorted[above] - sorted[below]);
}

// P(W+ <= w) under the null, for ranks 1..n without ties: counts of sign patterns by rank sum.
double ExactLowerTail(int n, double w) {
  const int max_sum = n * (n + 1) / 2;
  std::vector<double> count(static_cast<size_t>(max_sum) + 1, 0.0);
  count[0] = 1.0;
  for (int rank = 1; rank <= n; ++rank)
    for (int s = max_sum; s >= rank; --s)
      count[static_cast<size_t>(s)] += count[static_cast<size_t>(s - rank)];
  double below = 0.0;
  for (int s = 0; s <= max_sum && s <= static_cast<int>(std::floor(w + 1e-9)); ++s)
    below += count[static_cast<size_t>(s)];
  return below / std::ldexp(1.0, n);
}

double NormalCdf(double z) { return 0.5 * std::erfc(-z / std::sqrt(2.0)); }

}  // namespace

ConfidenceInterval BootstrapMeanInterval(const std::vector<double>& values, uint64_t seed,
                                         int resamples, double level) {
  ConfidenceInterval ci;
  ci.level = level;
  ci.resamples = resamples;
  if (values.empty()) {
    ci.low = ci.high = std::nan("");
    return ci;
  }
  if (values.size() == 1) {
    ci.low = ci.high = values.front();
    return ci;
  }
  std::mt19937_64 generator(seed);
  std::vector<double> means;
  means.reserve(static_cast<size_t>(resamples));
  const uint64_t n = values.size();
  for (int b = 0; b < resamples; ++b) {
    double sum = 0.0;
    // Index by the generator's raw output (not std::uniform_int_distribution, whose algorithm
    // differs between standard libraries), so that a seed gives the same interval everywhere.
    for (uint64_t k = 0; k < n; ++k) sum += values[generator() % n];
    means.push_back(sum / static_cast<double>(n));
  }
  std::sort(means.begin(), means.end());
  ci.low = Quantile(means, (1.0 - level) / 2.0);
  ci.high = Quantile(means, (1.0 + level) / 2.0);
  return ci;
}

SignedRankTest WilcoxonSignedRank(const std::vector<double>& differences) {
  SignedRankTest test;
  std::vector<double> d;
  for (const double x : differences)
    if (x != 0.0 && std::isfinite(x)) d.push_back(x);
  test.n = static_cast<int>(d.size());
  if (test.n == 0) return test;
  std::vector<size_t> order(d.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(),
            [&](size_t a, size_t b) { return std::abs(d[a]) < std::abs(d[b]); });
  std::vector<double> rank(d.size());
  bool ties = false;
  double tie_term = 0.0;  // sum of t^3 - t over tie groups
  for (size_t i = 0; i < order.size();) {
    size_t j = i;
    while (j + 1 < order.size() && std::abs(d[order[j + 1]]) == std::abs(d[order[i]])) ++j;
    const double average = 0.5 * static_cast<double>(i + j) + 1.0;
    for (size_t k = i; k <= j; ++k) rank[order[k]] = average;
    const double t = static_cast<double>(j - i + 1);
    if (t > 1) {
      ties = true;
      tie_term += t * t * t - t;
    }
    i = j + 1;
  }
  for (size_t i = 0; i < d.size(); ++i) (d[i] > 0 ? test.w_plus : test.w_minus) += rank[i];
  const double n = test.n;
  const double w = std::min(test.w_plus, test.w_minus);
  if (!ties && test.n <= 30) {
    test.exact = true;
    test.p_value = std::min(1.0, 2.0 * ExactLowerTail(test.n, w));
    return test;
  }
  const double mean = n * (n + 1.0) / 4.0;
  const double variance = n * (n + 1.0) * (2.0 * n + 1.0) / 24.0 - tie_term / 48.0;
  if (variance <= 0.0) return test;
  const double z = (w - mean + 0.5) / std::sqrt(variance);
  test.p_value = std::min(1.0, 2.0 * NormalCdf(z));
  return test;
}

}  // namespace mavloc
