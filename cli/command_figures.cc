// mavloc figures DIR: (re)draws the figures and report.html of a report folder written by `mavloc
// eval`, `mavloc compare` or `mavloc repro` (evaluation/report_figures.h) — after installing
// python3-matplotlib, or after editing a folder's CSV files.
#include <cstdio>
#include <filesystem>

#include "cli/commands.h"
#include "core/errors.h"
#include "core/input_file.h"
#include "evaluation/report_figures.h"

namespace mavloc::cli {
namespace {

// A report folder holds files, folders and (planted, replaced by the figures) links: a named pipe,
// a device or a socket where a report file is expected is refused before anything is read.
void RefuseSpecialFiles(const std::string& folder) {
  for (const auto& entry : std::filesystem::directory_iterator(folder)) {
    const auto type = entry.symlink_status().type();
    if (type == std::filesystem::file_type::regular ||
        type == std::filesystem::file_type::directory ||
        type == std::filesystem::file_type::symlink)
      continue;
    RequireRegularFile(entry.path().string());
  }
}

}  // namespace

void RegisterFigures(CLI::App& app, int* exit_code) {
  auto* command = app.add_subcommand(
      "figures",
      "Draw the figures and report.html of a report folder (eval, compare or repro); needs "
      "python3-matplotlib (MAVLOC_PYTHON names another interpreter)");
  auto folder = std::make_shared<std::string>();
  command->add_option("folder", *folder, "Report folder")->required();
  command->callback([folder, exit_code] {
    RequireFolder(*folder);
    RefuseSpecialFiles(*folder);
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
