#include "evaluation/eval/eval_report.h"

#include <fmt/format.h>

#include <cmath>
#include <iterator>
#include <numeric>
#include <stdexcept>

#include "datasets/io/tum_io.h"
#include "evaluation/report/latex.h"
#include "evaluation/report/report_protocol.h"

namespace mavloc {

namespace {

nlohmann::json StatsJsonOf(const ErrorStatistics& s) {
  return {{"rmse", s.rmse}, {"mean", s.mean}, {"median", s.median}, {"std", s.std},
          {"min", s.min},   {"max", s.max},   {"sse", s.sse},       {"count", s.count}};
}

constexpr double kRadPerDeg = M_PI / 180.0;

// The evo-exact engine states rotation errors in degrees, as evo does; report.json holds radians.
ErrorStatistics DegreesToRadians(ErrorStatistics s) {
  for (double* v : {&s.rmse, &s.mean, &s.median, &s.std, &s.min, &s.max}) *v *= kRadPerDeg;
  s.sse *= kRadPerDeg * kRadPerDeg;
  return s;
}

nlohmann::json AngleStatsJson(const ErrorStatistics& degrees) {
  return StatsJsonOf(DegreesToRadians(degrees));
}

struct RunAggregate {
  double mean = 0.0;
  double std = 0.0;  // sample standard deviation (n - 1); 0 for one run
  size_t n = 0;
};

RunAggregate SummariseRuns(const std::vector<double>& values) {
  RunAggregate a;
  a.n = values.size();
  if (values.empty()) return a;
  a.mean = std::accumulate(values.begin(), values.end(), 0.0) / static_cast<double>(a.n);
  if (a.n > 1) {
    double ss = 0.0;
    for (double v : values) ss += (v - a.mean) * (v - a.mean);
    a.std = std::sqrt(ss / static_cast<double>(a.n - 1));
  }
  return a;
}

std::string SigDigits(double value) {
  if (!std::isfinite(value)) return "-";
  return fmt::format("{:.4g}", value);
}

std::string RunCell(const RunAggregate& a, const char* plus_minus) {
  if (a.n == 0 || !std::isfinite(a.mean)) return "-";
  if (a.n == 1) return SigDigits(a.mean);
  return SigDigits(a.mean) + plus_minus + SigDigits(a.std);
}

std::string RpeTitle(const RpeDelta& d) {
  const double delta = d.delta;
  const std::string unit = d.unit == DeltaUnit::kFrames   ? "f"
                           : d.unit == DeltaUnit::kMetres ? "m"
                                                          : "s";
  return fmt::format("{:g} {}{}", delta, unit, d.all_pairs ? ", all pairs" : "");
}

std::string RelationUnit(PoseRelation relation) {
  switch (relation) {
    case PoseRelation::kTranslation:
      return "m";
    case PoseRelation::kRotationAngleDeg:
      return "deg";
    default:
      return "-";
  }
}

const ErrorStatistics& RelationStats(const TrajectoryEvaluation& e, PoseRelation relation) {
  switch (relation) {
    case PoseRelation::kRotationAngleDeg:
      return e.ape_rotation_deg;
    case PoseRelation::kRotationPart:
      return e.ape_rotation_part;
    case PoseRelation::kFull:
      return e.ape_full;
    default:
      return e.ape_translation_m;
  }
}

// All segments of all lengths pooled (the KITTI benchmark averages every segment error).
void PooledRelative(const TrajectoryEvaluation& e, double* translation_pct,
                    double* rotation_deg_m) {
  double t_sum = 0.0, r_sum = 0.0;
  size_t n = 0;
  for (const auto& length : e.relative) {
    if (length.count() == 0) continue;
    const double count = static_cast<double>(length.count());
    t_sum += length.translation_percent_stats.mean * count;
    r_sum += length.rotation_deg_per_m_stats.mean * count;
    n += length.count();
  }
  *translation_pct = n == 0 ? std::nan("") : t_sum / static_cast<double>(n);
  *rotation_deg_m = n == 0 ? std::nan("") : r_sum / static_cast<double>(n);
}

std::string AssociationText(const EvaluationProtocol& p, bool any_by_index) {
  std::string text =
      p.association == AssociationMode::kNearest
          ? fmt::format(
                "nearest ground-truth stamp within {:g} s (evo's matching_time_indices: "
                "the first of equal stamps)",
                p.max_dt_s)
          : fmt::format(
                "ground truth interpolated at each estimate stamp (positions linear, "
                "rotations slerp) when a ground-truth sample is within {:g} s",
                p.max_dt_s);
  text += fmt::format("; time offset {:g} s added to the estimate's stamps", p.time_offset_s);
  if (any_by_index) text += "; KITTI files without times: by index, as evo does";
  return text;
}

std::string AlignmentText(const EvaluationProtocol& p) {
  if (p.align_origin)
    return "origin (evo --align_origin): S = T_gt,0 T_est,0^-1 makes the first associated poses "
           "coincide";
  std::string text = AlignmentModeName(p.alignment);
  text += p.alignment == AlignmentMode::kSe3    ? " (Umeyama, rotation + translation)"
          : p.alignment == AlignmentMode::kSim3 ? " (Umeyama, rotation + translation + scale)"
          : p.alignment == AlignmentMode::kPosYaw
              ? " (4-DoF: translation + rotation about gravity z, as OpenVINS ov_eval)"
              : " (identity)";
  text += p.n_to_align < 0
              ? ", estimated on all associated pairs"
              : fmt::format(", estimated on the first {} associated pairs", p.n_to_align);
  return text;
}

std::string RpeDefinition() {
  return "RPE (evo_rpe): E_ij = (T_gt,i^-1 T_gt,j)^-1 (T_est,i^-1 T_est,j) over the index pairs "
         "(i, j) that evo/core/filters.py selects for the delta (frames: ids 0, d, 2d, ...; metres "
         "or seconds: successive indices once the path length or time since the last reaches d; "
         "all pairs: every i with its j); translation ||t(E)|| [m], rotation angle(R(E)) [deg]";
}

std::string RelativeDefinition() {
  return "relative error over sub-trajectories (rpg_trajectory_evaluation, KITTI): from every "
         "associated frame i, the frame j whose distance along the ground truth is closest to "
         "dist(i) + d (within 20 % of d); translation error ||t(E)|| / d in %, rotation error "
         "angle(E) / d in deg/m, E = (T_gt,i^-1 T_gt,j)^-1 (T_est,i^-1 T_est,j); the table pools "
         "every segment of every length (the KITTI average)";
}

std::string InputNote(const TrajectoryReadReport& r) {
  std::vector<std::string> notes;
  if (r.duplicates_dropped > 0)
    notes.push_back(fmt::format("{} repeated-stamp row{} dropped, first at line {}",
                                r.duplicates_dropped, r.duplicates_dropped == 1 ? "" : "s",
                                r.first_duplicate_line));
  if (r.sorted)
    notes.push_back(fmt::format("sorted (--sort): {} rows out of order{}", r.rows_out_of_order,
                                r.rows_out_of_order > 0
                                    ? fmt::format(", first at line {}", r.first_out_of_order_line)
                                    : std::string()));
  if (r.quaternions_normalised > 0)
    notes.push_back(fmt::format("{} rotations normalised (max | |q| - 1 | = {:.2g})",
                                r.quaternions_normalised, r.max_quaternion_norm_error));
  std::string text;
  for (const auto& n : notes) text += (text.empty() ? "" : "; ") + n;
  return text.empty() ? "-" : text;
}

nlohmann::json InputJson(const TrajectoryReadReport& r) {
  return {{"file", r.path},
          {"format", TrajectoryFormatName(r.format)},
          {"format_forced", r.format_forced},
          {"layout", r.layout},
          {"times_file", r.times_path},
          {"has_stamps", r.has_stamps},
          {"rows", r.rows},
          {"duplicates_dropped", r.duplicates_dropped},
          {"first_duplicate_line", r.first_duplicate_line},
          {"sorted", r.sorted},
          {"rows_out_of_order", r.rows_out_of_order},
          {"first_out_of_order_line", r.first_out_of_order_line},
          {"quaternions_normalised", r.quaternions_normalised},
          {"max_quaternion_norm_error", r.max_quaternion_norm_error},
          {"utf8_bom", r.had_bom},
          {"crlf", r.had_crlf}};
}

struct EvalTable {
  std::vector<std::string> titles;              // metric titles
  std::vector<std::string> keys;                // metric keys
  std::vector<std::vector<RunAggregate>> rows;  // per estimate, per metric
};

EvalTable BuildTable(const EvalReport& report) {
  EvalTable table;
  for (const auto& estimate : report.estimates) {
    std::vector<std::vector<double>> columns;
    for (const auto& run : estimate.runs) {
      const auto metrics = RunMetrics(run, report.protocol);
      if (table.titles.empty())
        for (const auto& m : metrics) {
          table.titles.push_back(m.title);
          table.keys.push_back(m.key);
        }
      columns.resize(metrics.size());
      for (size_t k = 0; k < metrics.size() && k < columns.size(); ++k)
        if (std::isfinite(metrics[k].value))
          columns[k].push_back(metrics[k].value * metrics[k].display_scale);
    }
    std::vector<RunAggregate> row;
    for (const auto& c : columns) row.push_back(SummariseRuns(c));
    table.rows.push_back(row);
  }
  return table;
}

std::string MarkdownTableText(const EvalReport& report) {
  const EvalTable table = BuildTable(report);
  std::string text = "| estimate | runs |";
  std::string rule = "| --- | ---: |";
  for (const auto& t : table.titles) {
    text += " " + t + " |";
    rule += " ---: |";
  }
  text += "\n" + rule + "\n";
  for (size_t e = 0; e < report.estimates.size(); ++e) {
    text += fmt::format("| {} | {} |", report.estimates[e].label, report.estimates[e].runs.size());
    for (const auto& a : table.rows[e]) text += fmt::format(" {} |", RunCell(a, " ± "));
    text += "\n";
  }
  return text;
}

std::vector<std::string> ProtocolLines(const EvalReport& report) {
  bool any_by_index = false;
  for (const auto& e : report.estimates)
    for (const auto& r : e.runs) any_by_index |= r.by_index;
  const EvaluationProtocol& p = report.protocol;
  std::vector<std::string> lines;
  lines.push_back("alignment: " + AlignmentText(p));
  lines.push_back("association: " + AssociationText(p, any_by_index));
  lines.push_back("APE (evo_ape): E_i = T_gt,i^-1 S T_est,i; headline pose relation " +
                  PoseRelationName(p.ape_relation) +
                  "; translation ||p_est' - p_gt|| [m], rotation angle(R_E) [deg]; statistics "
                  "over pairs as evo (rmse, mean, median, population std, min, max)");
  std::string deltas;
  for (const auto& d : p.rpe_deltas) deltas += (deltas.empty() ? "" : "; ") + RpeTitle(d);
  lines.push_back(RpeDefinition() + "; deltas: " + deltas);
  std::string lengths;
  for (double l : p.relative_lengths_m)
    lengths += (lengths.empty() ? "" : ", ") + fmt::format("{:g}", l);
  lines.push_back(RelativeDefinition() + "; lengths [m]: " + lengths +
                  (report.relative_lengths_given
                       ? " (given)"
                       : " (default: floor of 10, 20, 30, 40, 50 % of the ground truth's path "
                         "length, rpg's rule; the same lengths for every estimate)"));
  lines.push_back(
      "yaw drift: least-squares slope of the unwrapped yaw error against the ground "
      "truth's path length [deg/m]");
  lines.push_back("runs: mean ± sample standard deviation (n - 1) over the runs of a folder");
  lines.push_back(fmt::format("ground truth: {} ({}{}), {} poses; {}", report.truth.path,
                              report.truth.layout, report.truth.format_forced ? ", forced" : "",
                              report.truth_poses.size(), InputNote(report.truth)));
  return lines;
}

}  // namespace

std::vector<MetricValue> RunMetrics(const EvalRun& run, const EvaluationProtocol& protocol) {
  const TrajectoryEvaluation& e = run.evaluation;
  std::vector<MetricValue> m;
  m.push_back({"pairs", "pairs", static_cast<double>(e.pair_count)});
  if (protocol.ape_relation != PoseRelation::kTranslation &&
      protocol.ape_relation != PoseRelation::kRotationAngleDeg)
    m.push_back({"ape_" + PoseRelationName(protocol.ape_relation) + "_rmse",
                 "APE " + PoseRelationName(protocol.ape_relation) + " RMSE [" +
                     RelationUnit(protocol.ape_relation) + "]",
                 RelationStats(e, protocol.ape_relation).rmse});
  m.push_back({"ape_translation_rmse_m", "APE trans. RMSE [m]", e.ape_translation_m.rmse});
  m.push_back({"ape_rotation_rmse_rad", "APE rot. RMSE [deg]", e.ape_rotation_deg.rmse * kRadPerDeg,
               1.0 / kRadPerDeg});
  for (size_t k = 0; k < protocol.rpe_deltas.size(); ++k) {
    const std::string title = RpeTitle(protocol.rpe_deltas[k]);
    const bool has = k < e.rpe.size();
    m.push_back({fmt::format("rpe{}_translation_rmse_m", k), "RPE " + title + " trans. RMSE [m]",
                 has ? e.rpe[k].translation_m.rmse : std::nan("")});
    m.push_back({fmt::format("rpe{}_rotation_rmse_rad", k), "RPE " + title + " rot. RMSE [deg]",
                 has ? e.rpe[k].rotation_deg.rmse * kRadPerDeg : std::nan(""), 1.0 / kRadPerDeg});
  }
  double t_pct = 0.0, r_deg_m = 0.0;
  PooledRelative(e, &t_pct, &r_deg_m);
  m.push_back({"relative_translation_pct", "rel. trans. [%]", t_pct});
  m.push_back(
      {"relative_rotation_rad_per_m", "rel. rot. [deg/m]", r_deg_m * kRadPerDeg, 1.0 / kRadPerDeg});
  m.push_back({"yaw_drift_rad_per_m", "yaw drift [deg/m]",
               e.yaw_drift.valid ? e.yaw_drift.rate_deg_per_m * kRadPerDeg : std::nan(""),
               1.0 / kRadPerDeg});
  if (protocol.alignment == AlignmentMode::kSim3)
    m.push_back({"sim3_scale", "Sim3 scale", e.alignment.scale});
  return m;
}

std::string EstimateFileName(const EvalEstimate& estimate, const EvalRun& run) {
  return run.run > 0 ? fmt::format("estimate_{}_run{}.tum", estimate.label, run.run)
                     : fmt::format("estimate_{}.tum", estimate.label);
}

std::string EvalSummaryTable(const EvalReport& report) { return MarkdownTableText(report); }

std::string EvalMarkdown(const EvalReport& report) {
  std::string md = "# mavloc eval\n\n";
  md += MarkdownTableText(report);
  md += "\n## Protocol\n\n";
  for (const auto& line : ProtocolLines(report)) md += "- " + line + "\n";
  md +=
      "\n## Inputs\n\n| estimate | run | file | format | poses | pairs | aligned on | notes |\n"
      "| --- | ---: | --- | --- | ---: | ---: | ---: | --- |\n";
  for (const auto& e : report.estimates)
    for (const auto& r : e.runs)
      md += fmt::format("| {} | {} | {} | {} | {} | {} | {} | {} |\n", e.label, r.run, r.file,
                        r.input.layout + (r.input.format_forced ? ", forced" : ""),
                        r.evaluation.estimate_count, r.evaluation.pair_count,
                        r.evaluation.aligned_pairs, InputNote(r.input));
  md +=
      "\n## Relative error per length (mean over segments; ± over runs)\n\n"
      "| estimate | length [m] | segments | trans. [%] | rot. [deg/m] |\n"
      "| --- | ---: | ---: | ---: | ---: |\n";
  for (const auto& e : report.estimates) {
    for (size_t k = 0; k < report.protocol.relative_lengths_m.size(); ++k) {
      std::vector<double> t, r;
      size_t segments = 0;
      for (const auto& run : e.runs) {
        if (k >= run.evaluation.relative.size()) continue;
        const auto& rel = run.evaluation.relative[k];
        segments += rel.count();
        if (rel.count() == 0) continue;
        t.push_back(rel.translation_percent_stats.mean);
        r.push_back(rel.rotation_deg_per_m_stats.mean);
      }
      md += fmt::format("| {} | {:g} | {} | {} | {} |\n", e.label,
                        report.protocol.relative_lengths_m[k], segments,
                        RunCell(SummariseRuns(t), " ± "), RunCell(SummariseRuns(r), " ± "));
    }
  }
  std::string diagnostics;
  for (const auto& e : report.estimates)
    for (const auto& r : e.runs)
      for (const auto& message : r.evaluation.diagnostics.Messages())
        diagnostics += fmt::format("- {}{}: {}\n", e.label,
                                   r.run > 0 ? fmt::format(" run {}", r.run) : "", message);
  md += "\n## Diagnostics\n\n" + (diagnostics.empty() ? "None detected.\n" : diagnostics);
  return md;
}

std::string EvalLatex(const EvalReport& report) {
  const EvalTable table = BuildTable(report);
  // One 'r' column per metric; plain \\hline rules (no package needed).
  std::string tex =
      "% mavloc eval: mean $\\pm$ sample std over runs (protocol in "
      "report.md)\n\\begin{tabular}{lr";
  for (size_t k = 0; k < table.titles.size(); ++k) tex += "r";
  tex += "}\n\\hline\nestimate & runs";
  for (const auto& t : table.titles) tex += " & " + LatexEscape(t);
  tex += " \\\\\n\\hline\n";
  for (size_t e = 0; e < report.estimates.size(); ++e) {
    tex += LatexEscape(report.estimates[e].label) +
           fmt::format(" & {}", report.estimates[e].runs.size());
    for (const auto& a : table.rows[e]) {
      const std::string cell = RunCell(a, " \\pm ");
      tex += " & " + (a.n > 1 ? "$" + cell + "$" : cell);
    }
    tex += " \\\\\n";
  }
  tex += "\\hline\n\\end{tabular}\n";
  return tex;
}

nlohmann::json EvalJson(const EvalReport& report) {
  const EvaluationProtocol& p = report.protocol;
  bool any_by_index = false;
  for (const auto& e : report.estimates)
    for (const auto& r : e.runs) any_by_index |= r.by_index;
  nlohmann::json j;
  j["tool"] = "mavloc eval";
  j["report_kind"] = "eval";
  nlohmann::json deltas = nlohmann::json::array();
  for (const auto& d : p.rpe_deltas)
    deltas.push_back({{"delta", d.delta},
                      {"unit", DeltaUnitName(d.unit)},
                      {"all_pairs", d.all_pairs},
                      {"rel_delta_tol", d.rel_delta_tol}});
  j["protocol"] = {
      {"alignment",
       {{"mode", AlignmentModeName(p.alignment)},
        {"n_to_align", p.n_to_align},
        {"align_origin", p.align_origin},
        {"description", AlignmentText(p)}}},
      {"association",
       {{"method", any_by_index                                 ? "index"
                   : p.association == AssociationMode::kNearest ? "nearest"
                                                                : "interpolated"},
        {"max_diff_s", p.max_dt_s},
        {"time_offset_s", p.time_offset_s},
        {"description", AssociationText(p, any_by_index)}}},
      {"ape", {{"pose_relation", PoseRelationName(p.ape_relation)}}},
      {"rpe", {{"deltas", deltas}, {"definition", RpeDefinition()}}},
      {"relative_error",
       {{"lengths_m", p.relative_lengths_m},
        {"lengths_given", report.relative_lengths_given},
        {"max_length_diff_fraction", p.max_length_diff_fraction},
        {"definition", RelativeDefinition()}}},
      {"runs_statistics", "mean and sample standard deviation (n - 1) over runs"},
      {"errors_over_time_t_s", "seconds since the ground truth's first stamp"},
  };
  j["truth"] = InputJson(report.truth);
  j["truth"]["poses"] = report.truth_poses.size();
  j["estimates"] = nlohmann::json::array();
  for (const auto& estimate : report.estimates) {
    nlohmann::json e;
    e["label"] = estimate.label;
    e["source"] = estimate.source;
    e["kind"] = estimate.is_folder ? "runs" : "file";
    e["runs"] = nlohmann::json::array();
    std::map<std::string, std::vector<double>> values;
    std::vector<std::string> order;
    for (const auto& run : estimate.runs) {
      const TrajectoryEvaluation& ev = run.evaluation;
      nlohmann::json r;
      r["run"] = run.run;
      r["file"] = run.file;
      r["input"] = InputJson(run.input);
      r["association"] = run.by_index ? "index" : "stamps";
      r["estimate_file"] = EstimateFileName(estimate, run);
      r["poses"] = ev.estimate_count;
      r["pairs"] = ev.pair_count;
      r["aligned_pairs"] = ev.aligned_pairs;
      r["truth_path_length_m"] = ev.truth_path_length_m;
      r["duration_s"] = ev.duration_s;
      const Eigen::Matrix3d& R = ev.alignment.R;
      r["alignment"] = {
          {"scale", ev.alignment.scale},
          {"R",
           {{R(0, 0), R(0, 1), R(0, 2)}, {R(1, 0), R(1, 1), R(1, 2)}, {R(2, 0), R(2, 1), R(2, 2)}}},
          {"t", {ev.alignment.t.x(), ev.alignment.t.y(), ev.alignment.t.z()}}};
      r["ape"] = {{"translation_m", StatsJsonOf(ev.ape_translation_m)},
                  {"rotation_rad", AngleStatsJson(ev.ape_rotation_deg)},
                  {"rotation_part", StatsJsonOf(ev.ape_rotation_part)},
                  {"full", StatsJsonOf(ev.ape_full)}};
      r["rpe"] = nlohmann::json::array();
      for (const auto& rpe : ev.rpe)
        r["rpe"].push_back({{"delta", rpe.delta.delta},
                            {"unit", DeltaUnitName(rpe.delta.unit)},
                            {"all_pairs", rpe.delta.all_pairs},
                            {"translation_m", StatsJsonOf(rpe.translation_m)},
                            {"rotation_rad", AngleStatsJson(rpe.rotation_deg)},
                            {"rotation_part", StatsJsonOf(rpe.rotation_part)},
                            {"full", StatsJsonOf(rpe.full)}});
      r["relative"] = nlohmann::json::array();
      for (const auto& rel : ev.relative)
        r["relative"].push_back(
            {{"length_m", rel.length_m},
             {"segments", rel.count()},
             {"translation_m", StatsJsonOf(rel.translation_m_stats)},
             {"translation_percent", StatsJsonOf(rel.translation_percent_stats)},
             {"rotation_rad", AngleStatsJson(rel.rotation_deg_stats)},
             {"rotation_rad_per_m", AngleStatsJson(rel.rotation_deg_per_m_stats)},
             {"yaw_rad", AngleStatsJson(rel.yaw_deg_stats)},
             {"tilt_rad", AngleStatsJson(rel.tilt_deg_stats)}});
      r["yaw_drift"] = {{"valid", ev.yaw_drift.valid},
                        {"rad_per_m", ev.yaw_drift.rate_deg_per_m * kRadPerDeg},
                        {"rad_per_s", ev.yaw_drift.rate_deg_per_s * kRadPerDeg},
                        {"final_rad", ev.yaw_drift.final_deg * kRadPerDeg}};
      r["diagnostics"] = ev.diagnostics.Messages();
      nlohmann::json metrics;
      for (const auto& m : RunMetrics(run, report.protocol)) {
        metrics[m.key] = std::isfinite(m.value) ? nlohmann::json(m.value) : nlohmann::json();
        if (!values.count(m.key)) order.push_back(m.key);
        if (std::isfinite(m.value)) values[m.key].push_back(m.value);
      }
      r["metrics"] = metrics;
      e["runs"].push_back(r);
    }
    nlohmann::json summary;
    for (const auto& key : order) {
      const RunAggregate a = SummariseRuns(values[key]);
      summary[key] = {{"mean", a.mean}, {"std", a.std}, {"runs", a.n}};
    }
    e["summary"] = summary;
    j["estimates"].push_back(e);
  }
  // One estimate, one run: also the top-level keys of the single-file `mavloc eval --json` output
  // (pairs, align, ate, ate_rotation), which scripts read.
  if (report.estimates.size() == 1 && report.estimates[0].runs.size() == 1) {
    const TrajectoryEvaluation& ev = report.estimates[0].runs[0].evaluation;
    j["pairs"] = ev.pair_count;
    j["align"] = AlignmentModeName(p.alignment);
    j["ate"] = StatsJsonOf(ev.ape_translation_m);
    j["ate"]["unit"] = "m";
    j["ate_rotation"] = AngleStatsJson(ev.ape_rotation_deg);
    j["ate_rotation"]["unit"] = "rad";
  }
  j["protocol_lines"] = ProtocolLines(report);
  return j;
}

namespace {

// One estimator result per run: the ATE and RPE of the one trajectory-error engine in SI units,
// the coverage of the run's estimate, its diagnostics as warnings.
EstimatorResult ResultOfRun(const EvalEstimate& estimate, const EvalRun& run) {
  const TrajectoryEvaluation& ev = run.evaluation;
  EstimatorResult r;
  r.name = estimate.label + (run.run > 0 ? fmt::format(" run {}", run.run) : "");
  Coverage coverage;
  coverage.pairs = ev.pair_count;
  coverage.estimate_poses = ev.estimate_count;
  coverage.overlap_s = ev.duration_s;
  coverage.estimate_span_s = run.estimate_span_s;
  r.coverage = coverage;
  r.metrics["ate_translation"] = {"m", std::nullopt, ev.ape_translation_m};
  r.metrics["ate_rotation"] = {"rad", std::nullopt, DegreesToRadians(ev.ape_rotation_deg)};
  for (const auto& rpe : ev.rpe) {
    const std::string key =
        fmt::format("rpe_{:g}_{}", rpe.delta.delta, DeltaUnitName(rpe.delta.unit));
    r.metrics[key + "_translation"] = {"m", std::nullopt, rpe.translation_m};
    r.metrics[key + "_rotation"] = {"rad", std::nullopt, DegreesToRadians(rpe.rotation_deg)};
  }
  for (const auto& rel : ev.relative)
    if (rel.count() > 0)
      r.metrics[fmt::format("relative_translation_{:g}m", rel.length_m)] = {
          "%", std::nullopt, rel.translation_percent_stats};
  r.warnings = ev.diagnostics.Messages();
  if (coverage.estimate_span_s > 0.0 && coverage.Fraction() < kLowCoverageFraction)
    r.warnings.push_back(fmt::format(
        "the ground truth covers only {:.1f} of the estimate's {:.1f} s ({} of {} poses): the "
        "numbers describe that part alone",
        coverage.overlap_s, coverage.estimate_span_s, coverage.pairs, coverage.estimate_poses));
  return r;
}

}  // namespace

Report EvalModel(const EvalReport& report) {
  const EvaluationProtocol& p = report.protocol;
  bool any_by_index = false;
  int runs = 0;
  for (const auto& e : report.estimates)
    for (const auto& r : e.runs) {
      any_by_index |= r.by_index;
      ++runs;
    }
  Report model;
  model.kind = "eval";
  model.title = "mavloc eval";
  model.provenance.input = report.truth.path;
  model.provenance.runs = runs;
  model.protocol = ReportProtocolOf(p, any_by_index);
  for (const auto& e : report.estimates)
    for (const auto& r : e.runs) model.estimators.push_back(ResultOfRun(e, r));
  std::string body = EvalMarkdown(report);
  body = body.substr(body.find('\n') + 1);  // the title is the report's
  model.sections.push_back({"Per estimate", body});
  model.details = EvalJson(report);
  if (report.protocol.keep_series) {
    model.files = EvalReportFiles(report);
  } else {
    for (const std::string& name : EvalReportFileNames(report)) model.files[name];
  }
  return model;
}

std::vector<std::string> EvalReportFileNames(const EvalReport& report) {
  std::vector<std::string> names = {"eval.tex", "truth.tum", "errors_over_time.csv",
                                    "relative_errors.csv"};
  for (const auto& estimate : report.estimates)
    for (const auto& run : estimate.runs) names.push_back(EstimateFileName(estimate, run));
  return names;
}

std::map<std::string, std::string> EvalReportFiles(const EvalReport& report) {
  if (!report.protocol.keep_series)
    throw std::logic_error(
        "the eval report's files need the runs' series: evaluate with EvalOutputs::report_folder");
  std::map<std::string, std::string> files;
  files["eval.tex"] = EvalLatex(report);
  files["truth.tum"] = TumTrajectoryText(report.truth_poses);
  const TimeNs t0 = report.truth_poses.empty() ? 0 : report.truth_poses.front().t_ns;
  std::string over_time = "label,run,t_s,translation_error_m,rotation_error_deg\n";
  std::string relative = "label,run,length_m,translation_error_pct,rotation_error_deg_per_m\n";
  // Rows formatted in place at the end of each text (no string per row).
  auto over_time_out = std::back_inserter(over_time);
  auto relative_out = std::back_inserter(relative);
  for (const auto& estimate : report.estimates) {
    for (const auto& run : estimate.runs) {
      files[EstimateFileName(estimate, run)] = TumTrajectoryText(run.aligned_estimate);
      const TrajectoryEvaluation& ev = run.evaluation;
      for (size_t i = 0; i < ev.pair_t_ns.size() && i < ev.ape.translation_m.size(); ++i)
        fmt::format_to(over_time_out, "{},{},{:.9f},{:.9g},{:.9g}\n", estimate.label, run.run,
                       NsToSeconds(ev.pair_t_ns[i] - t0), ev.ape.translation_m[i],
                       i < ev.ape.rotation_deg.size() ? ev.ape.rotation_deg[i] : 0.0);
      for (const auto& rel : ev.relative)
        for (size_t s = 0; s < rel.count(); ++s)
          fmt::format_to(relative_out, "{},{},{:g},{:.9g},{:.9g}\n", estimate.label, run.run,
                         rel.length_m, rel.translation_percent[s], rel.rotation_deg_per_m[s]);
    }
  }
  files["errors_over_time.csv"] = std::move(over_time);
  files["relative_errors.csv"] = std::move(relative);
  return files;
}

}  // namespace mavloc
