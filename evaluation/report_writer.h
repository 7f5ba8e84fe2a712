// Report folders: report.md (people), report.json (tools; the contract of issue #2), and CSV files.
// Every file is written atomically (temporary file + rename); the folder is created if needed.
#pragma once

#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace mavloc {

struct Dataset;
struct EstimatorEvaluation;

struct ReportFiles {
  std::string markdown;                      // report.md
  nlohmann::json json;                       // report.json
  std::map<std::string, std::string> extra;  // file name -> contents (e.g. "errors.csv")
};

// Throws InputError when the folder cannot be created or written.
void WriteReportFolder(const std::string& folder, const ReportFiles& files);

// The trajectories of a comparison for its figures (evaluation/report_figures.h), as file name ->
// TUM text: truth.tum (the dataset's ground truth T_W_B) and estimate_<estimator>.tum for every
// estimator that returned poses, mapped by its ATE alignment S (p -> s R p + t, R_W_B -> R R_W_B)
// so that they overlay the truth as the ATE compares them. Estimator names are made file-safe.
std::map<std::string, std::string> ComparisonTrajectoryFiles(
    const Dataset& dataset, const std::vector<EstimatorEvaluation>& evaluations);

// A Markdown table from a header row and rows of cells.
std::string MarkdownTable(const std::vector<std::string>& header,
                          const std::vector<std::vector<std::string>>& rows);
// Number formatting for tables: fixed with `digits` decimals, "-" for NaN.
std::string FormatNumber(double value, int digits = 4);

}  // namespace mavloc
