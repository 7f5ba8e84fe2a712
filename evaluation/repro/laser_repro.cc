#include "evaluation/repro/laser_repro.h"
#include "evaluation/estimator_option_ranges.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>

#include "core/errors.h"
#include "core/key_values.h"
#include "core/numbers.h"
#include "core/rotation.h"
#include "datasets/scenarios/euroc_laser.h"
#include "datasets/scenarios/laser_plane.h"
#include "evaluation/exact_json.h"
#include "evaluation/json_number.h"
#include "evaluation/quantity_errors.h"
#include "evaluation/repro/repro_units.h"
#include "solver/estimator.h"

namespace mavloc {

namespace {

constexpr int kLaserDefaultRuns = 20;
const std::vector<std::string> kQuantities = {"alpha", "pitch", "roll", "v_o", "d"};

struct QuantityResult {
  double convergence_s = kNaN;  // NaN: never within the band until the end
  double mae_after = kNaN;      // SI
  double final_error = kNaN;    // SI, signed
  double mae_all = kNaN;        // SI, over the whole run
  double mae_late = kNaN;       // SI, over the last quarter of the run
};

struct RunResult {
  uint64_t seed = 0;
  bool converged = false;
  double duration_s = 0.0;
  std::map<std::string, QuantityResult> quantities;
  int failures = 0;
  std::string note;  // when the run could not be evaluated
};

struct Bands {
  std::map<std::string, double> si;  // quantity -> band in SI units
};

QuantityResult Analyse(const QuantityErrorSeries& series, TimeNs t0, double band) {
  QuantityResult r;
  if (series.error.empty()) return r;
  size_t first_inside = series.error.size();
  for (size_t i = series.error.size(); i-- > 0;) {
    if (std::abs(series.error[i]) > band) break;
    first_inside = i;
  }
  double sum_all = 0.0;
  for (const double e : series.error) sum_all += std::abs(e);
  r.mae_all = sum_all / static_cast<double>(series.error.size());
  r.final_error = series.error.back();
  const TimeNs t_late = t0 + (series.t_ns.back() - t0) * 3 / 4;
  double sum_late = 0.0;
  int n_late = 0;
  for (size_t i = 0; i < series.error.size(); ++i) {
    if (series.t_ns[i] < t_late) continue;
    sum_late += std::abs(series.error[i]);
    ++n_late;
  }
  if (n_late > 0) r.mae_late = sum_late / n_late;
  if (first_inside < series.error.size()) {
    r.convergence_s = NsToSeconds(series.t_ns[first_inside] - t0);
    double sum = 0.0;
    for (size_t i = first_inside; i < series.error.size(); ++i) sum += std::abs(series.error[i]);
    r.mae_after = sum / static_cast<double>(series.error.size() - first_inside);
  }
  return r;
}

// The modes are compared with the truth interpolated at the filter's output stamps, within 3 ms
// (a third of the 10 Hz spot interval), without alignment.
ReportProtocol LaserProtocol() {
  ReportProtocol protocol;
  protocol.association = "interpolate";
  protocol.max_dt_s = 0.003;
  protocol.pose_relation = "quantities";
  return protocol;
}

RunResult EvaluateRun(const Dataset& dataset, const EstimatorOptions& estimator_options,
                      const Bands& bands, uint64_t seed) {
  RunResult run;
  run.seed = seed;
  auto estimator = FindEstimator("laser-ekf")->create(estimator_options);
  const Applicability applies = estimator->AppliesTo(dataset);
  if (!applies.applies) {
    run.note = "laser-ekf does not apply: " + applies.reason;
    return run;
  }
  const Estimate estimate = estimator->Run(dataset);
  run.failures = estimate.FailureCount();
  const auto errors = ComputeQuantityErrors(estimate.quantities, dataset.truth_quantities,
                                            LaserProtocol().max_dt_s, kQuantities);
  const TimeNs t0 = estimate.quantities.t_ns.front();
  run.duration_s = NsToSeconds(estimate.quantities.t_ns.back() - t0);
  run.converged = true;
  for (const auto& name : kQuantities) {
    const auto it = std::find_if(errors.begin(), errors.end(),
                                 [&](const QuantityErrorSeries& s) { return s.name == name; });
    if (it == errors.end()) {
      run.converged = false;
      continue;
    }
    run.quantities[name] = Analyse(*it, t0, bands.si.at(name));
    if (!(run.quantities[name].mae_late <= bands.si.at(name))) run.converged = false;
  }
  return run;
}

bool IsAngle(const std::string& q) { return q == "alpha" || q == "roll" || q == "pitch"; }
std::string LaserUnit(const std::string& q) {
  if (IsAngle(q)) return "rad";
  return q == "d" ? "m" : "m/s";
}

double Max(const std::vector<double>& v) {
  double m = kNaN;
  for (const double x : v)
    if (std::isfinite(x)) m = std::isfinite(m) ? std::max(m, x) : x;
  return m;
}

std::string PaperClaim(const std::string& table, const std::string& quantity) {
  if (table == "simulated, with bias" && quantity == "alpha") return "final error < 1 deg (5.1.3)";
  if (table.rfind("euroc", 0) == 0) return "converges in < 0.5 s (5.2)";
  return "estimated, converged (figs. 4-8)";
}

struct TableResult {
  std::string name;
  std::string group, key;  // in details: tables.<group>.<key>
  std::vector<RunResult> runs;
};

int AlphaBelow1Deg(const TableResult& table) {
  int count = 0;
  for (const auto& run : table.runs) {
    if (run.quantities.count("alpha") && std::abs(run.quantities.at("alpha").final_error) < kDeg)
      ++count;
  }
  return count;
}

// A table's statistics in SI units, as details holds them and the report's tables show them.
nlohmann::json TableJson(const TableResult& table) {
  nlohmann::json j;
  int converged = 0;
  for (const auto& run : table.runs) converged += run.converged ? 1 : 0;
  j["runs"] = table.runs.size();
  j["runs_converged"] = converged;
  j["runs_alpha_final_below_1deg"] = AlphaBelow1Deg(table);
  for (const auto& q : kQuantities) {
    std::vector<double> tc, mae, fin, fin_abs, late;
    for (const auto& run : table.runs) {
      if (!run.quantities.count(q)) continue;
      const auto& r = run.quantities.at(q);
      tc.push_back(r.convergence_s);
      mae.push_back(r.mae_after);
      fin.push_back(r.final_error);
      fin_abs.push_back(std::abs(r.final_error));
      late.push_back(r.mae_late);
    }
    j["quantities"][q] = {{"unit", LaserUnit(q)},
                          {"mean_abs_error_after_convergence", MeanOfFinite(mae)},
                          {"mean_abs_final_error", MeanOfFinite(fin_abs)},
                          {"max_abs_final_error", Max(fin_abs)},
                          {"mean_convergence_time_s", MeanOfFinite(tc)},
                          {"max_convergence_time_s", Max(tc)},
                          {"per_run_final_error", fin},
                          {"per_run_convergence_time_s", tc},
                          {"per_run_mae_last_quarter", late},
                          {"paper", PaperClaim(table.name, q)}};
  }
  nlohmann::json seeds = nlohmann::json::array();
  for (const auto& run : table.runs) seeds.push_back(run.seed);
  j["seeds"] = seeds;
  return j;
}

// Per table (its TableJson): mean |error| after convergence and |final error| (mean, max) of
// every quantity, and the paper's claim in a row of its own.
ReportTable LaserErrorTable(const std::vector<std::pair<std::string, nlohmann::json>>& tables) {
  ReportTable out = ReproTable(
      "errors", "Errors after convergence and at the end of the run, beside the paper's claims",
      {"table", "statistic"});
  for (const auto& q : kQuantities) out.columns.push_back({q, LaserUnit(q)});
  for (const auto& [name, json] : tables) {
    for (const auto& [statistic, key] :
         {std::pair{"MAE after convergence", "mean_abs_error_after_convergence"},
          {"mean |final error|", "mean_abs_final_error"},
          {"max |final error|", "max_abs_final_error"},
          {"paper", "paper"}}) {
      std::vector<nlohmann::json> row = {name, statistic};
      for (const auto& q : kQuantities) row.push_back(json["quantities"][q][key]);
      out.rows.push_back(std::move(row));
    }
  }
  return out;
}

// Per table (its TableJson): runs, converged runs, runs with |final alpha error| < 1 deg (the
// paper's 5.1.3), and the mean and max convergence time of every quantity.
ReportTable LaserConvergenceTable(
    const std::vector<std::pair<std::string, nlohmann::json>>& tables) {
  ReportTable out =
      ReproTable("convergence", "Convergence: runs converged and convergence times t_c",
                 {"table", "runs", "converged", "|final alpha error| < 1 deg"});
  for (const auto& q : kQuantities)
    out.columns.insert(out.columns.end(), {{q + " mean t_c", "s"}, {q + " max t_c", "s"}});
  for (const auto& [name, json] : tables) {
    std::vector<nlohmann::json> row = {name, json["runs"], json["runs_converged"],
                                       json["runs_alpha_final_below_1deg"]};
    for (const auto& q : kQuantities)
      row.insert(row.end(), {json["quantities"][q]["mean_convergence_time_s"],
                             json["quantities"][q]["max_convergence_time_s"]});
    out.rows.push_back(std::move(row));
  }
  return out;
}

// Every run of one table: final error, late MAE and t_c of every quantity.
ReportTable LaserRunsTable(const TableResult& table) {
  ReportTable out =
      ReproTable("runs_" + table.key, table.name + ": every run", {"seed", "converged"});
  for (const auto& q : kQuantities)
    out.columns.insert(
        out.columns.end(),
        {{q + " final", LaserUnit(q)}, {q + " late MAE", LaserUnit(q)}, {q + " t_c", "s"}});
  for (const auto& run : table.runs) {
    std::vector<nlohmann::json> row = {
        run.seed, run.note.empty() ? (run.converged ? "yes" : "no") : run.note};
    for (const auto& q : kQuantities) {
      const QuantityResult r = run.quantities.count(q) ? run.quantities.at(q) : QuantityResult{};
      row.insert(row.end(), {r.final_error, r.mae_late, r.convergence_s});
    }
    out.rows.push_back(std::move(row));
  }
  return out;
}

void AppendCsv(const TableResult& table, std::string* csv) {
  for (const auto& run : table.runs) {
    for (const auto& q : kQuantities) {
      const QuantityResult r = run.quantities.count(q) ? run.quantities.at(q) : QuantityResult{};
      // The table name holds a comma ("simulated, no bias"): quoted as RFC 4180 says.
      *csv += fmt::format("\"{}\",{},{},{},{},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g}\n", table.name,
                          run.seed, run.converged ? 1 : 0, q, LaserUnit(q), r.final_error,
                          r.mae_after, r.mae_late, r.mae_all, r.convergence_s);
    }
  }
}

// A run's result as exact JSON (a unit's result on the sweep machinery; evaluation/exact_json.h).
constexpr auto ExactFields(std::type_identity<QuantityResult>) {
  return std::make_tuple(ExactField("convergence_s", &QuantityResult::convergence_s),
                         ExactField("mae_after", &QuantityResult::mae_after),
                         ExactField("final_error", &QuantityResult::final_error),
                         ExactField("mae_all", &QuantityResult::mae_all),
                         ExactField("mae_late", &QuantityResult::mae_late));
}
constexpr auto ExactFields(std::type_identity<RunResult>) {
  return std::make_tuple(
      ExactField("seed", &RunResult::seed), ExactField("converged", &RunResult::converged),
      ExactField("duration_s", &RunResult::duration_s),
      ExactField("quantities", &RunResult::quantities),
      ExactField("failures", &RunResult::failures), ExactField("note", &RunResult::note));
}

// The `--set` settings, parsed the same way in the report's process and in every sweep worker.
struct LaserSettings {
  std::map<std::string, std::string> ekf;  // "ekf.KEY=VALUE": laser-ekf options
  double duration_s = 60.0;
  int euroc_runs = 5;
  bool with_euroc = true;
  std::string data;
  Bands bands;
};

LaserSettings ParseLaserSettings(const std::map<std::string, std::string>& settings) {
  static const std::set<std::string> kKnown = {"duration_s",   "euroc_runs",     "euroc",
                                               "data",         "band_alpha_deg", "band_angle_deg",
                                               "band_v_o_m_s", "band_d_m"};
  LaserSettings out;
  for (const auto& [key, value] : settings) {
    if (key.rfind("ekf.", 0) == 0) {
      out.ekf[key.substr(4)] = value;
      continue;
    }
    if (!kKnown.count(key)) {
      std::string known;
      for (const auto& k : kKnown) known += (known.empty() ? "" : ", ") + k;
      throw InputError(fmt::format("repro laser: unknown setting '{}' (known: {})", key, known));
    }
  }
  // ekf.KEY are laser-ekf's options: their keys and values checked before any unit runs.
  CheckEstimatorOptionValues(*FindEstimator("laser-ekf"), EstimatorOptions(out.ekf));
  out.duration_s = GetDoubleSetting(settings, "duration_s", 60.0);
  out.euroc_runs = GetIntSetting(settings, "euroc_runs", 5);
  out.with_euroc = GetBoolSetting(settings, "euroc", true);
  out.data = GetStringSetting(settings, "data", "");
  out.bands.si["alpha"] = GetDoubleSetting(settings, "band_alpha_deg", 2.0) * kDeg;
  out.bands.si["roll"] = out.bands.si["pitch"] =
      GetDoubleSetting(settings, "band_angle_deg", 2.0) * kDeg;
  out.bands.si["v_o"] = GetDoubleSetting(settings, "band_v_o_m_s", 0.1);
  out.bands.si["d"] = GetDoubleSetting(settings, "band_d_m", 0.1);
  if (!(out.duration_s > 0.0 && out.duration_s <= kMaxScenarioDurationS))
    throw InputError(fmt::format("--set duration_s={}: outside (0, {}] s (kMaxScenarioDurationS)",
                                 out.duration_s, kMaxScenarioDurationS));
  return out;
}

// The units' names: one per table of simulated runs, one for the three EuRoC tables (which share
// the dataset of a seed).
constexpr const char* kNoBiasUnit = "laser-plane";
constexpr const char* kBiasUnit = "laser-plane-bias";
constexpr const char* kEurocUnit = "euroc-laser";

// One unit: {"runs": [RunResult, ...]} (one run; three for euroc-laser: raw, bias-corrected and
// ground-truth IMU) and, for euroc-laser, the distance range of the data.
nlohmann::json LaserUnitResult(const ReproSettings& raw, const std::string& unit, uint64_t seed) {
  const LaserSettings settings = ParseLaserSettings(raw);
  nlohmann::json runs = nlohmann::json::array();
  ScenarioOptions scenario;
  scenario.seed = seed;
  EstimatorOptions raw_options(settings.ekf);
  raw_options.Set("init_seed", std::to_string(seed));
  if (unit == kNoBiasUnit || unit == kBiasUnit) {
    scenario.duration_s = settings.duration_s;
    scenario.settings["bias"] = unit == kBiasUnit ? "true" : "false";
    runs.push_back(
        ToExactJson(EvaluateRun(GenerateLaserPlane(scenario), raw_options, settings.bands, seed)));
    return {{"runs", runs}};
  }
  if (unit != kEurocUnit) throw InputError("repro laser: no unit '" + unit + "'");
  if (!settings.data.empty()) scenario.settings["data"] = settings.data;
  const Dataset dataset = GenerateEurocLaser(scenario);
  EstimatorOptions corrected_options = raw_options;
  corrected_options.Set("bias_from_ground_truth", "true");
  runs.push_back(ToExactJson(EvaluateRun(dataset, raw_options, settings.bands, seed)));
  runs.push_back(ToExactJson(EvaluateRun(dataset, corrected_options, settings.bands, seed)));
  scenario.settings["imu"] = "from_ground_truth";
  runs.push_back(
      ToExactJson(EvaluateRun(GenerateEurocLaser(scenario), raw_options, settings.bands, seed)));
  return {{"runs", runs}, {"distance_range_m", dataset.scenario_info.at("distance_range_m")}};
}

// Units: (laser-plane, seed), (laser-plane-bias, seed) for every seed, (euroc-laser, seed) for the
// first euroc_runs seeds.
ReproPlan PlanLaser(const ReproSettings& settings, uint64_t) {
  const LaserSettings parsed = ParseLaserSettings(settings);
  ReproPlan plan{{{kNoBiasUnit}, {kBiasUnit}}, settings};
  if (parsed.with_euroc) plan.units.push_back({kEurocUnit, parsed.euroc_runs});
  return plan;
}

std::string LaserSetup(const LaserSettings& settings, const ReproRuns& runs,
                       const std::string& euroc_note, size_t euroc_runs) {
  const Bands& bands = settings.bands;
  std::string md = fmt::format(
      "Martinelli & Troiani, *Vision-Aided Inertial Navigation Using Virtual Features*, INRIA "
      "RR-7906, 2012, section 5. Estimator `laser-ekf` (EKF on m = [m1..m4, g_z], eq. 9-11, "
      "appendix C), started 10-20 % off the true modes (5.1.3).\n\n"
      "- simulated: scenario `laser-plane` ({} s, plane at 22.5 deg, L = 0.3 m, spot at 10 Hz "
      "with 1 deg noise, IMU 100 Hz with 1 deg/s and 0.01 m/s^2), seeds {}; with bias: "
      "0.03 deg/s and 0.03 m/s^2 on every axis.\n",
      settings.duration_s, runs.Seeds());
  if (settings.with_euroc) {
    md += fmt::format(
        "- euroc: scenario `euroc-laser` (real EuRoC V1_01_easy IMU and full ground truth; the "
        "ground truth is T_W_B of the IMU frame; the spot is simulated for a virtual down-looking "
        "camera at the IMU origin, z_C = -x_B; distance to the plane {} m), {} seeds of spot noise "
        "and initial error; 'bias-corrected' subtracts the ASL ground truth's bias estimate "
        "(a pre-calibration); 'IMU from ground truth' replaces the IMU by a bias-free one "
        "derived from the ground truth (rates from attitude differences, accelerations from "
        "second differences over +-50 ms) to separate the IMU's biases from the trajectory's "
        "excitation. The raw IMU of V1_01_easy has biases of about 0.55 m/s^2 (accelerometer y) "
        "and 4.4 deg/s (gyro z), and the ASL estimate leaves a drift of about +-0.3 deg/s, which "
        "the paper's filter (no bias states) cannot model.\n",
        euroc_note, euroc_runs);
  } else {
    md += "- euroc: skipped (euroc=false).\n";
  }
  md += fmt::format(
      "\nConvergence time t_c: the first time after which |error| stays within the band until "
      "the end (alpha {} deg, roll/pitch {} deg, v_o {} m/s, d {} m); MAE after convergence: "
      "mean |error| over t >= t_c; a run converged when every quantity's mean |error| over the "
      "last quarter of the run (late MAE) is within its band.\n",
      bands.si.at("alpha") / kDeg, bands.si.at("roll") / kDeg, bands.si.at("v_o"),
      bands.si.at("d"));
  return md;
}

Report SummarizeLaser(const ReproRuns& runs) {
  const LaserSettings settings = ParseLaserSettings(runs.settings);
  std::vector<TableResult> tables = {{"simulated, no bias", "simulated", "no_bias", {}},
                                     {"simulated, with bias", "simulated", "with_bias", {}}};
  if (settings.with_euroc)
    tables.insert(tables.end(),
                  {{"euroc, raw IMU", "euroc", "raw_imu", {}},
                   {"euroc, IMU bias-corrected", "euroc", "bias_corrected", {}},
                   {"euroc, IMU from ground truth", "euroc", "imu_from_ground_truth", {}}});
  std::string euroc_note;
  for (size_t u = 0; u < runs.results.size(); ++u) {
    for (const auto& result : runs.results[u]) {
      const nlohmann::json& unit_runs = result.at("runs");
      for (size_t r = 0; r < unit_runs.size(); ++r)
        tables[u == 2 ? 2 + r : u].runs.push_back(FromExactJson<RunResult>(unit_runs[r]));
      if (u == 2 && euroc_note.empty()) euroc_note = result.at("distance_range_m");
    }
  }

  Report report;
  report.title = "mavloc repro laser";
  report.provenance.input = settings.with_euroc ? "laser-plane, euroc-laser" : "laser-plane";
  report.protocol = LaserProtocol();
  std::string csv =
      "table,seed,converged,quantity,unit,final_error,mae_after_convergence,mae_last_quarter,"
      "mae_all,convergence_time_s\n";
  nlohmann::json json_tables;
  std::vector<std::pair<std::string, nlohmann::json>> statistics;
  for (const auto& table : tables) {
    statistics.emplace_back(table.name, TableJson(table));
    AppendCsv(table, &csv);
    json_tables[table.group][table.key] = statistics.back().second;
  }
  report.tables = {LaserErrorTable(statistics), LaserConvergenceTable(statistics)};
  for (const auto& table : tables) report.tables.push_back(LaserRunsTable(table));
  report.sections.push_back(
      {"Setup", LaserSetup(settings, runs, euroc_note,
                           settings.with_euroc ? runs.results.at(2).size() : 0)});
  report.sections.back().before_tables = true;
  report.files["runs.csv"] = csv;
  const Bands& bands = settings.bands;
  // The convergence bands in SI units (the definitions are in the setup section).
  report.details = {{"bands",
                     {{"alpha_rad", bands.si.at("alpha")},
                      {"roll_pitch_rad", bands.si.at("roll")},
                      {"v_o_m_s", bands.si.at("v_o")},
                      {"d_m", bands.si.at("d")}}},
                    {"tables", json_tables}};
  return report;
}

}  // namespace

ReproDefinition LaserRepro() {
  return {
      .name = "laser",
      .description = "laser-spot paper 5.1 (laser-plane, with/without bias) and 5.2 (euroc-laser)",
      .paper =
          "Martinelli & Troiani, Vision-Aided Inertial Navigation Using Virtual Features, "
          "INRIA RR-7906, 2012, section 5",
      .default_runs = kLaserDefaultRuns,
      .plan = PlanLaser,
      .unit = LaserUnitResult,
      .summarize = SummarizeLaser};
}

}  // namespace mavloc
