#include "evaluation/repro/three_point_repro.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <Eigen/LU>
#include <Eigen/SVD>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "core/errors.h"
#include "core/key_values.h"
#include "core/number_text.h"
#include "core/numbers.h"
#include "core/rotation.h"
#include "datasets/scenarios/three_point_hover.h"
#include "evaluation/comparison.h"
#include "evaluation/json_number.h"
#include "evaluation/report_writer.h"
#include "evaluation/repro/repro_units.h"
#include "solver/three_point/triangle_angle_filter.h"

namespace mavloc {

namespace {

using Settings = std::map<std::string, std::string>;

constexpr int kThreePointDefaultRuns = 20;
const std::vector<std::string> kColumns = {"x", "y", "z", "roll", "pitch", "yaw"};
// Table I of the paper: mean errors, x, y, z in %, roll, pitch, yaw in deg.
constexpr std::array<double, 6> kPaper3p = {0.26, 0.24, 0.08, 0.07, 0.04, 0.01};
constexpr std::array<double, 6> kPaper2p = {4.08, 5.41, 5.23, 1.63, 1.72, 1.36};
constexpr const char* kErrorDefinition =
    "angles: mean of |estimate - truth| (wrapped) in degrees; x, y, z in %: mean of "
    "100 |estimate - truth| / r, where r is the true distance from the vehicle to the feature P1 "
    "(the origin of the paper's frame) at that frame; means over every frame with a solution of "
    "every Monte-Carlo run; the same definition for every row";

bool IsPosition(const std::string& q) { return q == "x" || q == "y" || q == "z"; }
std::string ThreePointUnit(const std::string& q) { return IsPosition(q) ? "%" : "deg"; }

// Per-frame errors of one quantity pooled over runs.
struct ErrorStat {
  double sum = 0.0, sum2 = 0.0;
  long count = 0;
  std::vector<double> run_means;
  // One run given by its totals (a unit's JSON result).
  void AddRunTotals(double run_sum, double run_sum2, long run_count) {
    if (run_count <= 0) return;
    sum += run_sum;
    sum2 += run_sum2;
    count += run_count;
    run_means.push_back(run_sum / static_cast<double>(run_count));
  }
  double Mean() const { return count > 0 ? sum / static_cast<double>(count) : kNaN; }
  double Rms() const { return count > 0 ? std::sqrt(sum2 / static_cast<double>(count)) : kNaN; }
  double RunStd() const {
    if (run_means.size() < 2) return kNaN;
    double m = 0.0, s = 0.0;
    for (const double v : run_means) m += v;
    m /= static_cast<double>(run_means.size());
    for (const double v : run_means) s += (v - m) * (v - m);
    return std::sqrt(s / static_cast<double>(run_means.size() - 1));
  }
};

struct VariantStats {
  std::map<std::string, ErrorStat> quantities;
  long failures = 0;
  std::map<std::string, int> failure_reasons;
  double runtime_s = 0.0;
  double Mean(const std::string& q) const {
    const auto it = quantities.find(q);
    return it == quantities.end() ? kNaN : it->second.Mean();
  }
};

struct ThreePointVariant {
  std::string label;  // row name in the reports
  std::string estimator;
  EstimatorOptions options;
};

std::vector<ThreePointVariant> MakeVariants(double bearing_noise_deg, bool with_true_angles) {
  const std::string sigma = fmt::format("{}", bearing_noise_deg);
  std::vector<ThreePointVariant> variants;
  variants.push_back(
      {"three-point", "three-point", EstimatorOptions(Settings{{"bearing_sigma_deg", sigma}})});
  if (with_true_angles)
    variants.push_back({"three-point (true angles)", "three-point",
                        EstimatorOptions(Settings{{"true_angles", "true"}})});
  variants.push_back({"two-point", "two-point", EstimatorOptions()});
  variants.push_back({"gravity-ekf", "gravity-ekf", EstimatorOptions()});
  return variants;
}

// One run of one variant as JSON: per quantity the sums of its per-frame errors (x, y, z in %,
// angles in deg), the frames without a solution and the run time. The report is made from these
// whether the runs ran here or in sweep workers.
nlohmann::json RunVariant(const Dataset& d, const ThreePointVariant& variant) {
  EvaluationOptions evaluation_options;
  evaluation_options.quantities = kColumns;
  const EstimatorEvaluation e =
      RunAndEvaluate(variant.estimator, variant.options, d, evaluation_options);
  if (!e.ran)
    throw InputError("repro three-point: " + variant.estimator +
                     " does not apply: " + e.skipped_reason);
  const Eigen::Vector3d P1 = d.map.landmarks_W.at(1);
  nlohmann::json quantities = nlohmann::json::object();
  for (const auto& series : e.quantity_errors) {
    double sum = 0.0, sum2 = 0.0;
    for (size_t i = 0; i < series.error.size(); ++i) {
      const double error = std::abs(series.error[i]);
      const double v =
          IsPosition(series.name)
              ? 100.0 * error / (NearestTruth(d.ground_truth, series.t_ns[i]).T_W_B.p - P1).norm()
              : error / kDeg;
      sum += v;
      sum2 += v * v;
    }
    quantities[series.name] = {
        {"sum", JsonNumber(sum)}, {"sum2", JsonNumber(sum2)}, {"count", series.error.size()}};
  }
  return {{"quantities", quantities},
          {"failures", e.estimate.FailureCount()},
          {"failure_reasons", e.estimate.failures},
          {"runtime_s", e.runtime_s}};
}

void AddRunFromJson(const nlohmann::json& run, VariantStats* stats) {
  for (const auto& [name, q] : run.at("quantities").items())
    stats->quantities[name].AddRunTotals(NumberFromJson(q.at("sum")), NumberFromJson(q.at("sum2")),
                                         q.at("count").get<long>());
  stats->failures += run.at("failures").get<long>();
  for (const auto& [reason, count] : run.at("failure_reasons").items())
    stats->failure_reasons[reason] += count.get<int>();
  stats->runtime_s += run.at("runtime_s").get<double>();
}

// A configuration of the reproduction: table1 or one row of the sensitivity sweep.
struct ThreePointConfig {
  std::string label;  // "table1", "row0", "row1", ...: the unit's scenario on the sweep machinery
  Settings scenario;  // the scenario's settings
  double noise_deg = 0.0, height_m = 0.0;
  std::optional<double> accel_bias_m_s2;  // set on the biased-accelerometer rows
  std::vector<ThreePointVariant> variants;
};

// Everything the `--set` settings determine: the same in the report's process and in every
// sweep worker, so a unit names its configuration by label only.
struct ThreePointPlan {
  Settings scenario_settings;  // the settings that go to the scenario
  std::vector<double> noise_levels, heights;
  double bias_rows_accel_m_s2 = 0.0;
  double bearing_noise_deg = 1.0;
  Dataset reference;  // noiseless, default geometry: validates the settings, gives the map
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  std::vector<ThreePointConfig> configs;  // table1, then the sensitivity rows in report order
};

std::vector<double> ParseList(const Settings& settings, const std::string& key,
                              const std::string& fallback);

ThreePointPlan MakeThreePointPlan(const Settings& settings) {
  ThreePointPlan plan;
  plan.scenario_settings = settings;
  plan.noise_levels = ParseList(settings, "noise_levels_deg", "0.001,0.01,0.03,0.1,0.3,1");
  plan.heights = ParseList(settings, "heights_m", "0.2,0.4,0.6,0.8,1");
  plan.bias_rows_accel_m_s2 = GetDoubleSetting(settings, "bias_rows_accel_bias_m_s2", 0.05);
  plan.scenario_settings.erase("noise_levels_deg");
  plan.scenario_settings.erase("heights_m");
  plan.scenario_settings.erase("bias_rows_accel_bias_m_s2");

  ScenarioOptions probe;
  probe.settings = plan.scenario_settings;
  probe.settings["bearing_noise_deg"] = "0";
  plan.reference = GenerateThreePointHover(probe);  // validates the settings
  plan.bearing_noise_deg = plan.scenario_settings.count("bearing_noise_deg")
                               ? GetDoubleSetting(plan.scenario_settings, "bearing_noise_deg", 1.0)
                               : 1.0;
  const auto& landmarks = plan.reference.map.landmarks_W;
  plan.centroid = (landmarks.at(1) + landmarks.at(2) + landmarks.at(3)) / 3.0;

  plan.configs.push_back({"table1", plan.scenario_settings, plan.bearing_noise_deg, 0.0,
                          std::nullopt, MakeVariants(plan.bearing_noise_deg, true)});
  auto add_row = [&](double noise, double h, std::optional<double> accel_bias) {
    Settings s = plan.scenario_settings;
    s["bearing_noise_deg"] = fmt::format("{}", noise);
    s["start_x"] = fmt::format("{}", plan.centroid.x());
    s["start_y"] = fmt::format("{}", plan.centroid.y());
    s["start_z"] = fmt::format("{}", 1.25 * h);
    s["goal_x"] = fmt::format("{}", plan.centroid.x() + 0.5 * h);
    s["goal_y"] = fmt::format("{}", plan.centroid.y() + 0.3 * h);
    s["goal_z"] = fmt::format("{}", h);
    if (accel_bias) s["accel_bias_m_s2"] = fmt::format("{}", *accel_bias);
    const std::string label = fmt::format("row{}", plan.configs.size() - 1);
    plan.configs.push_back({label, s, noise, h, accel_bias, MakeVariants(noise, false)});
  };
  for (const double noise : plan.noise_levels)
    for (const double h : plan.heights) add_row(noise, h, std::nullopt);
  // The same noise axis with a biased accelerometer (the gravity EKF cannot see the bias, so its
  // roll/pitch is off by about bias / g): where the triangle's information could pay off.
  if (plan.bias_rows_accel_m_s2 > 0.0)
    for (const double noise : plan.noise_levels) add_row(noise, 0.4, plan.bias_rows_accel_m_s2);
  return plan;
}

// One Monte-Carlo run of one configuration: every variant on the same simulated dataset.
nlohmann::json RunThreePointUnit(const ThreePointConfig& config, uint64_t seed) {
  ScenarioOptions scenario;
  scenario.seed = seed;
  scenario.settings = config.scenario;
  const Dataset d = GenerateThreePointHover(scenario);
  nlohmann::json variants = nlohmann::json::object();
  for (const auto& variant : config.variants) {
    variants[variant.label] = RunVariant(d, variant);
  }
  return {{"variants", variants}};
}

std::map<std::string, VariantStats> MergeRuns(const ThreePointConfig& config,
                                              const std::vector<nlohmann::json>& runs) {
  std::map<std::string, VariantStats> stats;
  for (const auto& run : runs)
    for (const auto& variant : config.variants)
      AddRunFromJson(run.at("variants").at(variant.label), &stats[variant.label]);
  return stats;
}

// First-order prediction of the 3p roll/pitch error (IV-B): at the last frame of a noiseless run,
// the root of (6) moves by d(zeta) = -J_zeta^-1 J_xy d(xy) when the image points move by d(xy);
// with per-axis bearing noise sigma this gives the covariance of roll and pitch (the triangle's
// angles taken as exact).
struct FirstOrder {
  Eigen::Vector2d sigma_deg = Eigen::Vector2d::Constant(kNaN);  // roll, pitch
  double smallest_singular_value = kNaN;                        // of J_zeta (rad/rad)
};

FirstOrder FirstOrderTiltSigma(Settings settings, double bearing_noise_deg) {
  FirstOrder out;
  settings["bearing_noise_deg"] = "0";
  ScenarioOptions scenario;
  scenario.settings = settings;
  const Dataset d = GenerateThreePointHover(scenario);
  const TimeNs t_last = d.features.empty() ? 0 : d.features.back().t_ns;
  std::map<int, Eigen::Vector2d> xy;
  for (const auto& f : d.features)
    if (f.t_ns == t_last) xy[f.landmark_id] = f.xy;
  if (xy.size() < 3) return out;
  const auto it = std::find_if(d.ground_truth.begin(), d.ground_truth.end(),
                               [&](const GroundTruthState& s) { return s.t_ns == t_last; });
  if (it == d.ground_truth.end()) return out;
  const EulerRpy rpy = EulerFromQuaternion(it->T_W_B.q);
  TriangleAngleInput input;
  input.roll_rad = rpy.roll;
  input.pitch_rad = rpy.pitch;
  input.xy = {xy.at(1), xy.at(2), xy.at(3)};
  input.R_B_C = d.cameras.at(0).T_B_C.R();
  TriangleAngleMeasurement m;
  Eigen::Matrix<double, 2, 8> J;
  if (!MeasureTriangleAngles(input, &m, &J)) return out;
  const Eigen::Matrix2d J_zeta = J.rightCols<2>();
  const Eigen::Matrix<double, 2, 6> J_xy = J.leftCols<6>();
  Eigen::Matrix<double, 6, 6> sigma_xy = Eigen::Matrix<double, 6, 6>::Zero();
  for (int i = 0; i < 3; ++i) {
    const double s = bearing_noise_deg * kDeg * (1.0 + input.xy[i].squaredNorm());
    sigma_xy.block<2, 2>(2 * i, 2 * i) = s * s * Eigen::Matrix2d::Identity();
  }
  const Eigen::Matrix<double, 2, 6> A = J_zeta.inverse() * J_xy;
  const Eigen::Matrix2d cov = A * sigma_xy * A.transpose();
  out.sigma_deg = Eigen::Vector2d(std::sqrt(cov(0, 0)), std::sqrt(cov(1, 1))) / kDeg;
  const Eigen::Vector2d sv = Eigen::JacobiSVD<Eigen::Matrix2d>(J_zeta).singularValues();
  out.smallest_singular_value = sv(1);
  return out;
}

nlohmann::json StatsToJson(const VariantStats& stats, const std::array<double, 6>* paper) {
  nlohmann::json quantities = nlohmann::json::object();
  for (size_t c = 0; c < kColumns.size(); ++c) {
    const auto it = stats.quantities.find(kColumns[c]);
    if (it == stats.quantities.end()) continue;
    const ErrorStat& s = it->second;
    // Angles in rad (the statistics and the paper's Table I are in deg), positions in %.
    const double to_si = IsPosition(kColumns[c]) ? 1.0 : kDeg;
    nlohmann::json q = {{"mean_abs", s.Mean() * to_si},
                        {"rmse", s.Rms() * to_si},
                        {"std_over_runs", s.RunStd() * to_si},
                        {"count", s.count},
                        {"unit", IsPosition(kColumns[c]) ? "%" : "rad"}};
    if (paper != nullptr) q["paper"] = (*paper)[c] * to_si;
    quantities[kColumns[c]] = q;
  }
  nlohmann::json j = {{"quantities", quantities}, {"runtime_s", stats.runtime_s}};
  if (stats.failures > 0) j["failures"] = stats.failure_reasons;
  return j;
}

std::vector<double> ParseList(const Settings& settings, const std::string& key,
                              const std::string& fallback) {
  const auto it = settings.find(key);
  const std::string text = it == settings.end() ? fallback : it->second;
  std::vector<double> values;
  std::stringstream stream(text);
  std::string item;
  while (std::getline(stream, item, ',')) {
    const ParsedNumber<double> v = ParseDoubleText(item);
    if (!v.ok() || !(v.value > 0.0))
      throw InputError("repro three-point: --set " + key + "=" + text +
                       ": expected a comma-separated list of positive numbers" +
                       (v.ok() ? "" : " (" + DescribeNumberText(item, v) + ")"));
    values.push_back(v.value);
  }
  if (values.empty()) throw InputError("repro three-point: --set " + key + " is empty");
  return values;
}

std::string Cell(double value) {
  if (!std::isfinite(value)) return "-";
  if (std::abs(value) >= 100.0) return FormatNumber(value, 0);
  if (std::abs(value) >= 10.0) return FormatNumber(value, 1);
  return FormatNumber(value, std::abs(value) >= 1.0 ? 2 : 3);
}

bool BeatsOnEveryColumn(const VariantStats& three, const VariantStats& two) {
  for (const auto& q : kColumns)
    if (!(three.Mean(q) < two.Mean(q))) return false;
  return true;
}

// Appends the error columns (x, y, z in %, angles in rad) named prefix + quantity.
void AddThreePointErrorColumns(const std::string& prefix, ReportTable* table) {
  for (const auto& q : kColumns)
    table->columns.push_back({prefix + q, IsPosition(q) ? "%" : "rad"});
}

// Appends the mean errors of `stats` (or the paper's values) in SI units.
void AddThreePointErrorCells(const VariantStats* stats, const std::array<double, 6>* paper,
                             std::vector<nlohmann::json>* cells) {
  for (size_t c = 0; c < kColumns.size(); ++c) {
    const double shown = paper ? (*paper)[c] : stats->Mean(kColumns[c]);
    cells->push_back(IsPosition(kColumns[c]) ? shown : shown * kDeg);
  }
}

// Table I: the paper's rows beside mavloc's (mean errors; frames without a solution).
ReportTable ThreePointTable1(const std::map<std::string, VariantStats>& table1,
                             double bearing_noise_deg) {
  ReportTable table = ReproTable(
      "table1", fmt::format("Table I — mean error at bearing noise {} deg", bearing_noise_deg),
      {"row"});
  AddThreePointErrorColumns("", &table);
  table.columns.push_back({"frames without solution", ""});
  const auto add = [&](const std::string& row, const VariantStats* stats,
                       const std::array<double, 6>* paper) {
    std::vector<nlohmann::json> cells = {row};
    AddThreePointErrorCells(stats, paper, &cells);
    cells.push_back(stats ? nlohmann::json(stats->failures) : nlohmann::json());
    table.rows.push_back(std::move(cells));
  };
  add("3pAlgo (paper)", nullptr, &kPaper3p);
  add("3pAlgo (mavloc, filtered angles)", &table1.at("three-point"), nullptr);
  add("3pAlgo (mavloc, true angles)", &table1.at("three-point (true angles)"), nullptr);
  add("2pAlgo (paper)", nullptr, &kPaper2p);
  add("2pAlgo (mavloc)", &table1.at("two-point"), nullptr);
  add("gravity EKF (mavloc)", &table1.at("gravity-ekf"), nullptr);
  return table;
}

// The findings at table1's noise, column by column, against the paper's claims.
std::vector<std::string> ThreePointTable1Findings(const std::map<std::string, VariantStats>& table1,
                                                  const FirstOrder& first_order,
                                                  const ThreePointPlan& plan) {
  const VariantStats& s3 = table1.at("three-point");
  const VariantStats& s3t = table1.at("three-point (true angles)");
  const VariantStats& s2 = table1.at("two-point");
  const VariantStats& ekf = table1.at("gravity-ekf");
  std::vector<std::string> findings;
  for (size_t c = 0; c < kColumns.size(); ++c) {
    const std::string& q = kColumns[c];
    const double m3 = s3.Mean(q), m2 = s2.Mean(q);
    std::string line = fmt::format("- **{}**: 3p {} {} vs 2p {} {} (paper: 3p {}, 2p {}).", q,
                                   Cell(m3), ThreePointUnit(q), Cell(m2), ThreePointUnit(q),
                                   Cell(kPaper3p[c]), Cell(kPaper2p[c]));
    if (m3 < m2) {
      line += " 3p is better, as the paper claims";
      line += m3 <= 1.5 * kPaper3p[c] ? ", and reaches the paper's value."
                                      : ", but does not reach the paper's value.";
    } else if (q == "roll" || q == "pitch") {
      line += fmt::format(
          " The paper's claim is not met: 2p's {} is the gravity EKF's ({} deg, from the "
          "accelerometer at 0.01 m/s^2), while 3p replaces it by the root of (6). Tilting the "
          "levelling rotation changes the triangle's angles little when it is seen near the "
          "vertical: the smallest singular value of the Jacobian of (6) at the hover is {} "
          "rad/rad, so 1 deg of bearing noise gives a first-order 3p {} error of {} deg "
          "(measured {} deg).",
          q, Cell(ekf.Mean(q)), Cell(first_order.smallest_singular_value), q,
          Cell(q == "roll" ? first_order.sigma_deg.x() : first_order.sigma_deg.y()), Cell(m3));
    } else {
      line += fmt::format(
          " The paper's claim is not met: 3p's {} comes from the 2p formulas evaluated at 3p's "
          "roll and pitch, whose errors (mean {} / {} deg) mis-level the bearings: a tilt error "
          "delta shifts the position by about height x delta and rotates the levelled segment "
          "P1 P2, so the error grows rather than shrinks.",
          q, Cell(s3.Mean("roll")), Cell(s3.Mean("pitch")));
    }
    findings.push_back(line);
  }
  const Dataset& reference = plan.reference;
  findings.push_back(fmt::format(
      "- **2p against the paper's 2p row**: mavloc's 2p roll/pitch error is the gravity EKF's "
      "({} / {} deg), far below the paper's 1.63 / 1.72 deg; its yaw and position errors come "
      "from the bearing noise over the segment P1 P2, which subtends only about {} deg from the "
      "hover (D / range).",
      Cell(ekf.Mean("roll")), Cell(ekf.Mean("pitch")),
      Cell(reference.map.parameters.at("D") /
           (reference.ground_truth.back().T_W_B.p - plan.centroid).norm() / kDeg)));
  findings.push_back(fmt::format(
      "- **Filtered vs true triangle angles**: with the true angles 3p's roll/pitch error is "
      "{} / {} deg (filtered: {} / {} deg); the angle filter is not what limits 3p.",
      Cell(s3t.Mean("roll")), Cell(s3t.Mean("pitch")), Cell(s3.Mean("roll")),
      Cell(s3.Mean("pitch"))));
  return findings;
}

// One row of the sensitivity sweep.
struct ThreePointGridRow {
  const ThreePointConfig* config = nullptr;
  std::map<std::string, VariantStats> stats;
  FirstOrder first_order;
  bool beats = false;
  std::string Label() const {
    return fmt::format("{} deg, {} m{}", config->noise_deg, config->height_m,
                       config->accel_bias_m_s2 ? ", biased accelerometer" : "");
  }
  bool TiltBeatsEkf() const {
    const VariantStats& t = stats.at("three-point");
    const VariantStats& e = stats.at("gravity-ekf");
    return t.Mean("roll") < e.Mean("roll") && t.Mean("pitch") < e.Mean("pitch");
  }
};

ReportTable ThreePointSensitivityTable(const std::vector<ThreePointGridRow>& grid) {
  ReportTable table = ReproTable(
      "sensitivity",
      "Sensitivity — mean errors over bearing noise x hover height (and a biased accelerometer)",
      {"bearing noise [rad]", "h [m]", "accel bias [m/s^2]"});
  AddThreePointErrorColumns("2p ", &table);
  AddThreePointErrorColumns("3p ", &table);
  for (const char* column :
       {"EKF roll", "EKF pitch", "3p first-order sigma roll", "3p first-order sigma pitch"})
    table.columns.push_back({column, "rad"});
  table.columns.push_back({"3p better on all", ""});
  for (const auto& row : grid) {
    const ThreePointConfig& config = *row.config;
    std::vector<nlohmann::json> cells = {
        config.noise_deg * kDeg, config.height_m,
        config.accel_bias_m_s2 ? nlohmann::json(*config.accel_bias_m_s2) : nlohmann::json()};
    for (const char* variant : {"two-point", "three-point"})
      AddThreePointErrorCells(&row.stats.at(variant), nullptr, &cells);
    const VariantStats& ekf = row.stats.at("gravity-ekf");
    cells.insert(cells.end(), {ekf.Mean("roll") * kDeg, ekf.Mean("pitch") * kDeg,
                               row.first_order.sigma_deg.x() * kDeg,
                               row.first_order.sigma_deg.y() * kDeg, row.beats ? "yes" : "no"});
    table.rows.push_back(std::move(cells));
  }
  return table;
}

std::string ThreePointSensitivityProse(const std::vector<ThreePointGridRow>& grid, int runs,
                                       double bias_m_s2) {
  std::vector<std::string> regime, tilt_better;
  for (const auto& row : grid) {
    if (row.beats) regime.push_back(row.Label());
    if (row.TiltBeatsEkf()) tilt_better.push_back(row.Label());
  }
  std::string md = fmt::format(
      "Sweep geometry: start 1.25 h above the triangle's centroid, goal h (0.5, 0.3, 1) from it "
      "(h = 0.4 m is table1's geometry); {} runs per row. The noise axis extends "
      "0.01-1 deg down to 0.001 deg to locate the crossover. The last rows repeat the noise axis "
      "at h = 0.4 m with a constant accelerometer bias drawn N(0, ({} m/s^2)^2) per axis, which "
      "the gravity EKF cannot separate from gravity. Columns: mean errors of 2p and 3p, the "
      "gravity EKF's roll/pitch error, the first-order 3p roll/pitch sigma from the bearing "
      "noise, and whether 3p beats 2p on all six columns.\n\n",
      runs, bias_m_s2);
  md += "**Regime where 3p beats 2p on every column:** ";
  md += regime.empty() ? std::string("none of the rows.")
                       : fmt::format("{} of {} rows: {}.", regime.size(), grid.size(),
                                     fmt::join(regime, "; "));
  md += "\n\n**Rows where 3p's roll and pitch are both better than the gravity EKF's:** ";
  md +=
      tilt_better.empty() ? std::string("none.") : fmt::format("{}.", fmt::join(tilt_better, "; "));
  md +=
      "\n\nThe first-order sigma scales linearly with the bearing noise and grows with the "
      "height (the triangle's apparent size D / h shrinks), and it matches the measured 3p "
      "errors; the paper's 3p row (0.07 / 0.04 deg roll / pitch at 1 deg) would need a Jacobian "
      "of (6) hundreds of times better conditioned than a 0.1 m triangle seen from 0.2-1 m "
      "gives.\n";
  return md;
}

// The sensitivity rows' per-variant statistics (the table and the prose hold the rest).
nlohmann::json ThreePointSensitivityJson(const std::vector<ThreePointGridRow>& grid,
                                         const ThreePointPlan& plan) {
  nlohmann::json rows = nlohmann::json::array();
  for (const auto& row : grid) {
    const ThreePointConfig& config = *row.config;
    nlohmann::json r = {
        {"bearing_noise_rad", config.noise_deg * kDeg},
        {"height_m", config.height_m},
        {"accel_bias_sigma_m_s2",
         config.accel_bias_m_s2 ? *config.accel_bias_m_s2
                                : GetDoubleSetting(plan.scenario_settings, "accel_bias_m_s2", 0.0)},
        {"three_point_beats_two_point_on_every_column", row.beats}};
    for (const auto& [label, stats] : row.stats)
      r["estimators"][label] = StatsToJson(stats, nullptr);
    rows.push_back(r);
  }
  return {{"rows", rows}};
}

Report SummarizeThreePoint(const ReproRuns& runs) {
  const ThreePointPlan plan = MakeThreePointPlan(runs.settings);
  const auto stats_of = [&](size_t c) { return MergeRuns(plan.configs[c], runs.results[c]); };
  const auto table1 = stats_of(0);
  const FirstOrder first_order =
      FirstOrderTiltSigma(plan.scenario_settings, plan.bearing_noise_deg);
  std::vector<ThreePointGridRow> grid;
  for (size_t c = 1; c < plan.configs.size(); ++c) {
    ThreePointGridRow row{&plan.configs[c], stats_of(c), {}, false};
    row.first_order = FirstOrderTiltSigma(row.config->scenario, row.config->noise_deg);
    row.beats = BeatsOnEveryColumn(row.stats.at("three-point"), row.stats.at("two-point"));
    grid.push_back(std::move(row));
  }
  const std::vector<std::string> findings = ThreePointTable1Findings(table1, first_order, plan);

  Report report;
  report.title = "mavloc repro three-point";
  report.provenance.input = "three-point-hover";
  report.tables = {ThreePointTable1(table1, plan.bearing_noise_deg),
                   ThreePointSensitivityTable(grid)};
  report.sections.push_back(
      {"Setup",
       fmt::format(
           "Troiani, Al Zanati, Martinelli, *A 3 Points Vision Based Approach for MAV "
           "Localization in GPS Denied Environments*, ECMR 2013: Table I (sect. V-A).\n\n"
           "Scenario `three-point-hover` ({}), {} Monte-Carlo runs (seeds {}). Start, goal "
           "and camera are mavloc's choices (the paper does not state them): start {}; "
           "goal {}.\n\n**Error definition.** {}.\n",
           plan.scenario_settings.empty() ? "default settings" : "settings as given with --set",
           runs.runs, runs.Seeds(), plan.reference.scenario_info.at("start"),
           plan.reference.scenario_info.at("goal"), kErrorDefinition)});
  report.sections.back().before_tables = true;
  report.sections.push_back({"Table I findings", fmt::format("{}\n", fmt::join(findings, "\n"))});
  report.sections.push_back(
      {"Sensitivity", ThreePointSensitivityProse(grid, runs.runs, plan.bias_rows_accel_m_s2)});

  nlohmann::json t1;
  t1["estimators"]["three-point"] = StatsToJson(table1.at("three-point"), &kPaper3p);
  t1["estimators"]["three-point (true angles)"] =
      StatsToJson(table1.at("three-point (true angles)"), nullptr);
  t1["estimators"]["two-point"] = StatsToJson(table1.at("two-point"), &kPaper2p);
  t1["estimators"]["gravity-ekf"] = StatsToJson(table1.at("gravity-ekf"), nullptr);
  t1["first_order_three_point"] = {
      {"roll_sigma_rad", first_order.sigma_deg.x() * kDeg},
      {"pitch_sigma_rad", first_order.sigma_deg.y() * kDeg},
      {"smallest_singular_value_of_jacobian", first_order.smallest_singular_value}};
  report.details["tables"] = {{"table1", t1},
                              {"sensitivity", ThreePointSensitivityJson(grid, plan)}};
  return report;
}

ReproPlan PlanThreePoint(const ReproSettings& settings, uint64_t) {
  ReproPlan plan{{}, settings};
  for (const auto& config : MakeThreePointPlan(settings).configs)
    plan.units.push_back({config.label});
  return plan;
}

nlohmann::json RunThreePointReproUnit(const ReproSettings& settings, const std::string& label,
                                      uint64_t seed) {
  const ThreePointPlan plan = MakeThreePointPlan(settings);
  for (const auto& config : plan.configs)
    if (config.label == label) return RunThreePointUnit(config, seed);
  throw InputError("repro three-point: no configuration '" + label + "'");
}

}  // namespace

ReproDefinition ThreePointRepro() {
  return {.name = "three-point",
          .description = "three-point paper Table I (2p vs 3p) and a noise x height sweep",
          .paper =
              "Troiani, Al Zanati, Martinelli, A 3 Points Vision Based Approach for MAV "
              "Localization in GPS Denied Environments, ECMR 2013, Table I",
          .default_runs = kThreePointDefaultRuns,
          .plan = PlanThreePoint,
          .unit = RunThreePointReproUnit,
          .summarize = SummarizeThreePoint};
}

}  // namespace mavloc
