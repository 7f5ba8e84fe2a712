#include "evaluation/repro/pixhawk_repro.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "core/errors.h"
#include "core/key_values.h"
#include "core/numbers.h"
#include "datasets/scenarios/marker_board_flight.h"
#include "evaluation/comparison.h"
#include "evaluation/exact_json.h"
#include "evaluation/json_number.h"
#include "evaluation/report_writer.h"
#include "evaluation/repro/repro_units.h"

namespace mavloc {

namespace {

constexpr int kPixhawkDefaultRuns = 5;
constexpr double kJumpThresholdM = 0.10;

using Settings = std::map<std::string, std::string>;

// Errors pooled over frames and runs.
struct Metrics {
  double sum_p2 = 0.0, max_p = 0.0, sum_yaw2 = 0.0, sum_rp2 = 0.0, sum_v2 = 0.0;
  long n_p = 0, n_yaw = 0, n_rp = 0, n_v = 0;
  long jumps = 0, frames = 0, outputs = 0, failures = 0;
  int runs = 0;
  double runtime_s = 0.0;
  std::map<std::string, int> failure_reasons;

  double PositionRmse() const { return n_p ? std::sqrt(sum_p2 / n_p) : kNaN; }
  double PositionMax() const { return n_p ? max_p : kNaN; }
  double JumpsPerRun() const { return runs ? static_cast<double>(jumps) / runs : kNaN; }
  double YawRmse() const { return n_yaw ? std::sqrt(sum_yaw2 / n_yaw) : kNaN; }
  double RollPitchRmse() const { return n_rp ? std::sqrt(sum_rp2 / n_rp) : kNaN; }
  double VelocityRmse() const { return n_v ? std::sqrt(sum_v2 / n_v) : kNaN; }
  double OutputPercent() const { return frames ? 100.0 * outputs / frames : kNaN; }
  double SecondsPerFrame() const { return frames ? runtime_s / frames : kNaN; }

  // Adds another run's (or runs') sums: the per-configuration totals are the units' sums added in
  // seed order, so every --jobs gives the same bits.
  void Add(const Metrics& o) {
    sum_p2 += o.sum_p2;
    max_p = std::max(max_p, o.max_p);
    sum_yaw2 += o.sum_yaw2;
    sum_rp2 += o.sum_rp2;
    sum_v2 += o.sum_v2;
    n_p += o.n_p;
    n_yaw += o.n_yaw;
    n_rp += o.n_rp;
    n_v += o.n_v;
    jumps += o.jumps;
    frames += o.frames;
    outputs += o.outputs;
    failures += o.failures;
    runs += o.runs;
    runtime_s += o.runtime_s;
    for (const auto& [reason, count] : o.failure_reasons) failure_reasons[reason] += count;
  }
};

// The sums of a unit's Metrics as exact JSON (evaluation/exact_json.h).
constexpr auto ExactFields(std::type_identity<Metrics>) {
  return std::make_tuple(
      ExactField("sum_p2", &Metrics::sum_p2), ExactField("max_p", &Metrics::max_p),
      ExactField("sum_yaw2", &Metrics::sum_yaw2), ExactField("sum_rp2", &Metrics::sum_rp2),
      ExactField("sum_v2", &Metrics::sum_v2), ExactField("n_p", &Metrics::n_p),
      ExactField("n_yaw", &Metrics::n_yaw), ExactField("n_rp", &Metrics::n_rp),
      ExactField("n_v", &Metrics::n_v), ExactField("jumps", &Metrics::jumps),
      ExactField("frames", &Metrics::frames), ExactField("outputs", &Metrics::outputs),
      ExactField("failures", &Metrics::failures), ExactField("runs", &Metrics::runs),
      ExactField("runtime_s", &Metrics::runtime_s),
      ExactField("failure_reasons", &Metrics::failure_reasons));
}

struct PixhawkVariant {
  std::string label;
  std::string estimator;
  Settings options;
};

const QuantityErrorSeries* Find(const std::vector<QuantityErrorSeries>& all, const std::string& q) {
  for (const auto& s : all) {
    if (s.name == q) return &s;
  }
  return nullptr;
}

void Measure(const Dataset& d, const PixhawkVariant& variant, Metrics* m) {
  EvaluationOptions evaluation;
  evaluation.max_dt_s = 0.02;
  const EstimatorEvaluation e =
      RunAndEvaluate(variant.estimator, EstimatorOptions(variant.options), d, evaluation);
  if (!e.ran)
    throw InputError("repro pixhawk: " + variant.estimator +
                     " does not apply: " + e.skipped_reason);
  ++m->runs;
  m->runtime_s += e.runtime_s;
  m->frames += static_cast<long>(d.cameras.front().frames.size());
  m->outputs += static_cast<long>(e.estimate.quantities.size());
  // "Rejected or predicted frames": frames without a pose and frames whose measurement the outlier
  // test rejected (the filter predicted through them).
  m->failures += e.estimate.FailureCount() + e.estimate.RejectionCount();
  for (const auto& [reason, count] : e.estimate.failures) m->failure_reasons[reason] += count;
  for (const auto& [reason, count] : e.estimate.rejections) m->failure_reasons[reason] += count;

  // Position error per stamp from the x, y, z series (same stamps: one estimate row each).
  const auto* ex = Find(e.quantity_errors, "x");
  const auto* ey = Find(e.quantity_errors, "y");
  const auto* ez = Find(e.quantity_errors, "z");
  if (ex && ey && ez && ex->t_ns == ey->t_ns && ex->t_ns == ez->t_ns) {
    Eigen::Vector3d previous = Eigen::Vector3d::Zero();
    TimeNs previous_t = 0;
    for (size_t i = 0; i < ex->t_ns.size(); ++i) {
      const Eigen::Vector3d err(ex->error[i], ey->error[i], ez->error[i]);
      m->sum_p2 += err.squaredNorm();
      m->max_p = std::max(m->max_p, err.norm());
      ++m->n_p;
      if (i > 0 && NsToSeconds(ex->t_ns[i] - previous_t) <= 0.1 &&
          (err - previous).norm() > kJumpThresholdM)
        ++m->jumps;
      previous = err;
      previous_t = ex->t_ns[i];
    }
  }
  if (const auto* yaw = Find(e.quantity_errors, "yaw")) {
    for (const double v : yaw->error) m->sum_yaw2 += v * v;
    m->n_yaw += static_cast<long>(yaw->error.size());
  }
  for (const char* q : {"roll", "pitch"}) {
    if (const auto* s = Find(e.quantity_errors, q)) {
      for (const double v : s->error) m->sum_rp2 += v * v;
      m->n_rp += static_cast<long>(s->error.size());
    }
  }
  const auto* vx = Find(e.quantity_errors, "vx");
  const auto* vy = Find(e.quantity_errors, "vy");
  const auto* vz = Find(e.quantity_errors, "vz");
  if (vx && vy && vz && vx->error.size() == vy->error.size() &&
      vx->error.size() == vz->error.size()) {
    for (size_t i = 0; i < vx->error.size(); ++i)
      m->sum_v2 +=
          vx->error[i] * vx->error[i] + vy->error[i] * vy->error[i] + vz->error[i] * vz->error[i];
    m->n_v += static_cast<long>(vx->error.size());
  }
}

// The reproduction's settings: the tables, the flight's duration, the scenario's own settings.
struct PixhawkSettings {
  std::set<std::string> tables = {"fig15", "sweep", "kf", "timestamps"};
  std::optional<double> duration_s;
  Settings base;  // scenario settings from --set
};

PixhawkSettings ParsePixhawkSettings(const Settings& settings) {
  PixhawkSettings out;
  for (const auto& [key, value] : settings) {
    if (key == "tables") {
      out.tables.clear();
      std::stringstream list(value);
      std::string name;
      while (std::getline(list, name, ',')) {
        if (name != "fig15" && name != "sweep" && name != "kf" && name != "timestamps")
          throw InputError("repro pixhawk: --set tables: unknown table '" + name +
                           "' (fig15, sweep, kf, timestamps)");
        out.tables.insert(name);
      }
    } else if (key == "duration_s") {
      out.duration_s = GetDoubleSetting(settings, "duration_s", 0.0);
    } else {
      out.base[key] = value;
    }
  }
  return out;
}

// One configuration: scenario settings beside the defaults, and the variants run on each of its
// datasets (one per seed). A configuration and a seed make one unit of the sweep machinery.
struct PixhawkConfig {
  std::string name;  // the unit's name
  Settings scenario;
  std::vector<PixhawkVariant> variants;
};

// Every variant on the dataset of one configuration and seed; the Metrics of this one run each.
std::vector<Metrics> RunConfigOnce(const PixhawkSettings& settings, const PixhawkConfig& config,
                                   uint64_t seed) {
  ScenarioOptions options;
  options.seed = seed;
  options.duration_s = settings.duration_s;
  options.settings = settings.base;
  for (const auto& [key, value] : config.scenario) options.settings[key] = value;
  const Dataset d = GenerateMarkerBoardFlight(options);
  std::vector<Metrics> metrics(config.variants.size());
  for (size_t v = 0; v < config.variants.size(); ++v) Measure(d, config.variants[v], &metrics[v]);
  return metrics;
}

// Per configuration name: the Metrics of each variant, summed over the seeds.
using PixhawkResults = std::map<std::string, std::vector<Metrics>>;

// For the prose: centimetres and degrees with `digits` decimals.
std::string PixhawkCm(double metres, int digits = 2) {
  return FormatNumber(100.0 * metres, digits);
}
std::string PixhawkDeg(double rad, int digits = 3) { return FormatNumber(kRadToDeg * rad, digits); }
std::string PixhawkNumber(double value, int digits) { return FormatNumber(value, digits); }

nlohmann::json MetricsJson(const Metrics& m) {
  const auto num = [](double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(); };
  return {{"position_rmse_m", num(m.PositionRmse())},
          {"position_max_m", num(m.PositionMax())},
          {"jumps_over_10cm_per_run", num(m.JumpsPerRun())},
          {"yaw_rmse_rad", num(m.YawRmse())},
          {"roll_pitch_rmse_rad", num(m.RollPitchRmse())},
          {"velocity_rmse_m_s", num(m.VelocityRmse())},
          {"outputs_percent", num(m.OutputPercent())},
          {"runtime_s_per_frame", num(m.SecondsPerFrame())},
          {"runs", m.runs},
          {"failures", m.failure_reasons}};
}

// One table of the report, its rows as details JSON and the notes that discuss it.
struct PixhawkTable {
  ReportTable table;
  nlohmann::json json = nlohmann::json::array();
  std::string notes{};
};

const std::vector<std::string> kMetricColumns = {"position RMSE [m]",     "position max [m]",
                                                 "jumps > 10 cm per run", "yaw RMSE [rad]",
                                                 "roll/pitch RMSE [rad]", "outputs [%]"};
std::vector<nlohmann::json> MetricCells(const Metrics& m) {
  return {m.PositionRmse(), m.PositionMax(),   m.JumpsPerRun(),
          m.YawRmse(),      m.RollPitchRmse(), m.OutputPercent()};
}

// A table whose columns are `leading`, the metric columns and `trailing`.
ReportTable PixhawkMetricTable(const std::string& name, const std::string& title,
                               std::vector<std::string> leading,
                               const std::vector<std::string>& trailing = {}) {
  leading.insert(leading.end(), kMetricColumns.begin(), kMetricColumns.end());
  leading.insert(leading.end(), trailing.begin(), trailing.end());
  return ReproTable(name, title, leading);
}

// A row: the leading cells, then the metric cells.
std::vector<nlohmann::json> PixhawkMetricRow(std::vector<nlohmann::json> leading,
                                             const Metrics& m) {
  for (auto& cell : MetricCells(m)) leading.push_back(std::move(cell));
  return leading;
}

PixhawkVariant Pnp() { return {"pnp", "pnp", {{"ransac", "0"}}}; }  // the paper's baseline
PixhawkVariant Upright(const std::string& label, Settings options = {}) {
  return {label, "upright-2p", std::move(options)};
}

// ---- the configurations of each table (their names are the units' names) ----

const std::vector<double> kAttitudeErrorsDeg = {0.05, 0.1, 0.25, 0.5, 1.0, 2.0};
const std::vector<double> kPixelNoisesPx = {0.5, 1.0, 2.0, 3.0};
const std::vector<std::string> kMarkerCounts = {"1", "2", "4", "0"};  // 0: all
const std::vector<double> kOutlierFractions = {0.0, 0.05, 0.1, 0.2};
const std::vector<double> kSpeedsMs = {0.5, 1.5};

std::string MarkersLabel(const std::string& markers) { return markers == "0" ? "all" : markers; }

struct StampCase {
  std::string label, stamping, compensation_ms;
};
const std::vector<StampCase> kStampCases = {
    {"exposure (hardware trigger)", "exposure", "0"},
    {"arrival, uncompensated", "arrival", "0"},
    {"arrival, mean delay 17.5 ms subtracted", "arrival", "17.5"}};

struct KfCondition {
  std::string label, name;
  Settings scenario;
  bool dropped;  // adds the nominal-dt variant
};
const std::vector<KfCondition> kKfConditions = {
    {"defaults", "kf-defaults", {}, false},
    {"one marker in view", "kf-one-marker", {{"max_markers", "1"}}, false},
    {"20 % frames dropped", "kf-frames-dropped", {{"frame_drop_fraction", "0.2"}}, true}};

std::string SweepAttitudeName(const std::string& markers) {
  return "sweep-attitude-markers-" + MarkersLabel(markers);
}
std::string SweepPixelName(double px) { return fmt::format("sweep-pixel-noise-{}", px); }
std::string SweepMarkersName(const std::string& markers) {
  return "sweep-markers-" + MarkersLabel(markers);
}
std::string SweepOutliersName(double f) { return fmt::format("sweep-outliers-{}", f); }
std::string StampsName(double speed, const StampCase& c) {
  return fmt::format("timestamps-{}-{}-{}", speed, c.stamping, c.compensation_ms);
}

std::vector<PixhawkConfig> TableConfigs(const std::string& table) {
  std::vector<PixhawkConfig> configs;
  if (table == "fig15") {
    configs.push_back({"fig15", {}, {Pnp(), Upright("upright-2p (gravity EKF roll/pitch)")}});
  } else if (table == "sweep") {
    // IMU attitude error (ground-truth roll/pitch + Gauss-Markov error), all markers and one.
    for (const std::string markers : {"0", "1"}) {
      std::vector<PixhawkVariant> variants = {Pnp()};
      for (const double e : kAttitudeErrorsDeg)
        variants.push_back(
            Upright(fmt::format("upright-2p {} deg", e),
                    {{"attitude", "truth"}, {"attitude_error_deg", fmt::format("{}", e)}}));
      configs.push_back({SweepAttitudeName(markers), {{"max_markers", markers}}, variants});
    }
    for (const double px : kPixelNoisesPx)
      configs.push_back(
          {SweepPixelName(px), {{"pixel_noise_px", fmt::format("{}", px)}}, {Pnp(), Upright("u")}});
    for (const auto& markers : kMarkerCounts)
      configs.push_back(
          {SweepMarkersName(markers), {{"max_markers", markers}}, {Pnp(), Upright("u")}});
    for (const double f : kOutlierFractions)
      configs.push_back({SweepOutliersName(f),
                         {{"outlier_fraction", fmt::format("{}", f)}},
                         {Pnp(), Upright("u"), Upright("no-ransac", {{"ransac", "false"}})}});
  } else if (table == "kf") {
    std::vector<PixhawkVariant> variants = {
        Upright("upright-2p (raw)"),
        {"pixhawk-kf <- upright-2p", "pixhawk-kf", {}},
        Pnp(),
        {"pixhawk-kf <- pnp, roll/pitch check 5 deg", "pixhawk-kf", {{"source", "pnp"}}},
        {"pixhawk-kf <- pnp, no check",
         "pixhawk-kf",
         {{"source", "pnp"}, {"attitude_check_deg", "0"}}},
    };
    for (const auto& c : kKfConditions) {
      std::vector<PixhawkVariant> condition_variants = variants;
      if (c.dropped)
        condition_variants.push_back(
            {"pixhawk-kf <- upright-2p, nominal dt", "pixhawk-kf", {{"use_measured_dt", "false"}}});
      configs.push_back({c.name, c.scenario, condition_variants});
    }
  } else if (table == "timestamps") {
    for (const double speed : kSpeedsMs)
      for (const auto& c : kStampCases)
        configs.push_back(
            {StampsName(speed, c),
             {{"image_stamping", c.stamping}, {"speed_m_s", fmt::format("{}", speed)}},
             {Upright("upright-2p", {{"image_delay_ms", c.compensation_ms}}),
              {"pixhawk-kf", "pixhawk-kf", {{"image_delay_ms", c.compensation_ms}}}}});
  }
  return configs;
}

const std::vector<std::string> kTableOrder = {"fig15", "sweep", "kf", "timestamps"};

// The configurations of the selected tables, in report order.
std::vector<PixhawkConfig> SelectedConfigs(const std::set<std::string>& tables) {
  std::vector<PixhawkConfig> configs;
  for (const auto& table : kTableOrder) {
    if (!tables.count(table)) continue;
    for (auto& c : TableConfigs(table)) configs.push_back(std::move(c));
  }
  return configs;
}

// ---- the tables, from the summed Metrics of their configurations ----

// fig15: the defaults.
PixhawkTable Fig15(const PixhawkResults& results) {
  PixhawkTable t{PixhawkMetricTable("fig15", "fig15: pnp vs upright-2p at the defaults",
                                    {"estimator"}, {"runtime per frame [s]"})};
  const PixhawkConfig config = TableConfigs("fig15").front();
  const auto& metrics = results.at(config.name);
  for (size_t v = 0; v < config.variants.size(); ++v) {
    auto row = PixhawkMetricRow({config.variants[v].label}, metrics[v]);
    row.push_back(metrics[v].SecondsPerFrame());
    t.table.rows.push_back(std::move(row));
    nlohmann::json j = MetricsJson(metrics[v]);
    j["estimator"] = config.variants[v].label;
    t.json.push_back(j);
  }
  const Metrics& p = metrics[0];
  const Metrics& u = metrics[1];
  t.notes = fmt::format(
      "At the scenario's defaults (all markers in view, 1 px, IMU attitude from the gravity EKF: "
      "{} deg roll/pitch RMSE) upright-2p has {} cm position RMSE vs pnp's {} cm, max {} vs {} cm, "
      "{} vs {} jumps over 10 cm per run; pnp's own roll/pitch RMSE is {} deg.",
      PixhawkDeg(u.RollPitchRmse()), PixhawkCm(u.PositionRmse()), PixhawkCm(p.PositionRmse()),
      PixhawkCm(u.PositionMax()), PixhawkCm(p.PositionMax()), PixhawkNumber(u.JumpsPerRun(), 1),
      PixhawkNumber(p.JumpsPerRun(), 1), PixhawkDeg(p.RollPitchRmse()));
  return t;
}

// A sweep row: pnp vs upright-2p (and optional extra variants) under one configuration.
struct SweepRow {
  std::string dimension, value;
  Metrics pnp, upright;
  std::vector<std::pair<std::string, Metrics>> extra;
};

std::string Verdict(const Metrics& pnp, const Metrics& upright) {
  const bool accurate = upright.PositionRmse() < pnp.PositionRmse();
  const bool smoother =
      upright.JumpsPerRun() < pnp.JumpsPerRun() ||
      (upright.JumpsPerRun() == pnp.JumpsPerRun() && upright.PositionMax() < pnp.PositionMax());
  if (accurate && smoother) return "upright-2p more accurate and smoother";
  if (accurate) return "upright-2p more accurate";
  if (smoother) return "upright-2p smoother, pnp more accurate";
  return "pnp better";
}

std::vector<SweepRow> PixhawkSweepRows(const PixhawkResults& results) {
  std::vector<SweepRow> rows;
  for (const std::string markers : {"0", "1"}) {
    const auto& m = results.at(SweepAttitudeName(markers));
    for (size_t i = 0; i < kAttitudeErrorsDeg.size(); ++i)
      rows.push_back({fmt::format("IMU attitude error [deg], {} marker(s)", MarkersLabel(markers)),
                      fmt::format("{}", kAttitudeErrorsDeg[i]),
                      m[0],
                      m[i + 1],
                      {}});
  }
  for (const double px : kPixelNoisesPx) {
    const auto& m = results.at(SweepPixelName(px));
    rows.push_back({"pixel noise [px]", fmt::format("{}", px), m[0], m[1], {}});
  }
  for (const auto& markers : kMarkerCounts) {
    const auto& m = results.at(SweepMarkersName(markers));
    rows.push_back({"markers in view", MarkersLabel(markers), m[0], m[1], {}});
  }
  for (const double f : kOutlierFractions) {
    const auto& m = results.at(SweepOutliersName(f));
    rows.push_back({"outlier corners [%]",
                    fmt::format("{}", 100.0 * f),
                    m[0],
                    m[1],
                    {{"upright-2p without RANSAC", m[2]}}});
  }
  return rows;
}

// Where the known vertical stops paying off in RMSE (the largest IMU attitude error at which
// upright-2p is still more accurate than pnp, per marker setting), where upright-2p wins, and the
// outlier rows.
std::string PixhawkSweepNotes(const std::vector<SweepRow>& rows) {
  std::string notes{};
  for (const std::string markers : {"all", "1"}) {
    const std::string factor = fmt::format("IMU attitude error [deg], {} marker(s)", markers);
    std::string last_win = "none", first_loss = "none";
    double pnp_tilt = kNaN;
    for (const auto& r : rows) {
      if (r.dimension != factor) continue;
      pnp_tilt = r.pnp.RollPitchRmse();
      if (r.upright.PositionRmse() < r.pnp.PositionRmse()) {
        if (first_loss == "none") last_win = r.value;
      } else if (first_loss == "none") {
        first_loss = r.value;
      }
    }
    notes += fmt::format(
        "With {} marker(s) in view (pnp's own roll/pitch RMSE {} deg), upright-2p's position "
        "RMSE is below pnp's up to an IMU attitude error of {} deg{}. ",
        markers, PixhawkDeg(pnp_tilt), last_win,
        first_loss == "none" ? " (the whole sweep)" : ", not from " + first_loss + " deg on");
  }
  std::vector<std::string> wins, losses, outliers;
  for (const auto& r : rows) {
    const std::string verdict = Verdict(r.pnp, r.upright);
    if (verdict == "upright-2p more accurate and smoother")
      wins.push_back(r.dimension + " = " + r.value);
    else
      losses.push_back(r.dimension + " = " + r.value + " (" + verdict + ")");
    for (const auto& [name, m] : r.extra)
      outliers.push_back(fmt::format(
          "{} % outliers: pnp {} cm RMSE (max {}), upright-2p with RANSAC {} cm (max {}), "
          "without RANSAC {} cm (max {})",
          r.value, PixhawkCm(r.pnp.PositionRmse()), PixhawkCm(r.pnp.PositionMax()),
          PixhawkCm(r.upright.PositionRmse()), PixhawkCm(r.upright.PositionMax()),
          PixhawkCm(m.PositionRmse()), PixhawkCm(m.PositionMax())));
  }
  return notes + fmt::format(
                     "\n\nupright-2p is more accurate and smoother than pnp at: {}.\n\nNot (or "
                     "only partly) at: {}.\n\nOutliers (20-60 px): {}.",
                     fmt::join(wins, "; "), fmt::join(losses, "; "), fmt::join(outliers, "; "));
}

PixhawkTable Sweep(const PixhawkResults& results) {
  const std::vector<SweepRow> rows = PixhawkSweepRows(results);
  PixhawkTable t{
      ReproTable("sweep", "sweep: where the known vertical helps",
                 {"factor", "value", "pnp RMSE [m]", "upright-2p RMSE [m]", "pnp max [m]",
                  "upright-2p max [m]", "pnp jumps per run", "upright-2p jumps per run",
                  "pnp yaw RMSE [rad]", "upright-2p yaw RMSE [rad]", "verdict"})};
  for (const auto& r : rows) {
    t.table.rows.push_back({r.dimension, r.value, r.pnp.PositionRmse(), r.upright.PositionRmse(),
                            r.pnp.PositionMax(), r.upright.PositionMax(), r.pnp.JumpsPerRun(),
                            r.upright.JumpsPerRun(), r.pnp.YawRmse(), r.upright.YawRmse(),
                            Verdict(r.pnp, r.upright)});
    nlohmann::json j = {{"factor", r.dimension},
                        {"value", r.value},
                        {"pnp", MetricsJson(r.pnp)},
                        {"upright-2p", MetricsJson(r.upright)},
                        {"verdict", Verdict(r.pnp, r.upright)}};
    for (const auto& [name, m] : r.extra) j[name] = MetricsJson(m);
    t.json.push_back(j);
  }
  t.notes = PixhawkSweepNotes(rows);
  return t;
}

PixhawkTable Kf(const PixhawkResults& results) {
  PixhawkTable t{PixhawkMetricTable("kf", "kf: 4 x 1-D constant-velocity Kalman filters",
                                    {"condition", "estimator"},
                                    {"velocity RMSE [m/s]", "rejected or predicted frames"})};
  const auto configs = TableConfigs("kf");
  for (size_t c = 0; c < configs.size(); ++c) {
    const auto& metrics = results.at(configs[c].name);
    for (size_t v = 0; v < configs[c].variants.size(); ++v) {
      const Metrics& m = metrics[v];
      auto row = PixhawkMetricRow({kKfConditions[c].label, configs[c].variants[v].label}, m);
      row.push_back(m.VelocityRmse());
      row.push_back(m.failures);
      t.table.rows.push_back(std::move(row));
      nlohmann::json j = MetricsJson(m);
      j["condition"] = kKfConditions[c].label;
      j["estimator"] = configs[c].variants[v].label;
      t.json.push_back(j);
    }
  }
  t.notes =
      "pixhawk-kf outputs x, y, z, yaw and velocity (its roll/pitch column is the IMU's). "
      "\"rejected or predicted frames\" counts frames without an accepted measurement (no marker, "
      "RANSAC failure, failed roll/pitch check), summed over runs; on those the filter only "
      "predicts.";
  return t;
}

PixhawkTable Timestamps(const PixhawkResults& results) {
  PixhawkTable t{PixhawkMetricTable("timestamps", "timestamps: exposure vs arrival stamps",
                                    {"speed [m/s]", "stamps", "estimator"})};
  const auto configs = TableConfigs("timestamps");
  size_t c = 0;
  for (const double speed : kSpeedsMs) {
    for (const auto& stamp_case : kStampCases) {
      const PixhawkConfig& config = configs[c++];
      const auto& metrics = results.at(config.name);
      for (size_t v = 0; v < config.variants.size(); ++v) {
        t.table.rows.push_back(
            PixhawkMetricRow({speed, stamp_case.label, config.variants[v].label}, metrics[v]));
        nlohmann::json j = MetricsJson(metrics[v]);
        j["speed_m_s"] = speed;
        j["stamps"] = stamp_case.label;
        j["estimator"] = config.variants[v].label;
        t.json.push_back(j);
      }
    }
  }
  t.notes =
      "With arrival stamps the same pipeline reads the IMU attitude 16-19 ms late and labels the "
      "exposure-time pose with the arrival time; subtracting the mean delay removes the constant "
      "part, the +-1.5 ms jitter remains. Errors are against the truth at the output stamp.";
  return t;
}

// One unit: {"variants": [sums of each variant's Metrics]} for the configuration and seed.
nlohmann::json PixhawkUnitResult(const ReproSettings& raw, const std::string& unit, uint64_t seed) {
  const PixhawkSettings settings = ParsePixhawkSettings(raw);
  for (const auto& table : kTableOrder) {
    for (const auto& config : TableConfigs(table)) {
      if (config.name != unit) continue;
      nlohmann::json variants = nlohmann::json::array();
      for (const auto& m : RunConfigOnce(settings, config, seed))
        variants.push_back(ToExactJson(m));
      return {{"variants", variants}};
    }
  }
  throw InputError("repro pixhawk: no unit '" + unit + "'");
}

// Units: (configuration, seed) for every configuration of the selected tables. The scenario
// settings are checked once, before the long runs (the registry's generate also rejects keys the
// scenario does not have).
ReproPlan PlanPixhawk(const ReproSettings& settings, uint64_t) {
  const PixhawkSettings parsed = ParsePixhawkSettings(settings);
  ScenarioOptions check;
  check.settings = parsed.base;
  check.duration_s = parsed.duration_s;
  FindScenario("marker-board-flight")->generate(check);
  ReproPlan plan{{}, settings};
  for (const auto& config : SelectedConfigs(parsed.tables)) plan.units.push_back({config.name});
  return plan;
}

Report SummarizePixhawk(const ReproRuns& runs) {
  const PixhawkSettings settings = ParsePixhawkSettings(runs.settings);
  const std::vector<PixhawkConfig> configs = SelectedConfigs(settings.tables);
  PixhawkResults results;  // the runs' sums, added in seed order
  for (size_t c = 0; c < configs.size(); ++c) {
    auto& total = results[configs[c].name];
    total.resize(configs[c].variants.size());
    for (const auto& result : runs.results[c])
      for (size_t v = 0; v < total.size(); ++v)
        total[v].Add(FromExactJson<Metrics>(result.at("variants").at(v)));
  }
  std::vector<PixhawkTable> tables;
  if (settings.tables.count("fig15")) tables.push_back(Fig15(results));
  if (settings.tables.count("sweep")) tables.push_back(Sweep(results));
  if (settings.tables.count("kf")) tables.push_back(Kf(results));
  if (settings.tables.count("timestamps")) tables.push_back(Timestamps(results));

  Report report;
  report.title = "PIXHAWK marker localization (Meier et al., Autonomous Robots 2012)";
  report.provenance.input = "marker-board-flight";
  report.sections.push_back(
      {"Setup",
       fmt::format(
           "Scenario marker-board-flight, {} run(s) per configuration, seeds {}{}.\n\n", runs.runs,
           runs.Seeds(),
           settings.duration_s ? fmt::format(", flight cut at {} s", *settings.duration_s) : "") +
           "Metrics pooled over every output frame of every run: position error |p_est - "
           "p_true| (truth interpolated at the output stamp, no alignment), RMSE and max; jumps: "
           "consecutive outputs whose position error changes by more than 10 cm (per run); yaw "
           "and roll/pitch RMSE. The paper gives fig. 15 as a plot only (no numbers): the "
           "comparison is qualitative (upright-2p smoother and more accurate, no large jumps).\n"});
  report.sections.back().before_tables = true;
  for (auto& t : tables) {
    report.sections.push_back({t.table.title, t.notes + "\n"});
    report.details["tables"][t.table.name] = {{"rows", t.json}};
    report.files[t.table.name + ".csv"] = ReproTableCsv(t.table);
    report.tables.push_back(std::move(t.table));
  }
  return report;
}

}  // namespace

ReproDefinition PixhawkRepro() {
  return {.name = "pixhawk",
          .description = "PIXHAWK fig. 15 (pnp vs upright-2p), sweep, 4 x 1-D KF, time stamps",
          .paper = "Meier et al., PIXHAWK, Autonomous Robots 2012, sections 3.2-3.3, 5.1, 7.1-7.2",
          .default_runs = kPixhawkDefaultRuns,
          .plan = PlanPixhawk,
          .unit = PixhawkUnitResult,
          .summarize = SummarizePixhawk};
}

}  // namespace mavloc
