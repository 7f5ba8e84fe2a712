// Figures and report.html for every report folder (`mavloc eval`, `mavloc compare`, `mavloc
// repro`). The figures are drawn by Debian's python3-matplotlib: the plotting script is embedded in
// the binary at build time (scripts/figures/report_figures.py -> a generated header), written to a
// temporary file and run with /usr/bin/python3 (or $MAVLOC_PYTHON), so a binary that was moved away
// from its source tree still plots. report.html is then written beside the Markdown report: one
// self-contained page (its tables, figures as base64 PNG data URIs, no network).
//
// Missing python3 or matplotlib is not an error: report.html is written without figures and says
// how to get them (FigureOutcome::how_to_get_figures); nothing throws for it.
#pragma once

#include <string>
#include <vector>

namespace mavloc {

// What the folder holds, as its report.json (or eval.json) declares in "report_kind": eval
// (`mavloc eval --out DIR`), compare, repro, sweep, obstacles or matrix. A folder without such a
// file is no report, whatever other files it holds.
enum class ReportKind { kUnknown, kEval, kCompare, kRepro, kSweep, kObstacles, kMatrix, kImuNoise };

// "eval", "compare", "repro", "sweep", "obstacles", "matrix", "imu-noise", "unknown"
std::string ReportKindName(ReportKind kind);
ReportKind DetectReportKind(const std::string& report_dir);

struct FigureOutcome {
  ReportKind kind = ReportKind::kUnknown;
  std::vector<std::string> figures;  // PNG file names written in report_dir, in page order
  std::string html_path;             // report_dir/report.html; empty if it could not be written
  // Empty when figures were drawn; otherwise why none were (python missing, matplotlib missing,
  // script error, nothing to plot).
  std::string reason;
  // When no figures were drawn because the interpreter or matplotlib is missing: the exact
  // package and command ("sudo apt-get install python3-matplotlib", then "mavloc figures DIR"),
  // also written into report.html and the Markdown report.
  std::string how_to_get_figures;
  bool ok() const { return reason.empty(); }
};

// Detects the folder's kind, runs the embedded plotting script, writes report.html. Never throws
// for a missing interpreter or a plotting failure (see FigureOutcome::reason); returns with the
// reason set when report_dir does not exist. The interpreter is $MAVLOC_PYTHON when set (tests set
// it to a nonexistent path to exercise the fallback), else /usr/bin/python3; MAVLOC_FIGURES=0 (or
// off) skips the figures. The Markdown report (eval.md or report.md) gets a "Figures" section
// (listing them, or saying how to get them), replaced on every call.
// `shown_dir` is the folder the texts name ("then `mavloc figures DIR`", the fallback title): the
// report's final folder when report_dir is a staging folder renamed into place afterwards
// (cli/output_folder.h); empty means report_dir.
FigureOutcome WriteReportFigures(const std::string& report_dir, const std::string& shown_dir = "");

// One line for the terminal: "figures: a.png, b.png; report.html" or the reason and how to get
// them.
std::string DescribeFigureOutcome(const FigureOutcome& outcome);

}  // namespace mavloc
