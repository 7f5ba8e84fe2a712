// Runs estimators on a dataset and evaluates each against the ground truth: the engine behind
// `mavloc compare` and the building block of paper reproductions (Monte-Carlo loops call it per
// seed). Evaluation needs no knowledge of how an estimator works: only its named quantities and
// poses.
#pragma once

#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "core/dataset.h"
#include "core/estimate.h"
#include "evaluation/alignment.h"
#include "evaluation/quantity_errors.h"
#include "evaluation/reference.h"
#include "evaluation/report/report.h"
#include "evaluation/reprojection.h"
#include "evaluation/trajectory_evaluation.h"
#include "evaluation/trajectory_metrics.h"
#include "solver/estimator.h"

namespace mavloc {

struct EvaluationOptions {
  AlignmentMode align = AlignmentMode::kNone;  // for ATE
  double max_dt_s = 0.02;                      // association tolerance
  std::vector<std::string> quantities;         // restrict per-quantity errors (empty = all shared)
  // Compare against this reference (an estimate, not a truth) instead of the dataset's ground
  // truth. Not owned; must outlive the evaluation.
  const ComparisonReference* reference = nullptr;
};

// The ATE of a comparison, taken from the trajectory-error engine's result (rotation in rad).
struct AteResult {
  AlignmentMode align = AlignmentMode::kNone;
  Similarity alignment;
  ErrorStatistics translation_m;
  ErrorStatistics rotation_rad;
  std::vector<double> translation_errors_m;  // per pair, in pair order
};

struct EstimatorEvaluation {
  std::string estimator;
  bool ran = false;
  std::string skipped_reason;  // when !ran: why it does not apply
  double runtime_s = 0.0;
  Estimate estimate;
  std::vector<QuantityErrorSeries> quantity_errors;
  std::optional<AteResult> ate;
  // Against a reference: whether this estimator is the reference itself (not compared).
  bool is_reference = false;
  std::vector<ReprojectionStatistics> reprojection;  // tag corners, per camera
  // How much of the estimate's poses the ATE covers (set when the estimate has poses).
  std::optional<Coverage> coverage;
  // The trajectory-error engine's diagnostics (ill-conditioned alignment, time or rotation
  // offset, too few pairs), one line each.
  std::vector<std::string> warnings;
};

// The protocol of a comparison: the one trajectory-error engine (trajectory_evaluation.h) with the
// comparison's alignment and association tolerance, truth interpolated at the estimate's stamps.
EvaluationProtocol ComparisonProtocol(const EvaluationOptions& options);

// Evaluates an estimate against the dataset's ground truth, or against options.reference when set;
// the tag reprojection statistics are computed either way.
EstimatorEvaluation EvaluateEstimate(const std::string& estimator_name, Estimate estimate,
                                     const Dataset& dataset, const EvaluationOptions& options);

// Creates, runs (timing it) and evaluates an estimator; a non-applicable one comes back with
// ran = false and its reason.
EstimatorEvaluation RunAndEvaluate(const std::string& estimator_name,
                                   const EstimatorOptions& estimator_options,
                                   const Dataset& dataset, const EvaluationOptions& options);

// The report.json object of one estimator: {"quantities": {q: {mean_abs, rmse, unit}}, "ate":
// {rmse, align, ...}, "runtime_s"}, every value in SI units (angles in radians) with its unit.
nlohmann::json EvaluationToJson(const EstimatorEvaluation& evaluation);

// errors.csv (long format: estimator, quantity, unit, t, estimate, truth, error). With max_rows > 0
// and more rows than that, every series keeps every k-th row (k = RowStride of all rows, returned
// in *stride when given).
std::string ErrorsCsv(const std::vector<EstimatorEvaluation>& evaluations, size_t max_rows = 0,
                      size_t* stride = nullptr);

}  // namespace mavloc
