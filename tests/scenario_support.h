// Simulating a registered scenario in a test (header only: only the suites that link the
// scenarios include it; tests/test_support links no scenario code).
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <utility>

#include "core/dataset.h"
#include "datasets/scenarios/scenario.h"

namespace mavloc::testing {

// `scenario` with the seed, the duration and `--set` settings; an empty Dataset when the name is
// not registered.
inline Dataset Simulate(const std::string& scenario, uint64_t seed, double duration_s,
                        std::map<std::string, std::string> settings = {}) {
  const ScenarioEntry* entry = FindScenario(scenario);
  if (!entry) return Dataset{};
  ScenarioOptions options;
  options.seed = seed;
  options.duration_s = duration_s;
  options.settings = std::move(settings);
  return entry->generate(options);
}

}  // namespace mavloc::testing
