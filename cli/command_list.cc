// mavloc list: the scenarios, estimators and paper reproductions mavloc knows.
#include <cstdio>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "cli/commands.h"
#include "datasets/scenarios/scenario.h"
#include "evaluation/repro/repro.h"
#include "solver/estimator.h"

namespace mavloc::cli {

void RegisterList(CLI::App& app, int* exit_code) {
  auto* command = app.add_subcommand("list", "List the scenarios, estimators and reproductions");
  auto keys = std::make_shared<bool>(false);
  command->add_flag("--options", *keys,
                    "Also list each scenario's --set keys and each estimator's --option keys");
  command->callback([exit_code, keys] {
    const auto print_keys = [&](const char* flag, const std::set<std::string>& names,
                                const std::vector<std::string>& prefixes) {
      if (!*keys) return;
      std::string line;
      for (const auto& k : names) line += (line.empty() ? "" : ", ") + k;
      for (const auto& p : prefixes) line += (line.empty() ? "" : ", ") + p + "KEY";
      std::printf("  %-22s %s %s\n", "", flag, line.empty() ? "(none)" : line.c_str());
    };
    std::printf("Scenarios (mavloc simulate --scenario NAME):\n");
    for (const auto& e : ScenarioRegistry()) {
      std::printf("  %-22s %s%s\n", e.name.c_str(), e.description.c_str(),
                  e.name == DefaultScenarioName() ? " [default]" : "");
      print_keys("--set", e.settings, {});
    }
    std::printf("\nEstimators (mavloc run --estimator NAME):\n");
    for (const auto& e : EstimatorRegistry()) {
      std::printf("  %-22s %s\n", e.name.c_str(), e.description.c_str());
      print_keys("--option", e.options, e.option_prefixes);
    }
    std::printf("\nReproductions (mavloc repro NAME):\n");
    for (const auto& e : ReproRegistry())
      std::printf("  %-22s %s\n", e.name.c_str(), e.description.c_str());
    *exit_code = 0;
  });
}

}  // namespace mavloc::cli
