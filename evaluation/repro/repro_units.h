// The sweep-machinery side of a reproduction that runs as units (ReproEntry::unit): the grid of
// unit names x seeds, run on `options.jobs` sweep workers.
#pragma once

#include <cstddef>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "evaluation/repro/repro.h"

namespace mavloc {

// Runs the units `indices` of the grid unit_names x seeds options.seed .. options.seed + runs - 1
// (index = name * runs + k) of reproduction `repro` with options.settings, on options.jobs workers
// (options.worker_argv); returns their JSON results in the order of `indices`.
std::vector<nlohmann::json> RunReproUnitsInWorkers(const std::string& repro,
                                                   const ReproOptions& options,
                                                   const std::vector<std::string>& unit_names,
                                                   int runs, const std::vector<size_t>& indices);

}  // namespace mavloc
