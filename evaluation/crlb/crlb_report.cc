#include "evaluation/crlb/crlb_report.h"

#include <fmt/format.h>

#include <cmath>
#include <exception>

#include "core/rotation.h"
#include "evaluation/crlb/efficiency.h"
#include "evaluation/report_writer.h"
#include "solver/smoother/smoother_initialization.h"

namespace mavloc {

namespace {
const std::vector<std::string> kNames = {"x",  "y",   "z",   "roll", "pitch", "yaw", "vx", "vy",
                                         "vz", "bgx", "bgy", "bgz",  "bax",   "bay", "baz"};
}  // namespace

std::vector<std::pair<std::string, double>> BoundQuantityRms(const SmootherCrlb& bound,
                                                             bool filtering) {
  std::vector<double> sum(kNames.size(), 0.0);
  int n = 0;
  for (const CrlbKeyframe& kf : bound.keyframes) {
    const Matrix15d* C = filtering ? (kf.filtering ? &*kf.filtering : nullptr) : &kf.smoothing;
    if (!C) continue;
    const CrlbSigmas s = SigmasOf(*C, kf.T_W_B.q);
    for (int i = 0; i < 3; ++i) {
      sum[i] += s.xyz_m[i] * s.xyz_m[i];
      sum[3 + i] += s.rpy_rad[i] * s.rpy_rad[i];
      sum[6 + i] += s.v_m_s[i] * s.v_m_s[i];
      sum[9 + i] += s.b_g_rad_s[i] * s.b_g_rad_s[i];
      sum[12 + i] += s.b_a_m_s2[i] * s.b_a_m_s2[i];
    }
    ++n;
  }
  std::vector<std::pair<std::string, double>> out;
  for (size_t i = 0; i < kNames.size(); ++i)
    out.emplace_back(kNames[i], n > 0 ? std::sqrt(sum[i] / n) : std::nan(""));
  return out;
}

CrlbReport MakeCrlbReport(const Dataset& dataset,
                          const std::vector<EstimatorEvaluation>& evaluations,
                          const EstimatorOptions& smoother_options) {
  CrlbReport report;
  SmootherCrlb bound;
  try {
    bound = ComputeSmootherCrlb(dataset, smoother_options);
  } catch (const std::exception& e) {  // e.g. smoother options the bound cannot read
    bound.reason = e.what();
  }
  if (!bound.ok) {
    report.reason = bound.reason;
    report.json = {{"available", false}, {"reason", bound.reason}};
    report.markdown = "## Cramér–Rao bound\n\nNot available: " + bound.reason + ".\n";
    return report;
  }
  report.available = true;
  // Per-quantity bounds (display units: mm, deg, mm/s, deg/s, mm/s^2).
  const auto smoothing = BoundQuantityRms(bound, false);
  const auto filtering = BoundQuantityRms(bound, true);
  const auto scale = [](size_t i) {
    return i < 3 ? 1e3 : i < 6 ? 1.0 / kDeg : i < 9 ? 1e3 : i < 12 ? 1.0 / kDeg : 1e3;
  };
  std::vector<std::string> header = {"bound"};
  for (size_t i = 0; i < kNames.size(); ++i) header.push_back(kNames[i]);
  std::vector<std::vector<std::string>> quantity_rows;
  nlohmann::json qj;
  for (const auto& [label, values] :
       {std::pair{"smoothing", &smoothing}, std::pair{"filtering", &filtering}}) {
    std::vector<std::string> row = {label};
    for (size_t i = 0; i < values->size(); ++i) {
      row.push_back(FormatNumber((*values)[i].second * scale(i), 3));
      qj[label][(*values)[i].first] = (*values)[i].second;
    }
    quantity_rows.push_back(row);
  }
  // Efficiency per estimator.
  std::vector<std::vector<std::string>> rows;
  nlohmann::json ej = nlohmann::json::object();
  for (const EstimatorEvaluation& e : evaluations) {
    if (!e.ran) continue;
    const std::vector<StampedPose> poses = SeedPoses(e.estimate);
    if (poses.empty()) continue;
    const bool smoother = e.estimator == "smoother";
    const EfficiencySums s =
        CompareWithBound(bound, poses, smoother ? BoundKind::kSmoothing : BoundKind::kFiltering);
    if (s.frames == 0) continue;
    rows.push_back({e.estimator, smoother ? "smoothing" : "filtering",
                    FormatNumber(1e3 * s.PositionBoundRms(), 3), FormatNumber(s.PositionRatio(), 3),
                    FormatNumber(s.AttitudeBoundRms() / kDeg, 4),
                    FormatNumber(s.AttitudeRatio(), 3), std::to_string(s.frames)});
    ej[e.estimator] = {{"bound", smoother ? "smoothing" : "filtering"},
                       {"position_bound_rms_m", s.PositionBoundRms()},
                       {"position_rmse_over_bound", s.PositionRatio()},
                       {"attitude_bound_rms_deg", s.AttitudeBoundRms() / kDeg},
                       {"attitude_rmse_over_bound", s.AttitudeRatio()},
                       {"keyframes", s.frames}};
  }
  const std::string quantity_table = MarkdownTable(header, quantity_rows);
  const std::string efficiency_table =
      MarkdownTable({"estimator", "bound", "position bound [mm]", "position RMSE / bound",
                     "attitude bound [deg]", "attitude RMSE / bound", "keyframes"},
                    rows);
  const std::string intro = fmt::format(
      "Cramér–Rao bound of the smoother's batch problem at the true states ({} keyframes, {} "
      "visual residuals, computed in {} s): RMS over the keyframes of the standard deviation per "
      "quantity (mm, deg, mm/s, deg/s, mm/s^2). Smoothing: all data (the bound for the smoother); "
      "filtering: data up to each keyframe (posterior CRLB, Tichavsky et al. 1998; the bound for "
      "causal estimators).\n\n",
      bound.keyframes.size(), bound.visual_residuals, FormatNumber(bound.compute_s, 3));
  const std::string note =
      "RMSE / bound over the keyframes where the estimator has a pose (within 2 ms), position "
      "and rotation angle; this is one Monte-Carlo draw, so a ratio can fall below 1 by chance "
      "(`mavloc repro smoother` averages squared errors over seeds).\n\n";
  report.markdown =
      "## Cramér–Rao bound\n\n" + intro + quantity_table + "\n" + note + efficiency_table;
  report.text = "Cramér–Rao bound\n" + intro + quantity_table + "\n" + efficiency_table;
  report.json = {{"available", true},
                 {"keyframes", bound.keyframes.size()},
                 {"visual_residuals", bound.visual_residuals},
                 {"compute_s", bound.compute_s},
                 {"quantity_sigma_rms", qj},
                 {"units", "m, rad, m/s, rad/s, m/s^2"},
                 {"efficiency", ej}};
  return report;
}

}  // namespace mavloc
