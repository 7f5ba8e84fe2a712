// RMSE / bound of the laser quantities (evaluation/crlb/laser_efficiency.h) on a hand-made bound:
// association within the tolerance, angles wrapped, absent values skipped, sums over runs before
// the ratio, the Monte-Carlo standard error by hand, and the exact JSON round trip.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "evaluation/crlb/laser_bound.h"
#include "evaluation/crlb/laser_efficiency.h"

namespace mavloc {
namespace {

constexpr TimeNs kMs = 1'000'000;

// Three keyframes at 0, 100, 200 ms with the given truth and the bound's variances
// (d 1e-4 m^2, v_o 4e-4, roll/pitch/alpha 1e-6 rad^2); filtering only from the second one.
SmootherCrlb HandMadeBound() {
  SmootherCrlb bound;
  bound.ok = true;
  bound.laser_only = true;
  for (int k = 0; k < 3; ++k) {
    CrlbKeyframe kf;
    kf.t_ns = k * 100 * kMs;
    kf.smoothing = Matrix15d::Zero();
    CrlbLaserQuantities q;
    q.truth << 1.0 + 0.1 * k, 0.01 * k, 3.1, -0.2, 0.4;
    q.smoothing.diagonal() << 1e-4, 4e-4, 1e-6, 1e-6, 1e-6;
    if (k > 0) q.filtering = Eigen::Matrix<double, 5, 5>(4.0 * q.smoothing);
    kf.laser = q;
    bound.keyframes.push_back(kf);
  }
  return bound;
}

TEST(CrlbLaserEfficiency, SumsRatiosAndJson) {
  const SmootherCrlb bound = HandMadeBound();
  QuantityTable estimate(LaserQuantityNames(), LaserQuantityUnits());
  const double nan = std::numeric_limits<double>::quiet_NaN();
  // Keyframe 0 within 1 ms (roll across +-pi: -3.1 is 0.083 rad from 3.1), keyframe 1 with d
  // absent, keyframe 2 3 ms away (outside the 2 ms tolerance).
  estimate.Append(1 * kMs, {1.02, 0.0, -3.1, -0.19, 0.401});
  estimate.Append(101 * kMs, {nan, 0.03, 3.1, -0.2, 0.4});
  estimate.Append(203 * kMs, {5.0, 5.0, 0.0, 0.0, 0.0});
  const LaserEfficiencySums s = CompareLaserWithBound(bound, estimate, BoundKind::kSmoothing);
  EXPECT_EQ(s.runs, 1);
  ASSERT_EQ(s.quantities.count("d"), 1u);
  EXPECT_EQ(s.quantities.at("d").frames, 1);
  EXPECT_EQ(s.quantities.at("v_o").frames, 2);
  EXPECT_NEAR(s.Ratio("d"), std::sqrt(0.02 * 0.02 / 1e-4), 1e-9);
  EXPECT_NEAR(s.Ratio("v_o"), std::sqrt((0.0 + 0.02 * 0.02) / 8e-4), 1e-9);
  const double roll_error = 2.0 * M_PI - 6.2;
  EXPECT_NEAR(s.Rmse("roll"), std::sqrt(roll_error * roll_error / 2.0), 1e-9);
  EXPECT_NEAR(s.BoundRms("alpha"), 1e-3, 1e-12);
  EXPECT_TRUE(std::isnan(s.RatioStandardError("d")));  // one run

  // Filtering: keyframe 0 has none.
  const LaserEfficiencySums f = CompareLaserWithBound(bound, estimate, BoundKind::kFiltering);
  EXPECT_EQ(f.quantities.at("v_o").frames, 1);
  EXPECT_EQ(f.quantities.count("d"), 0u);

  // Two runs: squared errors summed before the ratio; the standard error by hand.
  LaserEfficiencySums total;
  total.Add(s);
  QuantityTable second(LaserQuantityNames(), LaserQuantityUnits());
  second.Append(0, {1.0, 0.0, 3.1, -0.2, 0.43});
  total.Add(CompareLaserWithBound(bound, second, BoundKind::kSmoothing));
  EXPECT_EQ(total.runs, 2);
  // alpha: run 1 has errors 0.001 and 0 (two frames), run 2 has 0.03 (one frame); bound 1e-6.
  EXPECT_NEAR(total.Ratio("alpha"), std::sqrt((1e-6 + 9e-4) / 3e-6), 1e-9);
  const double e1 = 1e-6 / 2.0, e2 = 9e-4, b = 1e-6;  // per-run means
  const double ratio2 = (e1 + e2) / 2.0 / b;
  const double var = std::pow(e1 - ratio2 * b, 2) + std::pow(e2 - ratio2 * b, 2);  // / (n - 1)
  EXPECT_NEAR(total.RatioStandardError("alpha"), 0.5 * std::sqrt(var / 2.0) / b / std::sqrt(ratio2),
              1e-9);

  // JSON: every field back exactly.
  const LaserEfficiencySums back = LaserEfficiencySumsFromJson(LaserEfficiencySumsToJson(total));
  EXPECT_EQ(back.runs, total.runs);
  ASSERT_EQ(back.quantities.size(), total.quantities.size());
  for (const auto& [name, q] : total.quantities) {
    const QuantityEfficiency& r = back.quantities.at(name);
    EXPECT_EQ(r.error2, q.error2) << name;
    EXPECT_EQ(r.bound2, q.bound2) << name;
    EXPECT_EQ(r.frames, q.frames) << name;
    EXPECT_EQ(r.run_error2, q.run_error2) << name;
    EXPECT_EQ(r.run_bound2, q.run_bound2) << name;
  }

  // A bound without laser quantities compares nothing.
  SmootherCrlb poses_only = bound;
  poses_only.laser_only = false;
  EXPECT_EQ(CompareLaserWithBound(poses_only, estimate, BoundKind::kSmoothing).runs, 0);
}

}  // namespace
}  // namespace mavloc
