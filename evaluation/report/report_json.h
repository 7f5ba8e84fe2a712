// report.json of a Report (report.h), as schemas/report.schema.json describes it. A number that is
// not finite is written as null (JSON has no NaN), never as a string or a huge value.
#pragma once

#include <nlohmann/json.hpp>

#include "evaluation/report/report.h"

namespace mavloc {

nlohmann::json ReportToJson(const Report& report);
nlohmann::json StatisticsToJson(const ErrorStatistics& statistics);
// The number, or null when it is not finite.
nlohmann::json FiniteOrNull(double value);

}  // namespace mavloc
