#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "evaluation/matrix/matrix_evaluation.h"
#include "evaluation/report/csv_field.h"
#include "evaluation/report/latex.h"
#include "evaluation/report/report_protocol.h"

namespace mavloc {
namespace {

const MatrixCell* Find(const MatrixResult& r, const std::string& e, const std::string& s) {
  for (const auto& c : r.cells)
    if (c.estimator == e && c.sequence == s) return &c;
  return nullptr;
}

// Sequences x estimators, mean +- sample std of the APE translation RMSE over runs [m]; the lowest
// mean of each sequence in bold.
std::string Latex(const MatrixResult& r) {
  std::string tex =
      "% mavloc matrix: APE translation RMSE [m], mean $\\pm$ sample std over runs; "
      "bold: the lowest mean of the sequence\n\\begin{tabular}{l";
  for (size_t k = 0; k < r.estimators.size(); ++k) tex += "r";
  tex += "}\n\\hline\nsequence";
  for (const auto& e : r.estimators) tex += " & " + LatexEscape(e);
  tex += " \\\\\n\\hline\n";
  for (const auto& s : r.sequences) {
    double best = INFINITY;
    for (const auto& e : r.estimators)
      if (const MatrixCell* c = Find(r, e, s)) best = std::min(best, c->mean_m);
    tex += LatexEscape(s);
    for (const auto& e : r.estimators) {
      const MatrixCell* c = Find(r, e, s);
      if (!c) {
        tex += " & --";
        continue;
      }
      std::string cell = c->runs.size() > 1
                             ? fmt::format("{:.4f} $\\pm$ {:.4f}", c->mean_m, c->std_m)
                             : fmt::format("{:.4f}", c->mean_m);
      tex += " & " + (c->mean_m == best ? "\\textbf{" + cell + "}" : cell);
    }
    tex += " \\\\\n";
  }
  return tex + "\\hline\n\\end{tabular}\n";
}

std::string RunsCsv(const MatrixResult& r) {
  std::string csv = "estimator,sequence,run,file,pairs,ate_rmse_m,ate_rotation_rmse_rad\n";
  for (const auto& c : r.cells)
    for (size_t k = 0; k < c.runs.size(); ++k)
      csv +=
          fmt::format("{},{},{},{},{},{:.9g},{:.9g}\n", CsvField(c.estimator), CsvField(c.sequence),
                      k, CsvField(std::filesystem::path(c.runs[k].path).filename().string()),
                      c.runs[k].pairs, c.runs[k].ate_rmse_m, c.runs[k].ate_rotation_rmse_rad);
  return csv;
}

std::string RelativeCsv(const MatrixResult& r) {
  std::string csv = "estimator,sequence,run,length_m,translation_error_pct\n";
  for (const auto& c : r.cells)
    for (size_t k = 0; k < c.runs.size(); ++k)
      for (const auto& rel : c.runs[k].relative)
        for (const double pct : rel.translation_percent)
          csv += fmt::format("{},{},{},{:g},{:.9g}\n", CsvField(c.estimator), CsvField(c.sequence),
                             k, rel.length_m, pct);
  return csv;
}

ReportTable MeanTable(const MatrixResult& r) {
  ReportTable t{"ate_rmse_mean",
                "APE translation RMSE, mean over runs, per sequence and estimator",
                {{"sequence", ""}},
                {}};
  for (const auto& e : r.estimators) t.columns.push_back({e, "m"});
  for (const auto& s : r.sequences) {
    std::vector<nlohmann::json> row = {s};
    for (const auto& e : r.estimators) {
      const MatrixCell* c = Find(r, e, s);
      row.push_back(c ? nlohmann::json(c->mean_m) : nlohmann::json());
    }
    t.rows.push_back(row);
  }
  return t;
}

ReportTable CellTable(const MatrixResult& r) {
  ReportTable t{"ate_rmse_cells",
                "APE translation RMSE over runs: mean, sample std and the bootstrap 95 % interval "
                "of the mean",
                {{"estimator", ""},
                 {"sequence", ""},
                 {"runs", ""},
                 {"mean", "m"},
                 {"std", "m"},
                 {"95 % low", "m"},
                 {"95 % high", "m"}},
                {}};
  for (const auto& c : r.cells)
    t.rows.push_back({c.estimator, c.sequence, static_cast<int>(c.runs.size()), c.mean_m, c.std_m,
                      c.interval.low, c.interval.high});
  return t;
}

// Every file the folder walk did not use, with the reason (matrix_evaluation.h: RpgLayout).
ReportTable SkippedTable(const MatrixResult& r) {
  ReportTable t{"skipped_files",
                "Files of the folder that were not used, and why",
                {{"file", ""}, {"reason", ""}},
                {}};
  for (const auto& skipped : r.skipped) t.rows.push_back({skipped.path, skipped.reason});
  return t;
}

ReportTable PairTable(const MatrixResult& r) {
  ReportTable t{"paired_tests",
                "Wilcoxon signed-rank test of the per-sequence mean RMSE, a - b, two-sided",
                {{"a", ""},
                 {"b", ""},
                 {"sequences", ""},
                 {"a lower on", ""},
                 {"W+", ""},
                 {"W-", ""},
                 {"p-value", ""},
                 {"p exact", ""}},
                {}};
  for (const auto& p : r.pairs)
    t.rows.push_back({p.a, p.b, p.sequences, p.a_better, p.test.w_plus, p.test.w_minus,
                      p.test.p_value, p.test.exact ? "yes" : "normal approximation"});
  return t;
}

}  // namespace

Report MatrixReport(const MatrixResult& r) {
  Report report;
  report.kind = "matrix";
  report.title = fmt::format("mavloc matrix: {} estimators x {} sequences", r.estimators.size(),
                             r.sequences.size());
  report.protocol = ReportProtocolOf(r.protocol, false);
  report.provenance.seeds = {r.seed};
  int runs = 0;
  for (const auto& c : r.cells) runs += static_cast<int>(c.runs.size());
  report.provenance.runs = runs;
  for (const auto& e : r.estimators) {
    EstimatorResult result;
    result.name = e;
    for (const auto& c : r.cells) {
      if (c.estimator != e) continue;
      std::vector<double> rmse;
      for (const auto& run : c.runs) rmse.push_back(run.ate_rmse_m);
      result.metrics["ate_translation_rmse." + c.sequence] = {"m", std::nullopt,
                                                              ComputeStatistics(rmse)};
    }
    report.estimators.push_back(result);
  }
  report.tables = {MeanTable(r), CellTable(r), PairTable(r)};
  if (!r.skipped.empty()) {
    report.tables.push_back(SkippedTable(r));
    // A file named like a run that was not used changes the result: each is a warning.
    for (const auto& skipped : r.skipped)
      if (std::filesystem::path(skipped.path).filename().string().rfind("stamped_", 0) == 0)
        report.warnings.push_back(skipped.path + ": not used: " + skipped.reason);
  }
  report.sections.push_back(
      {"Method",
       fmt::format(
           "Per run the APE translation RMSE of the one trajectory-error engine under the "
           "protocol above; per cell the mean and sample standard deviation over runs and a "
           "percentile bootstrap interval of the mean ({} resamples, seed {} mixed with the "
           "cell's index: the same seed gives the same intervals). Per pair of estimators the "
           "Wilcoxon signed-rank test of their per-sequence means over the sequences both ran "
           "(exact null distribution without ties up to 30 sequences). Relative errors over the "
           "same lengths for every estimator of a sequence (10..50 % of its ground truth's path) "
           "are in relative_errors.csv, drawn as grouped boxplots; matrix.tex is the LaTeX "
           "table with the lowest mean per sequence in bold.\n",
           r.cells.empty() ? 0 : r.cells.front().interval.resamples, r.seed)});
  report.files["matrix.tex"] = Latex(r);
  report.files["runs.csv"] = RunsCsv(r);
  report.files["relative_errors.csv"] = RelativeCsv(r);
  return report;
}

}  // namespace mavloc
