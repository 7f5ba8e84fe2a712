// Helpers shared by the mavloc commands: option parsing and loading a dataset from a folder or a
// scenario.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "core/dataset.h"
#include "core/key_values.h"  // SplitList
#include "datasets/scenarios/scenario.h"

namespace mavloc::cli {

// The running mavloc executable (/proc/self/exe), for the sweep workers it starts.
std::string SelfPath();

// Simulates a registered scenario in memory; throws InputError for an unknown name.
Dataset SimulateScenario(const std::string& name, const ScenarioOptions& options);

}  // namespace mavloc::cli
