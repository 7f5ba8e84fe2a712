// report.md of a Report (report.h): the tables for people. Angles are shown in degrees, everything
// else in the SI unit report.json holds; every column states its unit; RMSE is the headline with
// mean and max beside it; the coverage of each estimate is a column, with a warning below the
// table when the truth covers less than kLowCoverageFraction of an estimate.
#pragma once

#include <string>
#include <vector>

#include "evaluation/report/report.h"

namespace mavloc {

// One Markdown table. Cells are escaped ('|' -> '\|', line breaks -> spaces), so every row has as
// many cells as the header.
std::string MarkdownTableOf(const std::vector<std::string>& header,
                            const std::vector<std::vector<std::string>>& rows);

// The unit a table shows for an SI unit, and the factor from SI to it: "rad" -> "deg" by default;
// `preferred` chooses a smaller unit of the same quantity ("ms" for "s", "mm" or "cm" for "m",
// "deg" for "rad"), and is ignored when it does not measure the same quantity.
struct DisplayUnit {
  std::string label;
  double scale = 1.0;
};
DisplayUnit DisplayUnitFor(const std::string& si_unit, const std::string& preferred = "");

// A number for a table: 4 significant digits (fixed for ordinary magnitudes), "-" when not finite.
std::string TableNumber(double value);

// The estimators' tables (results with coverage, per-quantity RMSE, warnings, estimated
// calibration and other constants): what
// a command prints on the terminal.
std::string RenderResultTables(const Report& report);

// Title, protocol, RenderResultTables, the report's tables and sections.
std::string RenderReportMarkdown(const Report& report);

}  // namespace mavloc
