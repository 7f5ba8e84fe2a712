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
#include "evaluation/report_writer.h"

namespace mavloc {

namespace {

struct MetricSamples {
  std::string unit;
  std::vector<double> values;  // in unit order
};

struct SweepCell {
  std::string scenario, settings, estimator;
  int runs = 0, ran = 0;
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

std::string Number(double value) { return fmt::format("{:.6g}", value); }

}  // namespace

std::map<std::string, std::string> BuildSweepReport(const SweepGrid& grid,
                                                    const std::string& fingerprint,
                                                    const std::vector<nlohmann::json>& units) {
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
      for (const auto& [metric, value] : row.at("metrics").items()) {
        const std::string unit = row.at("units").value(metric, "");
        const double v = value.get<double>();
        auto& samples = cell.metrics[metric];
        samples.unit = unit;
        samples.values.push_back(v);
        csv += fmt::format("{},{},1,{},{},{}\n", prefix, CsvField(estimator), CsvField(metric),
                           CsvField(unit), v);
      }
    }
  }

  nlohmann::json json;
  json["report_kind"] = "sweep";
  json["sweep"] = {{"grid", SweepGridToJson(grid)},
                   {"fingerprint", fingerprint},
                   {"units", units.size()},
                   {"seeds_per_cell", grid.seeds.size()}};
  json["cells"] = nlohmann::json::array();
  std::string markdown = "# mavloc sweep\n\n";
  markdown += fmt::format(
      "{} units = {} scenario(s) x {} settings combination(s) x {} seed(s); estimators: {}.\n\n",
      units.size(), grid.scenarios.size(),
      units.size() / (grid.scenarios.size() * grid.seeds.size()), grid.seeds.size(),
      fmt::join(grid.estimators, ", "));
  markdown += fmt::format("Grid fingerprint `{}`; seeds {}..{} ({} listed); ATE alignment `{}`",
                          fingerprint, grid.seeds.front(), grid.seeds.back(), grid.seeds.size(),
                          grid.align);
  if (grid.duration_s) markdown += fmt::format("; duration {} s", *grid.duration_s);
  if (!grid.options.empty())
    markdown += fmt::format("; estimator options `{}`", fmt::join(grid.options, "`, `"));
  markdown +=
      ".\n\nPer cell (scenario, settings, estimator): statistics over the seeds where the "
      "estimator ran; std is the sample standard deviation; angles in degrees. Per-run numbers: "
      "runs.csv.\n";
  std::string current_section;
  std::vector<std::vector<std::string>> rows;
  auto flush = [&] {
    if (rows.empty()) return;
    const std::vector<std::string> header = {"estimator", "metric", "unit",   "n",  "mean",
                                             "std",       "min",    "median", "max"};
    markdown.push_back('\n');
    markdown.append(MarkdownTable(header, rows));
    rows.clear();
  };
  for (const SweepCell& cell : cells) {
    const std::string section =
        cell.scenario + (cell.settings.empty() ? "" : " (" + cell.settings + ")");
    if (section != current_section) {
      flush();
      markdown += "\n## " + section + "\n";
      current_section = section;
    }
    nlohmann::json j = {{"scenario", cell.scenario},
                        {"settings", cell.settings},
                        {"estimator", cell.estimator},
                        {"runs", cell.runs},
                        {"ran", cell.ran}};
    if (!cell.skipped_reasons.empty()) j["skipped"] = cell.skipped_reasons;
    j["metrics"] = nlohmann::json::object();
    if (cell.ran < cell.runs)
      rows.push_back(
          {cell.estimator, fmt::format("did not run in {} of {}", cell.runs - cell.ran, cell.runs),
           "", "", "", "", "", "", fmt::format("{}", fmt::join(cell.skipped_reasons, "; "))});
    for (const auto& [metric, samples] : cell.metrics) {
      const Statistics s = Summarize(samples.values);
      j["metrics"][metric] = {
          {"unit", samples.unit}, {"n", samples.values.size()}, {"mean", s.mean}, {"std", s.std},
          {"min", s.min},         {"median", s.median},         {"max", s.max}};
      rows.push_back({cell.estimator, metric, samples.unit, std::to_string(samples.values.size()),
                      Number(s.mean), Number(s.std), Number(s.min), Number(s.median),
                      Number(s.max)});
    }
    json["cells"].push_back(j);
  }
  flush();
  json["runs"] = units;
  // One report model and writer for every command (evaluation/report/): the cells and runs are
  // the sweep's details, the tables above its section.
  ReportFiles files;
  files.kind = "sweep";
  files.markdown = markdown;
  files.json = json;
  Report report = ReportFromFiles(files);
  report.provenance.seeds = grid.seeds;
  report.provenance.runs = static_cast<int>(units.size());
  const std::string json_text = ReportJsonText(report);
  report.provenance = WithInvocation(report.provenance);
  return {
      {"report.md", RenderReportMarkdown(report)}, {"report.json", json_text}, {"runs.csv", csv}};
}

void WriteSweepReport(const std::string& folder, const std::map<std::string, std::string>& files) {
  std::error_code error;
  CreateOutputDirectories(folder, error);
  if (error) throw InputError(folder, 0, "", "cannot create the report folder: " + error.message());
  for (const auto& [name, contents] : files) WriteFileAtomically(folder + "/" + name, contents);
}

}  // namespace mavloc
