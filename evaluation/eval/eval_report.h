// The report of `mavloc eval`: one table estimates x metrics (mean and
// sample standard deviation over the runs of an estimator), the protocol that reproduces every
// number, and the data files the figure writer (evaluation/report_figures.h) reads:
//   eval.md, eval.tex, eval.json,
//   truth.tum                         the ground truth as read (sorted, repeated stamps dropped),
//   estimate_<label>[_run<k>].tum     each estimate after alignment, in the truth's frame (stamps
//                                     with the time offset applied),
//   errors_over_time.csv              label,run,t_s,translation_error_m,rotation_error_deg
//                                     (APE per associated pair; t_s from the truth's first stamp),
//   relative_errors.csv               label,run,length_m,translation_error_pct,
//                                     rotation_error_deg_per_m (one row per sub-trajectory).
// run is k = 1..n for the runs of a folder, 0 for a single file.
#pragma once

#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "evaluation/eval/eval_run.h"
#include "evaluation/report/report.h"

namespace mavloc {

// The metrics of the table, per run; the same list for every run. `value` is SI (the json key
// names its unit); the tables show value * display_scale under `title` (degrees for angles).
struct MetricValue {
  std::string key;    // json key, e.g. "ape_rotation_rmse_rad"
  std::string title;  // table header, e.g. "APE rot. RMSE [deg]"
  double value = 0.0;
  double display_scale = 1.0;
};
std::vector<MetricValue> RunMetrics(const EvalRun& run, const EvaluationProtocol& protocol);

std::string EvalMarkdown(const EvalReport& report);
std::string EvalLatex(const EvalReport& report);
nlohmann::json EvalJson(const EvalReport& report);
// The table alone (for the terminal).
std::string EvalSummaryTable(const EvalReport& report);
// The data files of the report folder (eval.tex, the trajectories, the CSVs): name -> contents.
// Needs the runs' series (report.protocol.keep_series; std::logic_error otherwise).
std::map<std::string, std::string> EvalReportFiles(const EvalReport& report);
// Their names alone, without building them (report.json lists them).
std::vector<std::string> EvalReportFileNames(const EvalReport& report);
// The report of the one results model (evaluation/report/report.h): one estimator result per run,
// eval's own tables as a section, its JSON as the details, EvalReportFiles as the files. Evaluated
// without the series (report.json alone), the files are named with empty contents: the model is
// for ReportJsonText then, not for writing a report folder.
Report EvalModel(const EvalReport& report);
// estimate_<label>[_run<k>].tum
std::string EstimateFileName(const EvalEstimate& estimate, const EvalRun& run);

}  // namespace mavloc
