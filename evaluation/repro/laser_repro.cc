#include "evaluation/repro/laser_repro.h"

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
#include "evaluation/report_writer.h"
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
double Scale(const std::string& q) { return IsAngle(q) ? 1.0 / kDeg : 1.0; }
std::string LaserUnit(const std::string& q) {
  if (IsAngle(q)) return "deg";
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

nlohmann::json TableJson(const TableResult& table) {
  nlohmann::json j;
  int converged = 0;
  for (const auto& run : table.runs) converged += run.converged ? 1 : 0;
  j["runs"] = table.runs.size();
  j["runs_converged"] = converged;
  j["runs_alpha_final_below_1deg"] = AlphaBelow1Deg(table);
  for (const auto& q : kQuantities) {
    std::vector<double> tc, mae, fin, fin_abs;
    for (const auto& run : table.runs) {
      if (!run.quantities.count(q)) continue;
      const auto& r = run.quantities.at(q);
      tc.push_back(r.convergence_s);
      mae.push_back(r.mae_after * Scale(q));
      fin.push_back(r.final_error * Scale(q));
      fin_abs.push_back(std::abs(r.final_error) * Scale(q));
    }
    nlohmann::json qj;
    qj["unit"] = LaserUnit(q);
    qj["mean_abs_error_after_convergence"] = MeanOfFinite(mae);
    qj["mean_abs_final_error"] = MeanOfFinite(fin_abs);
    qj["max_abs_final_error"] = Max(fin_abs);
    qj["mean_convergence_time_s"] = MeanOfFinite(tc);
    qj["max_convergence_time_s"] = Max(tc);
    qj["per_run_final_error"] = fin;
    qj["per_run_convergence_time_s"] = tc;
    std::vector<double> late;
    for (const auto& run : table.runs)
      if (run.quantities.count(q)) late.push_back(run.quantities.at(q).mae_late * Scale(q));
    qj["per_run_mae_last_quarter"] = late;
    qj["paper"] = PaperClaim(table.name, q);
    j["quantities"][q] = qj;
  }
  nlohmann::json seeds = nlohmann::json::array();
  for (const auto& run : table.runs) seeds.push_back(run.seed);
  j["seeds"] = seeds;
  return j;
}

std::string SummaryMarkdown(const TableResult& table) {
  int converged = 0;
  for (const auto& run : table.runs) converged += run.converged ? 1 : 0;
  std::string md =
      fmt::format("### {} ({} runs, {} converged; |final alpha error| < 1 deg in {})\n\n",
                  table.name, table.runs.size(), converged, AlphaBelow1Deg(table));
  std::vector<std::vector<std::string>> rows;
  for (const auto& q : kQuantities) {
    std::vector<double> tc, mae, fin_abs;
    for (const auto& run : table.runs) {
      if (!run.quantities.count(q)) continue;
      const auto& r = run.quantities.at(q);
      tc.push_back(r.convergence_s);
      mae.push_back(r.mae_after * Scale(q));
      fin_abs.push_back(std::abs(r.final_error) * Scale(q));
    }
    rows.push_back({q, LaserUnit(q), FormatNumber(MeanOfFinite(mae), 4),
                    FormatNumber(MeanOfFinite(fin_abs), 4), FormatNumber(Max(fin_abs), 4),
                    FormatNumber(MeanOfFinite(tc), 2), FormatNumber(Max(tc), 2),
                    PaperClaim(table.name, q)});
  }
  md += MarkdownTable({"quantity", "unit", "MAE after convergence", "mean |final error|",
                       "max |final error|", "mean t_c [s]", "max t_c [s]", "paper"},
                      rows);
  return md + "\n";
}

std::string RunsMarkdown(const TableResult& table) {
  std::vector<std::string> header = {"seed", "converged"};
  for (const auto& q : kQuantities) {
    header.push_back(fmt::format("{} final [{}]", q, LaserUnit(q)));
    header.push_back(fmt::format("{} late MAE", q));
    header.push_back(q + " t_c [s]");
  }
  std::vector<std::vector<std::string>> rows;
  for (const auto& run : table.runs) {
    std::vector<std::string> row = {std::to_string(run.seed),
                                    run.note.empty() ? (run.converged ? "yes" : "no") : run.note};
    for (const auto& q : kQuantities) {
      const QuantityResult r = run.quantities.count(q) ? run.quantities.at(q) : QuantityResult{};
      row.push_back(FormatNumber(r.final_error * Scale(q), 4));
      row.push_back(FormatNumber(r.mae_late * Scale(q), 4));
      row.push_back(FormatNumber(r.convergence_s, 2));
    }
    rows.push_back(row);
  }
  return fmt::format("#### {}: every run\n\n", table.name) + MarkdownTable(header, rows) + "\n";
}

void AppendCsv(const TableResult& table, std::string* csv) {
  for (const auto& run : table.runs) {
    for (const auto& q : kQuantities) {
      const QuantityResult r = run.quantities.count(q) ? run.quantities.at(q) : QuantityResult{};
      // The table name holds a comma ("simulated, no bias"): quoted as RFC 4180 says.
      *csv += fmt::format("\"{}\",{},{},{},{},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g}\n", table.name,
                          run.seed, run.converged ? 1 : 0, q, LaserUnit(q),
                          r.final_error * Scale(q), r.mae_after * Scale(q), r.mae_late * Scale(q),
                          r.mae_all * Scale(q), r.convergence_s);
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
nlohmann::json LaserUnitResult(const LaserSettings& settings, const std::string& unit,
                               uint64_t seed) {
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

}  // namespace

nlohmann::json RunLaserReproUnit(const std::map<std::string, std::string>& settings,
                                 const std::string& unit, uint64_t seed) {
  return LaserUnitResult(ParseLaserSettings(settings), unit, seed);
}

int RunLaserRepro(const ReproOptions& options) {
  const LaserSettings settings = ParseLaserSettings(options.settings);
  const std::map<std::string, std::string>& ekf_settings = settings.ekf;
  const int runs = ReproRunCount(options, kLaserDefaultRuns);
  const double duration_s = settings.duration_s;
  const int euroc_runs = std::min(runs, settings.euroc_runs);
  const bool with_euroc = settings.with_euroc;
  Bands bands = settings.bands;

  // Units: (laser-plane, seed), (laser-plane-bias, seed) for every seed, (euroc-laser, seed) for
  // the first euroc_runs seeds.
  ReproUnitGrid grid;
  grid.runs = runs;
  grid.unit_names = {kNoBiasUnit, kBiasUnit};
  if (with_euroc) grid.unit_names.push_back(kEurocUnit);
  for (size_t u = 0; u < grid.unit_names.size(); ++u)
    for (int k = 0; k < (grid.unit_names[u] == kEurocUnit ? euroc_runs : runs); ++k)
      grid.indices.push_back(u * static_cast<size_t>(runs) + static_cast<size_t>(k));
  const std::vector<nlohmann::json> results =
      RunReproUnits("laser", options, grid, [&](const std::string& unit, uint64_t seed) {
        return LaserUnitResult(settings, unit, seed);
      });

  std::vector<TableResult> tables = {{"simulated, no bias", {}}, {"simulated, with bias", {}}};
  std::string euroc_note;
  if (with_euroc) {
    tables.push_back({"euroc, raw IMU", {}});
    tables.push_back({"euroc, IMU bias-corrected", {}});
    tables.push_back({"euroc, IMU from ground truth", {}});
  }
  for (size_t i = 0; i < results.size(); ++i) {
    const size_t u = grid.indices[i] / static_cast<size_t>(runs);
    const nlohmann::json& unit_runs = results[i].at("runs");
    for (size_t r = 0; r < unit_runs.size(); ++r)
      tables[u == 2 ? 2 + r : u].runs.push_back(FromExactJson<RunResult>(unit_runs[r]));
    if (u == 2 && euroc_note.empty()) euroc_note = results[i].at("distance_range_m");
  }

  // ---- report ----
  nlohmann::json json;
  json["paper"] =
      "Martinelli & Troiani, Vision-Aided Inertial Navigation Using Virtual Features, INRIA "
      "RR-7906, "
      "2012, section 5";
  json["estimator"] = "laser-ekf";
  json["estimator_options"] = ekf_settings;
  json["jobs"] = options.jobs;
  json["runs"] = runs;
  json["first_seed"] = options.seed;
  json["laser_plane_duration_s"] = duration_s;
  json["bands"] = {{"alpha_deg", bands.si["alpha"] / kDeg},
                   {"roll_pitch_deg", bands.si["roll"] / kDeg},
                   {"v_o_m_s", bands.si["v_o"]},
                   {"d_m", bands.si["d"]}};
  json["definitions"] =
      "t_c: first time after which |error| stays within the band to the end; MAE after "
      "convergence over t >= t_c; final error at the last sample; a run converged when every "
      "quantity's mean |error| over the last quarter of the run is within its band; filter "
      "started 10-20 % off the true modes";
  std::string md = fmt::format(
      "# mavloc repro laser\n\nMartinelli & Troiani, *Vision-Aided Inertial Navigation Using "
      "Virtual Features*, INRIA RR-7906, 2012, section 5. Estimator `laser-ekf` (EKF on "
      "m = [m1..m4, g_z], eq. 9-11, appendix C), started 10-20 % off the true modes (5.1.3).\n\n"
      "- simulated: scenario `laser-plane` ({} s, plane at 22.5 deg, L = 0.3 m, spot at 10 Hz "
      "with 1 deg noise, IMU 100 Hz with 1 deg/s and 0.01 m/s^2), seeds {}..{}; with bias: "
      "0.03 deg/s and 0.03 m/s^2 on every axis.\n",
      duration_s, options.seed, options.seed + runs - 1);
  if (with_euroc) {
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
  }
  md += fmt::format(
      "\nConvergence time t_c: the first time after which |error| stays within the band until "
      "the end (alpha {} deg, roll/pitch {} deg, v_o {} m/s, d {} m); MAE after convergence: "
      "mean |error| over t >= t_c; a run converged when every quantity's mean |error| over the "
      "last quarter of the run (late MAE) is within its band. Angles in degrees.\n\n",
      bands.si["alpha"] / kDeg, bands.si["roll"] / kDeg, bands.si["v_o"], bands.si["d"]);
  std::string runs_md;
  std::string csv =
      "table,seed,converged,quantity,unit,final_error,mae_after_convergence,mae_last_quarter,"
      "mae_all,convergence_time_s\n";
  for (const auto& table : tables) {
    md += SummaryMarkdown(table);
    runs_md += RunsMarkdown(table);
    AppendCsv(table, &csv);
    const std::string key =
        table.name.rfind("simulated", 0) == 0
            ? (table.name == "simulated, no bias" ? "no_bias" : "with_bias")
            : (table.name == "euroc, raw IMU"
                   ? "raw_imu"
                   : (table.name == "euroc, IMU bias-corrected" ? "bias_corrected"
                                                                : "imu_from_ground_truth"));
    json["tables"][table.name.rfind("simulated", 0) == 0 ? "simulated" : "euroc"][key] =
        TableJson(table);
  }
  if (!with_euroc) md += "(euroc table skipped: euroc=false)\n\n";
  md += "## Every run\n\n" + runs_md;
  ReportFiles files;
  files.markdown = md;
  files.json = json;
  files.extra["runs.csv"] = csv;
  files.protocol = LaserProtocol();
  WriteReportFolder(options.report_dir, files);
  return 0;
}

}  // namespace mavloc
