// mavloc matrix ROOT --out DIR: estimators x sequences x runs from rpg_trajectory_evaluation's
// folder layout (evaluation/matrix/matrix_evaluation.h): the mean APE RMSE per cell with its
// bootstrap interval, paired Wilcoxon tests, a LaTeX table, grouped boxplots.
#include <cstdio>

#include "cli/commands.h"
#include "cli/option_checks.h"
#include "cli/output_folder.h"
#include "core/errors.h"
#include "evaluation/matrix/matrix_evaluation.h"
#include "evaluation/report/report_folder.h"
#include "evaluation/report/report_markdown.h"
#include "evaluation/report_figures.h"

namespace mavloc::cli {

void RegisterMatrix(CLI::App& app, int* exit_code) {
  auto* command = app.add_subcommand(
      "matrix",
      "Estimators x sequences x runs from an rpg_trajectory_evaluation folder "
      "(<estimator>/<platform>_<estimator>_<sequence>/stamped_*.txt): mean APE RMSE with bootstrap "
      "intervals, paired Wilcoxon tests, LaTeX, grouped boxplots");
  struct Args {
    std::string root, out, align = "se3";
    uint64_t seed = 1;
    double max_dt_s = 0.01;
    bool force = false;
  };
  auto args = std::make_shared<Args>();
  command->add_option("root", args->root, "Platform folder of the rpg layout")->required();
  command->add_option("--out", args->out, "Report folder (created)")
      ->check(OutputFolder())
      ->required();
  command->add_option("--align", args->align, "Alignment: none, se3, sim3 or posyaw")
      ->capture_default_str();
  // Finite and at most an hour: CLI::PositiveNumber let "nan" through to blame a valid file.
  command->add_option("--t-max-diff", args->max_dt_s, "Association tolerance [s]")
      ->check(PositiveAtMost(3600.0, "s"))
      ->capture_default_str();
  AddSeedOption(command, &args->seed, "Seed of the bootstrap intervals");
  command->add_flag("--force", args->force, "Replace an existing --out folder (a mavloc report)");
  command->callback([args, exit_code] {
    const auto align = ParseAlignmentMode(args->align);
    if (!align)
      throw InputError("--align '" + args->align + "': expected none, se3, sim3 or posyaw");
    StagedFolder out(args->out, FolderKind::kReport, args->force);
    EvaluationProtocol protocol;
    protocol.alignment = *align;
    protocol.max_dt_s = args->max_dt_s;
    const MatrixResult result = EvaluateMatrix(FindRpgLayout(args->root), protocol, args->seed);
    Report report = MatrixReport(result);
    // Files the walk did not use are named in the report; the ones named like a run, here too.
    for (const auto& warning : report.warnings)
      std::fprintf(stderr, "mavloc: warning: %s\n", PrintableMessage(warning).c_str());
    if (!result.skipped.empty())
      std::fprintf(stderr, "mavloc: %zu file(s) not used, each with the reason: report.md\n",
                   result.skipped.size());
    report.provenance.input = args->root;
    std::printf("%s\n", report.title.c_str());
    for (const auto& table : report.tables)
      if (table.name != "ate_rmse_cells") {
        std::vector<std::string> header;
        for (const auto& c : table.columns)
          header.push_back(c.name + (c.unit.empty() ? "" : " [" + c.unit + "]"));
        std::vector<std::vector<std::string>> rows;
        for (const auto& row : table.rows) {
          std::vector<std::string> cells;
          for (const auto& cell : row)
            cells.push_back(cell.is_number()   ? TableNumber(cell.get<double>())
                            : cell.is_string() ? cell.get<std::string>()
                                               : "-");
          rows.push_back(cells);
        }
        std::printf("\n%s\n%s", table.title.c_str(), MarkdownTableOf(header, rows).c_str());
      }
    WriteReport(out.path(), report);
    const FigureOutcome figures = WriteReportFigures(out.path(), out.ForUser(out.path()));
    out.Commit();
    std::printf(
        "\nreport written to %s/ (report.md, report.json, matrix.tex, runs.csv, "
        "relative_errors.csv)\n%s\n",
        args->out.c_str(), out.ForUser(DescribeFigureOutcome(figures)).c_str());
    *exit_code = 0;
  });
}

}  // namespace mavloc::cli
