// mavloc repro NAME: reproduce a paper's tables (see `mavloc list`), with figures and report.html.
#include <cstdio>

#include "cli/commands.h"
#include "cli/common.h"
#include "cli/option_checks.h"
#include "cli/output_folder.h"
#include "core/errors.h"
#include "evaluation/report_figures.h"
#include "evaluation/repro/repro.h"
#include "evaluation/sweep/sweep_runner.h"

namespace mavloc::cli {

void RegisterRepro(CLI::App& app, int* exit_code) {
  auto* command = app.add_subcommand("repro", "Reproduce a paper's tables (names: `mavloc list`)");
  struct Args {
    std::string name, report;
    int runs = 0;
    int jobs = 0;
    uint64_t seed = 1;
    std::vector<std::string> settings;
    bool force = false;
  };
  auto args = std::make_shared<Args>();
  command->add_option("name", args->name, "Reproduction name")->required();
  command->add_option("--runs", args->runs, "Monte-Carlo runs (default: the reproduction's own)")
      ->check(WholeNumber(1, 100000));
  AddSeedOption(command, &args->seed, "First seed; run k uses seed + k");
  command
      ->add_option("--report", args->report,
                   "Report folder: created (an existing one only with --force)")
      ->check(OutputFolder())
      ->required();
  command->add_flag("--force", args->force,
                    "Replace an existing --report folder (a mavloc report)");
  command->add_option("--set", args->settings, "Setting key=value (repeatable)");
  command
      ->add_option(
          "--jobs", args->jobs,
          "Worker processes (every reproduction but euroc-imu-april; default: the core count). "
          "The numbers do not depend on it")
      ->check(WholeNumber(1, 1024));
  command->callback([args, exit_code] {
    const ReproDefinition* entry = FindRepro(args->name);
    if (!entry) {
      std::string known;
      for (const auto& e : ReproRegistry()) known += (known.empty() ? "" : ", ") + e.name;
      throw InputError("unknown reproduction '" + args->name + "' (known: " + known + ")");
    }
    ReproOptions options;
    if (args->runs > 0) options.runs = args->runs;
    options.seed = args->seed;
    options.settings = ParseKeyValues(args->settings, "--set");
    // Reproductions with a unit function run on the sweep machinery (evaluation/sweep/); the
    // others run in this process.
    if (entry->unit) {
      options.jobs = args->jobs > 0 ? args->jobs : AvailableCores();
      options.worker_argv = {SelfPath(), "sweep-worker", "--grid", "{grid}"};
    } else if (args->jobs > 1) {
      std::string with_units;
      for (const auto& e : ReproRegistry())
        if (e.unit) with_units += (with_units.empty() ? "" : ", ") + e.name;
      throw InputError("--jobs " + std::to_string(args->jobs) + ": repro " + args->name +
                       " runs in one process (--jobs applies to repro " + with_units + ")");
    }
    // Written whole into a fresh folder, then renamed into place (cli/output_folder.h).
    StagedFolder report(args->report, FolderKind::kReport, args->force);
    options.report_dir = report.path();
    *exit_code = RunRepro(*entry, options);
    const FigureOutcome figures = WriteReportFigures(report.path(), report.ForUser(report.path()));
    report.Commit();
    std::printf("report written to %s/\n%s\n", args->report.c_str(),
                report.ForUser(DescribeFigureOutcome(figures)).c_str());
  });
}

}  // namespace mavloc::cli
