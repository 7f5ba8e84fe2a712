// mavloc repro NAME: reproduce a paper's tables (see `mavloc list`), with figures and report.html.
#include <cstdio>

#include "cli/commands.h"
#include "core/errors.h"
#include "evaluation/report_figures.h"
#include "evaluation/repro/repro.h"

namespace mavloc::cli {

void RegisterRepro(CLI::App& app, int* exit_code) {
  auto* command = app.add_subcommand("repro", "Reproduce a paper's tables (names: `mavloc list`)");
  struct Args {
    std::string name, report;
    int runs = 0;
    uint64_t seed = 1;
    std::vector<std::string> settings;
  };
  auto args = std::make_shared<Args>();
  command->add_option("name", args->name, "Reproduction name")->required();
  command->add_option("--runs", args->runs, "Monte-Carlo runs (default: the reproduction's own)")
      ->check(CLI::PositiveNumber);
  command->add_option("--seed", args->seed, "First seed; run k uses seed + k")
      ->capture_default_str();
  command->add_option("--report", args->report, "Report folder (created)")->required();
  command->add_option("--set", args->settings, "Setting key=value (repeatable)");
  command->callback([args, exit_code] {
    const ReproEntry* entry = FindRepro(args->name);
    if (!entry) {
      std::string known;
      for (const auto& e : ReproRegistry()) known += (known.empty() ? "" : ", ") + e.name;
      throw InputError("unknown reproduction '" + args->name + "' (known: " + known + ")");
    }
    ReproOptions options;
    if (args->runs > 0) options.runs = args->runs;
    options.seed = args->seed;
    options.report_dir = args->report;
    options.settings = ParseKeyValues(args->settings, "--set");
    *exit_code = entry->run(options);
    std::printf("%s\n", DescribeFigureOutcome(WriteReportFigures(options.report_dir)).c_str());
  });
}

}  // namespace mavloc::cli
