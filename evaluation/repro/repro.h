// Paper reproductions: `mavloc repro NAME [--runs N] [--seed S] --report DIR`. A reproduction is a
// definition: its paper, a plan (the `--set` settings -> the units it runs), a function that runs
// one unit for one seed and returns JSON, and a summary that turns the units' results into a
// Report (evaluation/report/report.h: tables in SI units, prose sections, per-run `details`). One
// runner (RunRepro, defined in repro_units.cc) owns the units x seeds loop, --jobs, progress and
// the report's provenance, and writes the report with the one report writer.
#pragma once

#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "evaluation/report/report.h"

namespace mavloc {

using ReproSettings = std::map<std::string, std::string>;

struct ReproOptions {
  std::optional<int> runs;  // Monte-Carlo runs (each reproduction has its default)
  uint64_t seed = 1;        // first seed; run k uses seed + k
  std::string report_dir;
  ReproSettings settings;  // `--set key=value`
  // Runs in `jobs` worker processes on the sweep machinery (evaluation/sweep/sweep_runner.h) when
  // the reproduction has a unit function and jobs > 1; worker_argv as SweepRunOptions'.
  int jobs = 1;
  std::vector<std::string> worker_argv;
};

// One unit of a plan (a configuration or a scenario), run for the seeds seed + k,
// k < min(runs, max_runs).
struct ReproUnit {
  std::string name;
  int max_runs = std::numeric_limits<int>::max();
};

// What the `--set` settings determine before anything runs.
struct ReproPlan {
  std::vector<ReproUnit> units;
  // The settings every unit receives: the `--set` settings and whatever the plan fixes.
  ReproSettings settings;
};

// The units' results, as a summary receives them.
struct ReproRuns {
  ReproSettings settings;  // the plan's
  int runs = 1;            // runs of a unit without max_runs
  uint64_t first_seed = 1;
  // Per unit of the plan (in its order), one result per seed in seed order.
  std::vector<std::vector<nlohmann::json>> results;
  std::string Seeds() const;  // "first..last"
};

struct ReproDefinition {
  std::string name{};
  std::string description{};
  std::string paper{};  // the citation, details' "paper" (empty: mavloc's own study)
  int default_runs = 1;
  // The units the settings ask for; throws InputError for bad settings.
  std::function<ReproPlan(const ReproSettings& settings, uint64_t first_seed)> plan{};
  // One unit for one seed, with the plan's settings (here or in a sweep worker): JSON of sums,
  // not means, so that runs combine exactly whatever the number of jobs.
  std::function<nlohmann::json(const ReproSettings& settings, const std::string& unit,
                               uint64_t seed)>
      unit{};
  // The report from every unit's results: title, tables (SI), sections, details, files. The
  // runner fills kind and provenance.
  std::function<Report(const ReproRuns& runs)> summarize{};
  // A reproduction that is one run on one input, not a set of units (no plan, unit, summarize):
  // its report, made in this process.
  std::function<Report(const ReproOptions&)> single{};
};

const std::vector<ReproDefinition>& ReproRegistry();  // evaluation/repro/repro_registry.cc
const ReproDefinition* FindRepro(const std::string& name);

// Runs a reproduction and writes its report to options.report_dir (repro_units.cc); returns the
// exit code. Throws InputError for bad options or settings.
int RunRepro(const ReproDefinition& repro, const ReproOptions& options);

// Throws InputError "--set KEY=VALUE: repro NAME has no setting 'KEY' (known: ...)" for the first
// setting not in `known` (evaluation/repro/repro_registry.cc).
void RejectUnknownReproSettings(const std::string& repro, const ReproSettings& settings,
                                const std::vector<std::string>& known);

// Registers every reproduction that runs as units as a sweep unit kind of its name
// (evaluation/sweep/unit_kinds.h), for `repro NAME --jobs N` and sweep workers; called once at
// program start.
void RegisterReproUnitKinds();

}  // namespace mavloc
