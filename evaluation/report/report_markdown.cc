#include "evaluation/report/report_markdown.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>

namespace mavloc {
namespace {

constexpr double kRadToDeg = 180.0 / M_PI;

std::string EscapeCell(const std::string& text) {
  std::string escaped;
  for (const char c : text) {
    if (c == '|')
      escaped += "\\|";
    else if (c == '\n' || c == '\r')
      escaped += ' ';
    else
      escaped += c;
  }
  return escaped;
}

std::string Header(const std::string& name, const std::string& si_unit,
                   const std::string& preferred = "") {
  const std::string unit = DisplayUnitFor(si_unit, preferred).label;
  return unit.empty() ? name : name + " [" + unit + "]";
}

std::string Shown(double si_value, const std::string& si_unit, const std::string& preferred = "") {
  return TableNumber(si_value * DisplayUnitFor(si_unit, preferred).scale);
}

std::string CoverageCell(const EstimatorResult& e) {
  if (!e.coverage) return "-";
  const Coverage& c = *e.coverage;
  return fmt::format("{}/{} poses, {:.1f} of {:.1f} s ({:.0f} %)", c.pairs, c.estimate_poses,
                     c.overlap_s, c.estimate_span_s, 100.0 * c.Fraction());
}

// RMSE, mean and max of a metric's statistics (or its single value) in display units.
std::vector<std::string> StatisticsCells(const EstimatorResult& e, const std::string& metric) {
  const auto it = e.metrics.find(metric);
  if (it == e.metrics.end()) return {"-", "-", "-"};
  const Metric& m = it->second;
  if (m.statistics)
    return {Shown(m.statistics->rmse, m.unit), Shown(m.statistics->mean, m.unit),
            Shown(m.statistics->max, m.unit)};
  return {m.value ? Shown(*m.value, m.unit) : "-", "-", "-"};
}

std::string ResultsTable(const Report& report) {
  std::vector<std::string> header = {"estimator", "coverage"};
  for (const char* stat : {"RMSE", "mean", "max"})
    header.push_back(Header("ATE " + std::string(stat), "m"));
  for (const char* stat : {"RMSE", "mean", "max"})
    header.push_back(Header("rotation " + std::string(stat), "rad"));
  header.insert(header.end(), {"frames without pose", "rejected measurements", "runtime [s]"});
  std::vector<std::vector<std::string>> rows;
  for (const auto& e : report.estimators) {
    if (!e.ran) {
      std::vector<std::string> row = {e.name, "not run: " + e.skipped_reason};
      row.resize(header.size(), "-");
      rows.push_back(row);
      continue;
    }
    std::vector<std::string> row = {e.name + (e.is_reference ? " (reference)" : ""),
                                    CoverageCell(e)};
    for (const auto& cell : StatisticsCells(e, "ate_translation")) row.push_back(cell);
    for (const auto& cell : StatisticsCells(e, "ate_rotation")) row.push_back(cell);
    row.push_back(std::to_string(e.frames_without_pose));
    row.push_back(std::to_string(e.rejected_measurements));
    row.push_back(TableNumber(e.runtime_s));
    rows.push_back(row);
  }
  return MarkdownTableOf(header, rows);
}

// Estimators x quantities: the RMSE of each quantity's error (the metrics other than ATE).
std::string QuantityRmseTable(const Report& report) {
  std::vector<std::string> quantities;
  std::map<std::string, std::string> unit_of;
  for (const auto& e : report.estimators)
    for (const auto& [name, metric] : e.metrics) {
      if (name == "ate_translation" || name == "ate_rotation" || !metric.statistics) continue;
      if (unit_of.emplace(name, metric.unit).second) quantities.push_back(name);
    }
  if (quantities.empty()) return "";
  // The pose and velocity first, in the order people read them, then the others alphabetically.
  static const std::vector<std::string> kStandard = {"x",   "y",  "z",  "roll", "pitch",
                                                     "yaw", "vx", "vy", "vz"};
  std::stable_sort(quantities.begin(), quantities.end(), [](const auto& a, const auto& b) {
    const auto rank = [](const std::string& q) {
      return std::find(kStandard.begin(), kStandard.end(), q) - kStandard.begin();
    };
    return rank(a) < rank(b);
  });
  std::vector<std::string> header = {"estimator"};
  for (const auto& q : quantities) header.push_back(Header(q, unit_of[q]));
  std::vector<std::vector<std::string>> rows;
  for (const auto& e : report.estimators) {
    if (!e.ran || e.is_reference) continue;
    std::vector<std::string> row = {e.name};
    for (const auto& q : quantities) row.push_back(StatisticsCells(e, q)[0]);
    rows.push_back(row);
  }
  return "RMSE of each quantity's error:\n\n" + MarkdownTableOf(header, rows);
}

std::string ParameterTable(const Report& report) {
  std::vector<std::vector<std::string>> rows;
  for (const auto& e : report.estimators)
    for (const auto& [name, v] : e.parameters) {
      const DisplayUnit unit = DisplayUnitFor(v.unit);
      rows.push_back({e.name, name, TableNumber(v.value * unit.scale),
                      v.sigma ? TableNumber(*v.sigma * unit.scale) : "-", unit.label});
    }
  if (rows.empty()) return "";
  return "## Estimated calibration and other constants\n\n" +
         MarkdownTableOf({"estimator", "quantity", "value", "sigma", "unit"}, rows);
}

std::string TableCell(const nlohmann::json& cell, const ReportTable::Column& column) {
  if (cell.is_number()) return Shown(cell.get<double>(), column.unit, column.display_unit);
  if (cell.is_string()) return cell.get<std::string>();
  if (cell.is_null()) return "-";
  return cell.dump();
}

std::string RenderTable(const ReportTable& table) {
  std::vector<std::string> header;
  for (const auto& c : table.columns) header.push_back(Header(c.name, c.unit, c.display_unit));
  std::vector<std::vector<std::string>> rows;
  for (const auto& row : table.rows) {
    std::vector<std::string> cells;
    for (size_t k = 0; k < table.columns.size(); ++k)
      cells.push_back(k < row.size() ? TableCell(row[k], table.columns[k]) : "-");
    rows.push_back(cells);
  }
  return "### " + table.title + "\n\n" + MarkdownTableOf(header, rows);
}

std::string ProtocolLine(const Report& report) {
  if (!report.protocol) return "";
  const ReportProtocol& p = *report.protocol;
  std::string against = p.reference == "truth"
                            ? "the ground truth"
                            : "a reference that is an estimate, not a truth: the numbers are "
                              "differences, not errors";
  return fmt::format(
      "Compared with {}; alignment {}, association {} within {:g} s, time offset {:g} s; "
      "rotation errors are the angle of the rotation error.\n\n",
      against, p.alignment, p.association, p.max_dt_s, p.time_offset_s);
}

}  // namespace

DisplayUnit DisplayUnitFor(const std::string& si_unit, const std::string& preferred) {
  if (si_unit == "s" && preferred == "ms") return {"ms", 1e3};
  if (si_unit == "m" && preferred == "mm") return {"mm", 1e3};
  if (si_unit == "m" && preferred == "cm") return {"cm", 1e2};
  if (si_unit == "rad") return {"deg", kRadToDeg};
  if (si_unit == "rad/s") return {"deg/s", kRadToDeg};
  return {si_unit, 1.0};
}

std::string TableNumber(double value) {
  if (!std::isfinite(value)) return "-";
  const double magnitude = std::abs(value);
  if (magnitude != 0.0 && (magnitude < 1e-3 || magnitude >= 1e6))
    return fmt::format("{:.3e}", value);
  if (magnitude >= 100.0) return fmt::format("{:.1f}", value);
  return fmt::format("{:.4g}", value);
}

std::string MarkdownTableOf(const std::vector<std::string>& header,
                            const std::vector<std::vector<std::string>>& rows) {
  const auto append_row = [&](std::string& text, const std::vector<std::string>& cells) {
    text.push_back('|');
    for (size_t k = 0; k < header.size(); ++k) {
      text.push_back(' ');
      text.append(k < cells.size() ? EscapeCell(cells[k]) : std::string("-"));
      text.append(" |");
    }
    text.push_back('\n');
  };
  std::string text;
  append_row(text, header);
  text.push_back('|');
  for (size_t k = 0; k < header.size(); ++k) text.append(k == 0 ? " --- |" : " ---: |");
  text.push_back('\n');
  for (const auto& row : rows) append_row(text, row);
  return text;
}

std::string RenderResultTables(const Report& report) {
  std::string md;
  const bool has_trajectory_results = std::any_of(
      report.estimators.begin(), report.estimators.end(),
      [](const auto& e) { return !e.ran || e.metrics.count("ate_translation") || e.coverage; });
  if (has_trajectory_results) md += "## Results\n\n" + ResultsTable(report) + "\n";
  if (const std::string q = QuantityRmseTable(report); !q.empty()) md += q + "\n";
  std::vector<std::string> warnings = report.warnings;
  for (const auto& e : report.estimators)
    for (const auto& w : e.warnings) warnings.push_back(e.name + ": " + w);
  if (!warnings.empty()) {
    md += "Warnings:\n\n";
    for (const auto& w : warnings) md += "- " + w + "\n";
    md += "\n";
  }
  if (const std::string c = ParameterTable(report); !c.empty()) md += c + "\n";
  return md;
}

std::string RenderReportMarkdown(const Report& report) {
  std::string md = "# " + report.title + "\n\n";
  md += ProtocolLine(report);
  const auto sections = [&](bool before_tables) {
    for (const auto& section : report.sections)
      if (section.before_tables == before_tables)
        md +=
            (section.title.empty() ? "" : "## " + section.title + "\n\n") + section.markdown + "\n";
  };
  sections(true);
  md += RenderResultTables(report);
  for (const auto& table : report.tables) md += RenderTable(table) + "\n";
  sections(false);
  md += fmt::format("mavloc {}; the command, seeds and settings are in report.json (provenance).\n",
                    report.provenance.version);
  return md;
}

}  // namespace mavloc
