// The Cramér–Rao section of a `mavloc compare` report: on a simulated dataset the
// smoother's bound (evaluation/crlb/smoother_bound.h), per quantity as a standard deviation (RMS
// over the keyframes) for smoothing and filtering, and every estimator's RMSE / bound at the
// keyframes where it has a pose (smoother: smoothing bound; causal estimators: filtering bound).
// One dataset is one Monte-Carlo draw: `mavloc repro smoother` averages over seeds. Laser-only
// data: the bound and the ratios of the five laser quantities (d, v_o, roll, pitch, alpha) of
// every estimator that reports them, instead of position and attitude.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/dataset.h"
#include "evaluation/comparison.h"
#include "evaluation/crlb/smoother_bound.h"

namespace mavloc {

struct CrlbReport {
  bool available = false;
  std::string reason;    // why not, when !available
  std::string markdown;  // a "## Cramér–Rao bound" section
  std::string text;      // the same tables for stdout
  nlohmann::json json;
};

CrlbReport MakeCrlbReport(const Dataset& dataset,
                          const std::vector<EstimatorEvaluation>& evaluations,
                          const EstimatorOptions& smoother_options);

// Per-quantity RMS of the bound's standard deviations (x y z [m], roll pitch yaw [rad], vx vy vz
// [m/s], bgx.. [rad/s], bax.. [m/s^2]), smoothing or filtering, over the keyframes that have both
// bounds (their count in *keyframes), so that the two compare the same keyframes.
std::vector<std::pair<std::string, double>> BoundQuantityRms(const SmootherCrlb& bound,
                                                             bool filtering, int* keyframes);

// Laser-only data: RMS over the keyframes of the bound's standard deviation of d [m], v_o [m/s],
// roll, pitch, alpha [rad] (LaserQuantityNames); filtering over the keyframes where it exists;
// NaN where there is none.
std::vector<double> LaserBoundRms(const SmootherCrlb& bound, bool filtering);

}  // namespace mavloc
