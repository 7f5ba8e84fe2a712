// Checks of command-line values, one place for every command. CLI11 runs a
// validator on the text before converting it and reports "--name: message", which main() prints
// as one line with exit code 2 before the command does anything.
//
// Numbers must be finite: CLI::PositiveNumber alone lets "nan" through (nan <= 0 is false) and
// CLI11 reads "-1" into an unsigned seed as 18446744073709551615, so mavloc's options use these.
#pragma once

#include <CLI/CLI.hpp>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "solver/estimator.h"

namespace mavloc::cli {

// A finite number (no nan, inf).
CLI::Validator FiniteNumber();
// A finite number > 0.
CLI::Validator PositiveFinite();
// A finite number in [min, max] (`unit` is appended to the bounds in the message, e.g. "s").
CLI::Validator FiniteRange(double min, double max, const std::string& unit = "");
// A finite number in (0, max].
CLI::Validator PositiveAtMost(double max, const std::string& unit = "");
// A whole number in [min, max] written in decimal digits (a leading '-' only when min < 0).
CLI::Validator WholeNumber(long long min, long long max);
// A seed: decimal digits only, 0 .. 2^64 - 1 (a sign, a fraction or an exponent is refused).
CLI::Validator SeedNumber();

// A file a command writes (--out FILE, --json FILE), checked before any work: a name (not empty,
// not ending in '/'), not an existing folder, in a folder that exists (unless the command creates
// it: `parent_must_exist` false).
CLI::Validator OutputFile(bool parent_must_exist = true);
// A folder a command writes (--out DIR, --report DIR): a name, not empty. The folder itself is
// checked by StagedFolder (cli/output_folder.h) before any work.
CLI::Validator OutputFolder();

// Adds `--seed` to a command with SeedNumber().
CLI::Option* AddSeedOption(CLI::App* command, uint64_t* seed, const std::string& description);
// Adds `--duration` for a simulated scenario: (0, kMaxScenarioDurationS] seconds.
CLI::Option* AddScenarioDurationOption(CLI::App* command, double* duration_s,
                                       const std::string& description);

// `--option` items for a run of the estimators `names`: "name:key=value" for one estimator,
// "key=value" for every estimator of the run that has the option (EstimatorEntry::options).
// Returns the options of each estimator. Throws InputError for a malformed item, a prefix that is
// not an estimator or not in `names`, an option the named estimator does not have, or a
// "key=value" that no estimator of the run has (each message lists the known names).
//
// The values are checked as well (CheckEstimatorOptionValues,
// evaluation/estimator_option_ranges.h), before anything runs.
std::map<std::string, EstimatorOptions> EstimatorOptionsFor(const std::vector<std::string>& items,
                                                            const std::vector<std::string>& names);

}  // namespace mavloc::cli
