// Report folders: report.md (people), report.json (tools: the keys other programs read), and CSV
// files. Every file is written atomically (temporary file + rename); the folder is created if
// needed.
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

struct ReportFiles {
  // What wrote the report: "compare", "repro", "obstacles" (report.json's report_kind, by which
  // `mavloc figures` recognises a report folder).
  std::string kind = "repro";
  std::string markdown;                      // report.md
  nlohmann::json json;                       // report.json
  std::map<std::string, std::string> extra;  // file name -> contents (e.g. "errors.csv")
  // The trajectory or quantity comparison protocol the producer used, stated in the report.
  std::optional<ReportProtocol> protocol;
};

// A producer's Markdown and JSON as a Report (evaluation/report/report.h): the title from the
// Markdown's first heading, the rest of it as one section, the JSON as the report's details.
Report ReportFromFiles(const ReportFiles& files);

// Writes ReportFromFiles(files) with the one report writer (evaluation/report/report_folder.h).
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
