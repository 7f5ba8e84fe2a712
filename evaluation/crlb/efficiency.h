// Efficiency of an estimator against a Cramér–Rao bound: squared errors and bound
// variances summed over the keyframes where both exist, and over Monte-Carlo runs, before the
// ratio RMSE / bound = sqrt(sum |e|^2 / sum trace(C)). trace(C) of the position (attitude) block
// bounds the mean squared position error (rotation angle, R_true^T R_est) of any unbiased
// estimator, so the ratio is >= 1 up to Monte-Carlo noise for an unbiased estimator.
#pragma once

#include <array>
#include <map>
#include <nlohmann/json.hpp>
#include <vector>

#include "core/pose.h"
#include "evaluation/crlb/smoother_bound.h"

namespace mavloc {

struct EfficiencySums {
  double position_error2 = 0.0;  // sum |p_est - p_true|^2 [m^2]
  double position_bound2 = 0.0;  // sum trace(C_pp)
  double attitude_error2 = 0.0;  // sum angle(R_true^T R_est)^2 [rad^2]
  double attitude_bound2 = 0.0;  // sum trace(C_thetatheta)
  int frames = 0;
  int runs = 0;

  void Add(const EfficiencySums& other);
  // RMS over the frames (and runs) of the bound's standard deviation, and the ratios; NaN when
  // no frame was compared.
  double PositionBoundRms() const;
  double AttitudeBoundRms() const;
  double PositionRatio() const;
  double AttitudeRatio() const;
  // Per-run squared-error means (for the Monte-Carlo uncertainty of the ratio).
  std::vector<double> run_position_error2, run_position_bound2;
  std::vector<double> run_attitude_error2, run_attitude_bound2;
  // Per keyframe stamp (rounded to 1 ms): sums over runs of |e_p|^2, trace C_pp, angle^2,
  // trace C_thetatheta, and the number of runs (for error-RMS-over-time against the bound).
  std::map<TimeNs, std::array<double, 5>> per_time;
};

// Every field as JSON and back, exactly (doubles keep all their digits; a non-finite value is
// written as null and read back as NaN): a run computed in a sweep worker (`repro smoother
// --jobs`) adds up to the same sums as one computed in the process. Throws nlohmann's exceptions
// for a malformed object.
nlohmann::json EfficiencySumsToJson(const EfficiencySums& sums);
EfficiencySums EfficiencySumsFromJson(const nlohmann::json& json);

enum class BoundKind { kSmoothing, kFiltering };

// One run: the estimate's poses (any rate; associated within max_dt_ns to the bound's keyframes)
// against the bound. Keyframes without a pose, or without a filtering bound (kFiltering, before
// the state is observable), are left out of both sums.
EfficiencySums CompareWithBound(const SmootherCrlb& bound, const std::vector<StampedPose>& poses,
                                BoundKind kind, TimeNs max_dt_ns = 2'000'000);

}  // namespace mavloc
