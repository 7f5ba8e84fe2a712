// Efficiency of an estimator's laser quantities (d, v_o, roll, pitch, alpha of RR-7906, the
// gauge-invariant quantities of laser-only data; evaluation/crlb/laser_bound.h) against the
// Cramér–Rao bound, per quantity as efficiency.h does for position and attitude:
// squared errors e = estimate - truth (angles wrapped into (-pi, pi]) and the bound's variances
// summed over the keyframes where both exist and over Monte-Carlo runs before the ratio
// RMSE / bound = sqrt(sum e^2 / sum sigma^2) (>= 1 up to Monte-Carlo noise for an unbiased
// estimator). The truth is the bound's (CrlbLaserQuantities::truth: the simulator's definition at
// the keyframe's true state, equal to the dataset's truth quantities at its stamps).
#pragma once

#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/quantities.h"
#include "evaluation/crlb/efficiency.h"
#include "evaluation/crlb/smoother_bound.h"

namespace mavloc {

struct QuantityEfficiency {
  double error2 = 0.0;  // sum of squared errors (SI^2)
  double bound2 = 0.0;  // sum of the bound's variances
  int frames = 0;
  // Per run: the mean squared error and the mean bound variance over its frames (for the
  // Monte-Carlo uncertainty of the ratio; runs without a frame are left out).
  std::vector<double> run_error2, run_bound2;
};

struct LaserEfficiencySums {
  std::map<std::string, QuantityEfficiency> quantities;  // by name (LaserQuantityNames)
  int runs = 0;

  void Add(const LaserEfficiencySums& other);
  // RMS over frames and runs of the bound's standard deviation, RMSE, and RMSE / bound; NaN when
  // no frame was compared.
  double BoundRms(const std::string& name) const;
  double Rmse(const std::string& name) const;
  double Ratio(const std::string& name) const;
  // Monte-Carlo standard error of Ratio (delta method on the per-run means: the ratio of means
  // sqrt(mean e2 / mean b2) with its linearised variance over runs); NaN with fewer than 2 runs.
  double RatioStandardError(const std::string& name) const;
};

// One run: the estimate's quantity table (columns named as LaserQuantityNames; rows associated
// within max_dt_ns to the bound's keyframes) against the bound (kSmoothing: the batch bound,
// kFiltering: the causal bound, keyframes before it exists left out). Empty (no quantity) when the
// bound has no laser quantities.
LaserEfficiencySums CompareLaserWithBound(const SmootherCrlb& bound, const QuantityTable& estimate,
                                          BoundKind kind, TimeNs max_dt_ns = 2'000'000);

// Every field as JSON and back, exactly (non-finite values as null, read back as NaN), for sweep
// workers. Throws nlohmann's exceptions for a malformed object.
nlohmann::json LaserEfficiencySumsToJson(const LaserEfficiencySums& sums);
LaserEfficiencySums LaserEfficiencySumsFromJson(const nlohmann::json& json);

}  // namespace mavloc
