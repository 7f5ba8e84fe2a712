#include "evaluation/sweep/sweep_unit.h"

#include <cmath>

#include "core/errors.h"
#include "datasets/scenarios/scenario.h"
#include "evaluation/comparison.h"
#include "evaluation/sweep/unit_kinds.h"
#include "solver/estimator.h"

namespace mavloc {

namespace {

std::pair<std::string, std::string> SplitKeyValue(const std::string& item) {
  const auto eq = item.find('=');
  if (eq == std::string::npos || eq == 0)
    throw InputError("--option '" + item + "': expected [estimator:]key=value");
  return {item.substr(0, eq), item.substr(eq + 1)};
}

}  // namespace

EstimatorOptions SweepEstimatorOptions(const std::string& estimator,
                                       const std::vector<std::string>& items) {
  const EstimatorEntry* entry = FindEstimator(estimator);
  EstimatorOptions specific;
  std::vector<std::pair<std::string, std::string>> global;
  for (const auto& item : items) {
    const auto colon = item.find(':');
    const auto eq = item.find('=');
    if (colon != std::string::npos && (eq == std::string::npos || colon < eq)) {
      const auto [key, value] = SplitKeyValue(item.substr(colon + 1));
      if (item.substr(0, colon) == estimator) specific.Set(key, value);
    } else {
      global.push_back(SplitKeyValue(item));
    }
  }
  for (const auto& [key, value] : global)
    if (entry && entry->HasOption(key) && !specific.Has(key)) specific.Set(key, value);
  // A sweep's parallelism is across units (--jobs, shards): an estimator with its own thread pool
  // (the smoother's Ceres solve, 2 threads by default) runs on one thread unless the grid says
  // otherwise, so that N jobs use N cores without oversubscribing them, and every unit gives the
  // same numbers whatever --jobs is.
  if (entry && entry->HasOption("threads") && !specific.Has("threads"))
    specific.Set("threads", "1");
  return specific;
}

namespace {

void AddMetric(nlohmann::json& row, const std::string& name, double value,
               const std::string& unit) {
  if (!std::isfinite(value)) return;
  row["metrics"][name] = value;
  row["units"][name] = unit;
}

}  // namespace

nlohmann::json RunSweepUnit(const SweepGrid& grid, size_t index) {
  const SweepUnit unit = SweepUnitAt(grid, index);
  if (!grid.repro.empty()) {  // one run of a reproduction (`repro NAME --jobs N`)
    const SweepUnitKind* kind = FindSweepUnitKind(grid.repro);
    if (!kind)
      throw InputError("sweep: '" + grid.repro + "' is not a reproduction that runs as units");
    nlohmann::json result = (*kind)(grid.repro_settings, unit.scenario, unit.seed);
    result["index"] = index;
    return result;
  }
  ScenarioOptions scenario_options;
  scenario_options.seed = unit.seed;
  scenario_options.duration_s = grid.duration_s;
  scenario_options.settings = unit.settings;
  const ScenarioEntry* scenario = FindScenario(unit.scenario);
  if (!scenario) throw InputError("unknown scenario '" + unit.scenario + "'");
  const Dataset dataset = scenario->generate(scenario_options);

  EvaluationOptions evaluation_options;
  evaluation_options.align = *ParseAlignmentMode(grid.align);
  evaluation_options.max_dt_s = grid.max_dt_s;

  nlohmann::json result;
  result["index"] = index;
  result["scenario"] = unit.scenario;
  result["seed"] = unit.seed;
  result["settings"] = unit.settings;
  result["estimators"] = nlohmann::json::array();
  for (const auto& name : grid.estimators) {
    const EstimatorEvaluation evaluation = RunAndEvaluate(
        name, SweepEstimatorOptions(name, grid.options), dataset, evaluation_options);
    nlohmann::json row;
    row["name"] = name;
    row["ran"] = evaluation.ran;
    if (!evaluation.ran) {
      row["skipped"] = evaluation.skipped_reason;
      result["estimators"].push_back(row);
      continue;
    }
    row["metrics"] = nlohmann::json::object();
    row["units"] = nlohmann::json::object();
    if (evaluation.ate) {
      AddMetric(row, "ate_rmse", evaluation.ate->translation_m.rmse, "m");
      AddMetric(row, "ate_rotation_rmse", evaluation.ate->rotation_rad.rmse, "rad");
    }
    // The per-quantity numbers exactly as `compare` reports them (SI: angles in radians).
    const nlohmann::json reported = EvaluationToJson(evaluation);
    if (reported.contains("quantities"))
      for (const auto& [quantity, stats] : reported["quantities"].items()) {
        const std::string unit_name = stats.value("unit", "");
        if (stats["mean_abs"].is_number())
          AddMetric(row, quantity + ".mean_abs", stats["mean_abs"].get<double>(), unit_name);
        if (stats["rmse"].is_number())
          AddMetric(row, quantity + ".rmse", stats["rmse"].get<double>(), unit_name);
      }
    AddMetric(row, "failures", evaluation.estimate.FailureCount(), "frames");
    result["estimators"].push_back(row);
  }
  return result;
}

}  // namespace mavloc
