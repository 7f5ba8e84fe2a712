#include "evaluation/sweep/sweep_report.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "core/atomic_file.h"
#include "core/errors.h"
#include "core/interrupt.h"
#include "evaluation/report/csv_field.h"
#include "evaluation/report/provenance.h"
#include "evaluation/report/report_folder.h"
#include "evaluation/report/report_markdown.h"

namespace mavloc {

namespace {

struct MetricSamples {
  std::string unit;
  std::vector<double> values;  // in unit order
  std::vector<size_t> units;   // the unit of each value
};

struct SweepCell {
  std::string scenario, settings, estimator;
  int runs = 0, ran = 0;
  std::vector<size_t> ran_units;             // the units where the estimator ran
  std::vector<std::string> skipped_reasons;  // distinct, first seen first
  std::map<std::string, MetricSamples> metrics;
};

struct Statistics {
  double mean = 0.0, std = 0.0, min = 0.0, median = 0.0, max = 0.0;
};

Statistics Summarize(std::vector<double> values) {
  Statistics s;
  const double n = static_cast<double>(values.size());
  double sum = 0.0;
  for (const double v : values) sum += v;  // unit order: the same sum however units were run
  s.mean = sum / n;
  double squares = 0.0;
  for (const double v : values) squares += (v - s.mean) * (v - s.mean);
  s.std = values.size() > 1 ? std::sqrt(squares / (n - 1.0)) : 0.0;
  std::sort(values.begin(), values.end());
  s.min = values.front();
  s.max = values.back();
  const size_t mid = values.size() / 2;
  s.median = values.size() % 2 == 1 ? values[mid] : 0.5 * (values[mid - 1] + values[mid]);
  return s;
}

std::string SectionName(const SweepCell& cell) {
  return cell.scenario + (cell.settings.empty() ? "" : " (" + cell.settings + ")");
}

// The units where the cell's estimator ran without a value of `metric`.
std::vector<size_t> MissingUnits(const SweepCell& cell, const std::string& metric) {
  const std::vector<size_t>& have = cell.metrics.at(metric).units;
  std::vector<size_t> missing;
  for (const size_t unit : cell.ran_units)
    if (std::find(have.begin(), have.end(), unit) == have.end()) missing.push_back(unit);
  return missing;
}

// A metric with fewer values than the runs where the estimator ran: a unit without it (a NaN left
// out, or a result that lost it), so its statistics are over fewer seeds than the cell's.
std::vector<std::string> ShortCellWarnings(const SweepCell& cell) {
  std::vector<std::string> warnings;
  for (const auto& [metric, samples] : cell.metrics)
    if (static_cast<int>(samples.values.size()) < cell.ran)
      warnings.push_back(
          fmt::format("{}: {}: {} has {} value(s) for the {} runs where it ran "
                      "(missing in unit {}): its statistics are over fewer seeds",
                      SectionName(cell), cell.estimator, metric, samples.values.size(), cell.ran,
                      fmt::join(MissingUnits(cell, metric), ", ")));
  return warnings;
}

nlohmann::json CellJson(const SweepCell& cell) {
  nlohmann::json j = {{"scenario", cell.scenario},
                      {"settings", cell.settings},
                      {"estimator", cell.estimator},
                      {"runs", cell.runs},
                      {"ran", cell.ran}};
  if (!cell.skipped_reasons.empty()) j["skipped"] = cell.skipped_reasons;
  j["metrics"] = nlohmann::json::object();
  for (const auto& [metric, samples] : cell.metrics) {
    const Statistics s = Summarize(samples.values);
    j["metrics"][metric] = {
        {"unit", samples.unit}, {"n", samples.values.size()}, {"mean", s.mean}, {"std", s.std},
        {"min", s.min},         {"median", s.median},         {"max", s.max}};
  }
  return j;
}

// The metrics of one unit, as a table's title names them.
std::string MetricGroupName(const std::string& unit) {
  if (unit == "rad") return "angles";
  if (unit == "rad/s") return "angular rates";
  if (unit.empty() || unit == "frames") return "counts";
  return "metrics in " + unit;
}

// Per scenario and settings combination, one table per unit (every number of a column in one
// unit): a row per estimator and metric with n, mean, sample std, min, median and max over the
// seeds where the estimator ran.
std::vector<ReportTable> CellTables(const std::vector<SweepCell>& cells) {
  std::vector<ReportTable> tables;
  std::map<std::string, size_t> table_of;  // section \n unit -> index
  for (const SweepCell& cell : cells) {
    const std::string section = SectionName(cell);
    for (const auto& [metric, samples] : cell.metrics) {
      auto [it, inserted] = table_of.try_emplace(section + "\n" + samples.unit, tables.size());
      if (inserted) {
        ReportTable t;
        t.name = fmt::format("cells_{}", tables.size() + 1);
        t.title = fmt::format("{}: {}, statistics over the seeds", section,
                              MetricGroupName(samples.unit));
        const std::string unit = samples.unit == "frames" ? "" : samples.unit;
        const std::string shown = unit == "m" ? "mm" : "";  // sweeps compare mm-level errors
        for (const char* name : {"estimator", "metric", "n"}) t.columns.push_back({name, ""});
        for (const char* name : {"mean", "std", "min", "median", "max"})
          t.columns.push_back({name, unit, shown});
        tables.push_back(std::move(t));
      }
      const Statistics s = Summarize(samples.values);
      tables[it->second].rows.push_back(
          {cell.estimator, metric, samples.values.size(), s.mean, s.std, s.min, s.median, s.max});
    }
  }
  return tables;
}

std::map<std::string, std::string> SweepSettings(const SweepGrid& grid,
                                                 const std::string& fingerprint) {
  std::map<std::string, std::string> settings = {
      {"fingerprint", fingerprint},
      {"estimators", fmt::format("{}", fmt::join(grid.estimators, ","))}};
  if (grid.duration_s) settings["duration_s"] = fmt::format("{}", *grid.duration_s);
  if (!grid.options.empty()) settings["options"] = fmt::format("{}", fmt::join(grid.options, " "));
  if (!grid.repro.empty()) settings["repro"] = grid.repro;
  return settings;
}

ReportProtocol SweepProtocol(const SweepGrid& grid) {
  ReportProtocol protocol;
  protocol.alignment = grid.align;
  protocol.max_dt_s = grid.max_dt_s;
  return protocol;
}

std::string GridText(const SweepGrid& grid, const std::string& fingerprint, size_t units) {
  std::string text = fmt::format(
      "{} units = {} scenario(s) x {} settings combination(s) x {} seed(s); estimators: {}.\n\n",
      units, grid.scenarios.size(), units / (grid.scenarios.size() * grid.seeds.size()),
      grid.seeds.size(), fmt::join(grid.estimators, ", "));
  text += fmt::format("Grid fingerprint `{}`; seeds {}..{} ({} listed)", fingerprint,
                      grid.seeds.front(), grid.seeds.back(), grid.seeds.size());
  if (grid.duration_s) text += fmt::format("; duration {} s", *grid.duration_s);
  if (!grid.options.empty())
    text += fmt::format("; estimator options `{}`", fmt::join(grid.options, "`, `"));
  return text +
         ".\n\nPer cell (scenario, settings, estimator): statistics over the seeds where the "
         "estimator ran; std is the sample standard deviation. Per-run numbers (SI): runs.csv.\n";
}

}  // namespace

std::map<std::string, std::string> BuildSweepReport(const SweepGrid& grid,
                                                    const std::string& fingerprint,
                                                    const std::vector<nlohmann::json>& units,
                                                    std::vector<std::string>* warnings) {
  if (units.size() != SweepUnitCount(grid))
    throw InputError(fmt::format("sweep report: {} unit results for a grid of {} units",
                                 units.size(), SweepUnitCount(grid)));
  std::vector<SweepCell> cells;
  std::map<std::string, size_t> cell_index;  // key: scenario \n settings \n estimator
  std::string csv = "unit,scenario,settings,seed,estimator,ran,metric,unit,value\n";
  for (size_t k = 0; k < units.size(); ++k) {
    const nlohmann::json& u = units[k];
    if (u.at("index").get<size_t>() != k)
      throw InputError(fmt::format("sweep report: unit {} out of order", k));
    const std::string scenario = u.at("scenario").get<std::string>();
    const std::string settings =
        SettingsLabel(u.at("settings").get<std::map<std::string, std::string>>());
    const std::string prefix = fmt::format("{},{},{},{}", k, CsvField(scenario), CsvField(settings),
                                           u.at("seed").get<uint64_t>());
    for (const auto& row : u.at("estimators")) {
      const std::string estimator = row.at("name").get<std::string>();
      const std::string key = scenario + "\n" + settings + "\n" + estimator;
      auto [it, inserted] = cell_index.try_emplace(key, cells.size());
      if (inserted) {
        SweepCell cell;
        cell.scenario = scenario;
        cell.settings = settings;
        cell.estimator = estimator;
        cells.push_back(std::move(cell));
      }
      SweepCell& cell = cells[it->second];
      ++cell.runs;
      if (!row.at("ran").get<bool>()) {
        const std::string reason = row.value("skipped", "");
        if (std::find(cell.skipped_reasons.begin(), cell.skipped_reasons.end(), reason) ==
            cell.skipped_reasons.end())
          cell.skipped_reasons.push_back(reason);
        csv += fmt::format("{},{},0,,,\n", prefix, CsvField(estimator));
        continue;
      }
      ++cell.ran;
      cell.ran_units.push_back(k);
      for (const auto& [metric, value] : row.at("metrics").items()) {
        const std::string unit = row.at("units").value(metric, "");
        const double v = value.get<double>();
        auto& samples = cell.metrics[metric];
        samples.unit = unit;
        samples.values.push_back(v);
        samples.units.push_back(k);
        csv += fmt::format("{},{},1,{},{},{}\n", prefix, CsvField(estimator), CsvField(metric),
                           CsvField(unit), v);
      }
    }
  }

  Report report;
  report.kind = "sweep";
  report.title = "mavloc sweep";
  report.provenance.input = fmt::format("{}", fmt::join(grid.scenarios, ", "));
  report.provenance.seeds = grid.seeds;
  report.provenance.runs = static_cast<int>(units.size());
  report.provenance.settings = SweepSettings(grid, fingerprint);
  report.protocol = SweepProtocol(grid);
  report.sections.push_back({"Grid", GridText(grid, fingerprint, units.size()), true});
  report.details["sweep"] = {{"grid", SweepGridToJson(grid)},
                             {"fingerprint", fingerprint},
                             {"units", units.size()},
                             {"seeds_per_cell", grid.seeds.size()}};
  report.details["cells"] = nlohmann::json::array();
  for (const SweepCell& cell : cells) {
    report.details["cells"].push_back(CellJson(cell));
    if (cell.ran < cell.runs)
      report.warnings.push_back(fmt::format("{}: {} did not run in {} of {} seeds: {}",
                                            SectionName(cell), cell.estimator, cell.runs - cell.ran,
                                            cell.runs, fmt::join(cell.skipped_reasons, "; ")));
    for (const std::string& warning : ShortCellWarnings(cell)) report.warnings.push_back(warning);
  }
  if (warnings) *warnings = report.warnings;
  report.tables = CellTables(cells);
  report.details["runs"] = units;
  report.files["runs.csv"] = csv;
  // One report for a serial run and a merge of shards: the files but report.json's provenance
  // (the command line, the elapsed time) are the same bytes.
  std::map<std::string, std::string> files = report.files;
  files["report.json"] = ReportJsonText(report);
  report.provenance = WithInvocation(report.provenance);
  files["report.md"] = RenderReportMarkdown(report);
  return files;
}

void WriteSweepReport(const std::string& folder, const std::map<std::string, std::string>& files) {
  std::error_code error;
  CreateOutputDirectories(folder, error);
  if (error) throw InputError(folder, 0, "", "cannot create the report folder: " + error.message());
  for (const auto& [name, contents] : files) WriteFileAtomically(folder + "/" + name, contents);
}

}  // namespace mavloc
