// Reading report.json (schemas/report.schema.json) in tests: an estimator's entry by name and its
// headline numbers.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

namespace mavloc::testing {

// The entry of `name` in report["estimators"]; null when there is none.
inline nlohmann::json ReportEstimator(const nlohmann::json& report, const std::string& name) {
  if (report.contains("estimators") && report["estimators"].is_array())
    for (const auto& e : report["estimators"])
      if (e.value("name", "") == name) return e;
  return nullptr;
}

// The statistics of a metric of an estimator entry ("ate_translation", "roll", ...); null when
// absent.
inline nlohmann::json MetricStatistics(const nlohmann::json& estimator, const std::string& metric) {
  if (!estimator.is_object() || !estimator.contains("metrics") ||
      !estimator["metrics"].contains(metric) ||
      !estimator["metrics"][metric].contains("statistics"))
    return nullptr;
  return estimator["metrics"][metric]["statistics"];
}

}  // namespace mavloc::testing
