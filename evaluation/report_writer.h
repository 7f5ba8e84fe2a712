// Helpers of the report producers: the trajectory files a comparison's figures draw, and Markdown
// tables and numbers for the producers' prose sections. The report itself is written by the one
// writer of evaluation/report/report_folder.h.
#pragma once

#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "evaluation/report/report.h"

namespace mavloc {

struct Dataset;
struct EstimatorEvaluation;

// The trajectories of a comparison for its figures (evaluation/report_figures.h), as file name ->
// TUM text: truth.tum (the dataset's ground truth T_W_B) and estimate_<estimator>.tum for every
// estimator that returned poses, mapped by its ATE alignment S (p -> s R p + t, R_W_B -> R R_W_B)
// so that they overlay the truth as the ATE compares them. Estimator names are made file-safe.
// With max_rows > 0 a file longer than that keeps every k-th pose (k = RowStride), and *strides
// (when given) receives k for every file thinned so.
std::map<std::string, std::string> ComparisonTrajectoryFiles(
    const Dataset& dataset, const std::vector<EstimatorEvaluation>& evaluations,
    size_t max_rows = 0, std::map<std::string, size_t>* strides = nullptr);

// The smallest k such that every k-th of `rows` rows fits in max_rows (1 when max_rows is 0).
size_t RowStride(size_t rows, size_t max_rows);

// A Markdown table from a header row and rows of cells.
std::string MarkdownTable(const std::vector<std::string>& header,
                          const std::vector<std::vector<std::string>>& rows);
// Number formatting for tables: fixed with `digits` decimals, "-" for NaN.
std::string FormatNumber(double value, int digits = 4);

}  // namespace mavloc
