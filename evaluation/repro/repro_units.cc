#include "evaluation/repro/repro_units.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "core/errors.h"
#include "core/progress.h"
#include "evaluation/report/csv_field.h"
#include "evaluation/report/report_folder.h"
#include "evaluation/sweep/sweep_grid.h"
#include "evaluation/sweep/sweep_runner.h"

namespace mavloc {

ReportTable ReproTable(const std::string& name, const std::string& title,
                       const std::vector<std::string>& columns) {
  ReportTable table{name, title, {}, {}};
  for (const auto& spec : columns) {
    const auto open = spec.rfind(" [");
    if (open != std::string::npos && spec.back() == ']')
      table.columns.push_back(
          {spec.substr(0, open), spec.substr(open + 2, spec.size() - open - 3)});
    else
      table.columns.push_back({spec, ""});
  }
  return table;
}

std::string ReproTableCsv(const ReportTable& table) {
  std::string csv;
  for (size_t k = 0; k < table.columns.size(); ++k) {
    const auto& column = table.columns[k];
    csv += (k ? "," : "") +
           CsvField(column.unit.empty() ? column.name : column.name + " [" + column.unit + "]");
  }
  csv += "\n";
  for (const auto& row : table.rows) {
    for (size_t k = 0; k < row.size(); ++k) {
      const nlohmann::json& cell = row[k];
      std::string text;
      if (cell.is_string())
        text = CsvField(cell.get<std::string>());
      else if (cell.is_number_float())
        text = std::isfinite(cell.get<double>()) ? fmt::format("{}", cell.get<double>()) : "";
      else if (!cell.is_null())
        text = cell.dump();
      csv += (k ? "," : "") + text;
    }
    csv += "\n";
  }
  return csv;
}

std::string ReproRuns::Seeds() const {
  return fmt::format("{}..{}", first_seed, first_seed + static_cast<uint64_t>(runs) - 1);
}

namespace {

// The units x seeds of a definition with units: unit u, seed first + k (k < its runs) is the
// sweep grid's index u * runs + k. Run in options.jobs sweep workers (the registered unit
// function) when jobs > 1, otherwise here with one progress line per run; every result is parsed
// from its JSON text either way, and handed to the summary per unit in seed order.
Report RunAndSummarize(const ReproDefinition& repro, const ReproOptions& options, int runs) {
  const ReproPlan plan = repro.plan(options.settings, options.seed);
  SweepGrid grid;
  grid.repro = repro.name;
  grid.repro_settings = plan.settings;
  for (int k = 0; k < runs; ++k) grid.seeds.push_back(options.seed + static_cast<uint64_t>(k));
  std::vector<size_t> indices;
  for (size_t u = 0; u < plan.units.size(); ++u) {
    grid.scenarios.push_back(plan.units[u].name);
    for (int k = 0; k < std::min(runs, plan.units[u].max_runs); ++k)
      indices.push_back(u * static_cast<size_t>(runs) + static_cast<size_t>(k));
  }
  std::vector<nlohmann::json> results;
  if (options.jobs > 1) {
    SweepRunOptions run_options;
    run_options.jobs = options.jobs;
    run_options.worker_argv = options.worker_argv;
    results = RunSweepUnits(grid, indices, run_options);
  } else {
    for (const size_t index : indices) {
      const ReproUnit& unit = plan.units[index / static_cast<size_t>(runs)];
      const uint64_t seed = grid.seeds[index % static_cast<size_t>(runs)];
      ReportProgress("repro " + repro.name,
                     fmt::format("{} run {}/{} (seed {})", unit.name, index % runs + 1,
                                 std::min(runs, unit.max_runs), seed));
      results.push_back(nlohmann::json::parse(repro.unit(plan.settings, unit.name, seed).dump()));
    }
  }
  ReproRuns in{plan.settings, runs, options.seed, {}};
  in.results.resize(plan.units.size());
  for (size_t i = 0; i < results.size(); ++i)
    in.results[indices[i] / static_cast<size_t>(runs)].push_back(std::move(results[i]));
  return repro.summarize(in);
}

}  // namespace

int RunRepro(const ReproDefinition& repro, const ReproOptions& options) {
  if (options.runs.value_or(1) < 1) throw InputError("", 0, "--runs", "must be >= 1");
  if (options.jobs < 1) throw InputError("", 0, "--jobs", "must be >= 1");
  const int runs = repro.single ? 1 : options.runs.value_or(repro.default_runs);
  Report report = repro.single ? repro.single(options) : RunAndSummarize(repro, options, runs);
  report.kind = "repro";
  if (report.title.empty()) report.title = "mavloc repro " + repro.name;
  if (!repro.paper.empty()) report.details["paper"] = repro.paper;
  Provenance& provenance = report.provenance;
  provenance.runs = runs;
  provenance.jobs = options.jobs;
  provenance.settings = options.settings;
  if (!repro.single)
    for (int k = 0; k < runs; ++k)
      provenance.seeds.push_back(options.seed + static_cast<uint64_t>(k));
  WriteReport(options.report_dir, std::move(report));
  return 0;
}

}  // namespace mavloc
