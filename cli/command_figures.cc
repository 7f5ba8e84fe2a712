// mavloc figures DIR: (re)draws the figures and report.html of a report folder written by `mavloc
// eval`, `mavloc compare` or `mavloc repro` (evaluation/report_figures.h) — after installing
// python3-matplotlib, or after editing a folder's CSV files.
#include <cstdio>
#include <filesystem>

#include "cli/commands.h"
#include "core/errors.h"
#include "evaluation/report_figures.h"

namespace mavloc::cli {

void RegisterFigures(CLI::App& app, int* exit_code) {
  auto* command = app.add_subcommand(
      "figures",
      "Draw the figures and report.html of a report folder (eval, compare or repro); needs "
      "python3-matplotlib (MAVLOC_PYTHON names another interpreter)");
  auto folder = std::make_shared<std::string>();
  command->add_option("folder", *folder, "Report folder")->required();
  command->callback([folder, exit_code] {
    if (!std::filesystem::is_directory(*folder)) throw InputError(*folder, 0, "", "not a folder");
    if (DetectReportKind(*folder) == ReportKind::kUnknown)
      throw InputError(*folder, 0, "",
                       "no mavloc report here (no report.json or eval.json naming its "
                       "report_kind)");
    const FigureOutcome outcome = WriteReportFigures(*folder);
    std::printf("%s\n", DescribeFigureOutcome(outcome).c_str());
    // No figures is a failure of this command (its only job), unlike after eval/compare/repro.
    *exit_code = outcome.figures.empty() ? 1 : 0;
  });
}

}  // namespace mavloc::cli
