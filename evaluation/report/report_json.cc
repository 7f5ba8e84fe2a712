#include "evaluation/report/report_json.h"

#include <cmath>

namespace mavloc {
namespace {

nlohmann::json MetricToJson(const Metric& metric) {
  nlohmann::json j = {{"unit", metric.unit}};
  if (metric.value) j["value"] = FiniteOrNull(*metric.value);
  if (metric.statistics) j["statistics"] = StatisticsToJson(*metric.statistics);
  return j;
}

nlohmann::json CoverageToJson(const Coverage& coverage) {
  return {{"pairs", coverage.pairs},
          {"estimate_poses", coverage.estimate_poses},
          {"overlap_s", FiniteOrNull(coverage.overlap_s)},
          {"estimate_span_s", FiniteOrNull(coverage.estimate_span_s)},
          {"fraction", FiniteOrNull(coverage.Fraction())}};
}

nlohmann::json EstimatorToJson(const EstimatorResult& e) {
  nlohmann::json j = {{"name", e.name}, {"ran", e.ran}};
  if (!e.ran) {
    j["skipped_reason"] = e.skipped_reason;
    return j;
  }
  j["is_reference"] = e.is_reference;
  j["coverage"] = e.coverage ? CoverageToJson(*e.coverage) : nlohmann::json();
  j["metrics"] = nlohmann::json::object();
  for (const auto& [name, metric] : e.metrics) j["metrics"][name] = MetricToJson(metric);
  j["parameters"] = nlohmann::json::object();
  for (const auto& [name, v] : e.parameters)
    j["parameters"][name] = {{"value", FiniteOrNull(v.value)},
                             {"sigma", v.sigma ? FiniteOrNull(*v.sigma) : nlohmann::json()},
                             {"unit", v.unit}};
  j["frames_without_pose"] = e.frames_without_pose;
  j["rejected_measurements"] = e.rejected_measurements;
  j["failures"] = e.failures;
  j["runtime_s"] = FiniteOrNull(e.runtime_s);
  j["warnings"] = e.warnings;
  return j;
}

nlohmann::json TableToJson(const ReportTable& table) {
  nlohmann::json columns = nlohmann::json::array();
  for (const auto& c : table.columns) {
    nlohmann::json column = {{"name", c.name}, {"unit", c.unit}};
    if (!c.display_unit.empty()) column["display_unit"] = c.display_unit;
    columns.push_back(column);
  }
  nlohmann::json rows = nlohmann::json::array();
  for (const auto& row : table.rows) {
    nlohmann::json cells = nlohmann::json::array();
    for (const auto& cell : row)
      cells.push_back(cell.is_number_float() ? FiniteOrNull(cell.get<double>()) : cell);
    rows.push_back(cells);
  }
  return {{"name", table.name}, {"title", table.title}, {"columns", columns}, {"rows", rows}};
}

}  // namespace

nlohmann::json FiniteOrNull(double value) {
  return std::isfinite(value) ? nlohmann::json(value) : nlohmann::json();
}

nlohmann::json StatisticsToJson(const ErrorStatistics& s) {
  return {{"count", s.count},
          {"rmse", FiniteOrNull(s.rmse)},
          {"mean", FiniteOrNull(s.mean)},
          {"median", FiniteOrNull(s.median)},
          {"std", FiniteOrNull(s.std)},
          {"min", FiniteOrNull(s.min)},
          {"max", FiniteOrNull(s.max)}};
}

nlohmann::json ReportToJson(const Report& report) {
  const Provenance& p = report.provenance;
  nlohmann::json j;
  j["schema"] = kReportSchema;
  j["report_kind"] = report.kind;
  j["title"] = report.title;
  j["provenance"] = {{"command", p.command},   {"version", p.version},
                     {"input", p.input},       {"seeds", p.seeds},
                     {"runs", p.runs},         {"jobs", p.jobs},
                     {"settings", p.settings}, {"elapsed_s", FiniteOrNull(p.elapsed_s)}};
  if (report.protocol) {
    const ReportProtocol& q = *report.protocol;
    j["protocol"] = {{"reference", q.reference},         {"alignment", q.alignment},
                     {"association", q.association},     {"max_dt_s", q.max_dt_s},
                     {"time_offset_s", q.time_offset_s}, {"pose_relation", q.pose_relation}};
  } else {
    j["protocol"] = nullptr;
  }
  j["estimators"] = nlohmann::json::array();
  for (const auto& e : report.estimators) j["estimators"].push_back(EstimatorToJson(e));
  j["tables"] = nlohmann::json::array();
  for (const auto& t : report.tables) j["tables"].push_back(TableToJson(t));
  j["sections"] = nlohmann::json::array();
  for (const auto& s : report.sections)
    j["sections"].push_back({{"title", s.title}, {"markdown", s.markdown}});
  j["warnings"] = report.warnings;
  nlohmann::json files = nlohmann::json::array();
  for (const auto& [name, contents] : report.files) files.push_back(name);
  j["files"] = files;
  j["details"] = report.details.is_object() ? report.details : nlohmann::json::object();
  return j;
}

}  // namespace mavloc
