// Paper reproductions: `mavloc repro NAME [--runs N] [--seed S] --report DIR`. Each one writes a
// report folder whose report.json holds {"paper": ..., "tables": {"<table>": {...}}}, with the same
// per-estimator objects as `mavloc compare` and "paper": value beside a statistic wherever the
// paper gives one.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

namespace mavloc {

struct ReproOptions {
  std::optional<int> runs;  // Monte-Carlo runs (each reproduction has its default)
  uint64_t seed = 1;        // first seed; run k uses seed + k
  std::string report_dir;
  std::map<std::string, std::string> settings;  // `--set key=value`
  // Runs in `jobs` worker processes on the sweep machinery (evaluation/sweep/sweep_runner.h) when
  // the reproduction has a unit function and jobs > 1; worker_argv as SweepRunOptions'.
  int jobs = 1;
  std::vector<std::string> worker_argv;
};

struct ReproEntry {
  std::string name;
  std::string description;
  // Runs the reproduction and writes the report; returns a process exit code. Throws InputError
  // for bad options.
  std::function<int(const ReproOptions&)> run;
  // One Monte-Carlo run (scenario, seed) with the `--set` settings as JSON, for the sweep
  // machinery (`repro NAME --jobs N`, sweep workers); empty for reproductions that run in one
  // process only. The reproduction's report is made from these JSON results whatever the number
  // of jobs, so that --jobs 1 and --jobs N give the same numbers.
  std::function<nlohmann::json(const std::map<std::string, std::string>& settings,
                               const std::string& scenario, uint64_t seed)>
      unit;
};

const std::vector<ReproEntry>& ReproRegistry();  // evaluation/repro/repro_registry.cc

// Throws InputError "--set KEY=VALUE: repro NAME has no setting 'KEY' (known: ...)" for the first
// setting not in `known` (evaluation/repro/repro_registry.cc).
void RejectUnknownReproSettings(const std::string& repro,
                                const std::map<std::string, std::string>& settings,
                                const std::vector<std::string>& known);
const ReproEntry* FindRepro(const std::string& name);

// Registers every reproduction that runs as units as a sweep unit kind of its name
// (evaluation/sweep/unit_kinds.h), for `repro NAME --jobs N` and sweep workers; called once at
// program start.
void RegisterReproUnitKinds();

}  // namespace mavloc
