// mavloc: offline evaluator for visual-inertial localization of micro aerial vehicles.
// Thin: parses options (CLI11) and calls the libraries.
#include <glog/logging.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <string>

#include "cli/commands.h"
#include "core/errors.h"
#include "core/huge_pages.h"
#include "core/input_file.h"
#include "core/interrupt.h"
#include "evaluation/report/provenance.h"
#include "evaluation/repro/repro.h"

int main(int argc, char** argv) {
  // 2 MiB pages for the heap (core/huge_pages.h): may re-execute the process, so first of all.
  mavloc::ReexecWithHugePages(argv);
  // SIGINT/SIGTERM: temporary outputs removed, exit 130/143 (core/interrupt.h). First, before
  // any library starts a thread, so that every thread inherits the blocked signals.
  mavloc::InstallInterruptHandler();
  // Ceres logs every rejected trust-region step ("Step failed to evaluate": a trial pose put a
  // laser spot behind its laser) as a warning; the smoother reports its own statistics, so only
  // Ceres' errors are printed unless MAVLOC_CERES_WARNINGS is set.
  FLAGS_logtostderr = true;
  FLAGS_minloglevel = std::getenv("MAVLOC_CERES_WARNINGS") ? google::GLOG_INFO : google::GLOG_ERROR;
  google::InitGoogleLogging(argv[0]);
  CLI::App app{
      "mavloc: evaluate visual-inertial localization of micro aerial vehicles on logged "
      "(EuRoC/ASL)\n"
      "or synthetic datasets, compare estimators, and reproduce the tables of four papers."};
  app.require_subcommand(1);
  app.set_help_all_flag("--help-all", "Print help for every command");
  int exit_code = 0;
  mavloc::RecordInvocation(argc, argv);  // the provenance of every report
  mavloc::RegisterReproUnitKinds();      // what `repro --jobs` and sweep workers run
  mavloc::cli::RegisterList(app, &exit_code);
  mavloc::cli::RegisterSimulate(app, &exit_code);
  mavloc::cli::RegisterRun(app, &exit_code);
  mavloc::cli::RegisterEval(app, &exit_code);
  mavloc::cli::RegisterConvert(app, &exit_code);
  mavloc::cli::RegisterCompare(app, &exit_code);
  mavloc::cli::RegisterRepro(app, &exit_code);
  mavloc::cli::RegisterObservability(app, &exit_code);
  mavloc::cli::RegisterDetectTags(app, &exit_code);
  mavloc::cli::RegisterObstacles(app, &exit_code);
  mavloc::cli::RegisterImportAprilgrid(app, &exit_code);
  mavloc::cli::RegisterFigures(app, &exit_code);
  mavloc::cli::RegisterImportTagslam(app, &exit_code);
  mavloc::cli::RegisterLog(app, &exit_code);
  mavloc::cli::RegisterSweep(app, &exit_code);
  mavloc::cli::RegisterMatrix(app, &exit_code);
  mavloc::cli::RegisterImuNoise(app, &exit_code);
  mavloc::cli::RegisterTrackFeatures(app, &exit_code);
  // An unknown first word is named in the message (CLI11 would only say a command is required).
  const auto subcommands = app.get_subcommands({});
  const bool known_command =
      argc > 1 && std::any_of(subcommands.begin(), subcommands.end(), [&](const CLI::App* command) {
        return command->check_name(argv[1]);
      });
  if (argc > 1 && argv[1][0] != '-' && !known_command) {
    std::string known;
    for (const auto* command : subcommands)
      known += (known.empty() ? "" : ", ") + command->get_name();
    std::fprintf(stderr, "mavloc: unknown command '%s' (commands: %s)\n",
                 mavloc::PrintableMessage(argv[1], 200).c_str(), known.c_str());
    return 2;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    // Unknown options, missing arguments, bad values: one line, exit code 2.
    std::fprintf(stderr, "mavloc: %s (see --help)\n", mavloc::PrintableMessage(e.what()).c_str());
    return 2;
  } catch (const mavloc::InputError& e) {
    // One readable line whatever the input held (binary garbage, a 10 MB field).
    std::fprintf(stderr, "mavloc: error: %s\n", mavloc::PrintableMessage(e.what()).c_str());
    return 2;
  } catch (const std::filesystem::filesystem_error& e) {
    // A path that cannot be walked (a loop of links, a folder gone mid-walk): the input's fault.
    std::fprintf(stderr, "mavloc: error: %s\n",
                 mavloc::PrintableMessage(mavloc::DescribeFilesystemError(e)).c_str());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "mavloc: internal error: %s\n",
                 mavloc::PrintableMessage(e.what()).c_str());
    return 1;
  }
  return exit_code;
}
