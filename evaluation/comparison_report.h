// The Report (evaluation/report/report.h) of a comparison: one EstimatorResult per estimator with
// the ATE of the one trajectory-error engine (translation [m] and rotation angle [rad]), the
// coverage, the RMSE statistics of every quantity's error, the reprojection RMS per camera,
// estimated calibration with its sigma, frames without a pose and rejected measurements apart.
#pragma once

#include <string>
#include <vector>

#include "core/dataset.h"
#include "evaluation/comparison.h"
#include "evaluation/report/report.h"

namespace mavloc {

EstimatorResult ResultOfEvaluation(const EstimatorEvaluation& evaluation);

// The report of `mavloc compare`: estimators, protocol, warnings (low coverage, estimators left
// out); the caller adds files, sections and details.
Report ComparisonReport(const std::string& title, const Dataset& dataset,
                        const std::vector<EstimatorEvaluation>& evaluations,
                        const EvaluationOptions& options, const std::vector<std::string>& left_out);

}  // namespace mavloc
