#include "evaluation/obstacle_report.h"

#include <fmt/format.h>

#include <cmath>

#include "evaluation/json_number.h"
#include "evaluation/report/report_markdown.h"

namespace mavloc {
namespace {

constexpr double kMsToS = 1e-3;

std::string Metres(double value_m) {
  return std::isfinite(value_m) ? fmt::format("{:.3f} m", value_m) : std::string("none");
}

nlohmann::json NumberOrNull(double value) {
  return std::isfinite(value) ? nlohmann::json(value) : nlohmann::json(nullptr);
}

std::string SettingsMarkdown(const StereoObstacleRun& run) {
  const StereoPipelineOptions& o = run.options;
  const DisparityOptions& d = o.disparity;
  const std::string matcher = fmt::format(
      "{} (OpenCV), block {} px, {} disparities from {}, uniqueness {} %, texture threshold {}, "
      "speckle window {} px / range {} px, left-right check {} px, prefilter cap {}",
      d.matcher == StereoMatcherType::kBlockMatching ? "StereoBM" : "StereoSGBM", d.block_size_px,
      d.num_disparities, d.min_disparity_px, d.uniqueness_ratio, d.texture_threshold,
      d.speckle_window_size, d.speckle_range_px, d.disp12_max_diff_px, d.pre_filter_cap);
  return MarkdownTableOf(
      {"setting", "value"},
      {{"rectified pair",
        fmt::format("{} x {} px, f {:.1f} px, baseline {:.4f} m", run.geometry.width_px,
                    run.geometry.height_px, run.geometry.f_px, run.geometry.baseline_m)},
       {"matcher", matcher},
       {"eq. (4)",
        fmt::format("dz {} m, dd {} px: sqrt(b f dd / dz) = {:.3f} px, d_min = {} px", o.delta_z_m,
                    o.delta_d_px, run.limits.d_min_unrounded_px, run.limits.d_min_px)},
       {"maximum range b f / d_min",
        fmt::format("{:.3f} m (without the ceiling: {:.3f} m)", run.limits.max_range_m,
                    run.limits.max_range_unrounded_m)},
       {"alert", fmt::format("clearance {} m, cluster of >= {} points (voxels {} m, "
                             "26-connected), points remembered {} s",
                             o.alert.clearance_m, o.alert.min_cluster_points, o.alert.voxel_m,
                             o.alert.memory_s)},
       {"point cloud pixel stride", std::to_string(o.pixel_stride)}});
}

// Table 1 of the paper: mean time per frame of each stage, beside the paper's.
ReportTable TimingTable(const StereoObstacleRun& run) {
  const StereoStageTimings mean = MeanStageTimings(run);
  ReportTable t;
  t.name = "timing";
  t.title = fmt::format(
      "Time per frame of each stage, in the form of the paper's Table 1 (means over {} frames, "
      "OpenCV with {} threads, on a shared machine)",
      run.frames.size(), run.opencv_threads);
  t.columns = {
      {"process", ""}, {"mean per frame", "s", "ms"}, {"paper, 1.86 GHz Core 2 Duo", "s", "ms"}};
  const nlohmann::json none = nullptr;
  t.rows = {{"Image rectification", mean.rectification_ms * kMsToS, 5 * kMsToS},
            {"Disparity mapping", mean.disparity_ms * kMsToS, 29 * kMsToS},
            {"Point cloud generation", mean.point_cloud_ms * kMsToS, 1 * kMsToS},
            {"Total", mean.total_ms * kMsToS, 35 * kMsToS},
            {"Obstacle check (not in Table 1)", mean.obstacle_check_ms * kMsToS, none}};
  return t;
}

ReportTable DetectionTable(const ObstacleEvaluation& e) {
  const std::string title = fmt::format(
      "Alerts against the truth: a frame is positive when the true distance to the nearest "
      "obstacle or room surface is below the clearance ({} m)",
      e.clearance_m);
  std::vector<ReportTable::Column> counts;
  for (const char* name : {"frames", "alerts", "TP", "FP", "FN", "TN", "precision", "recall"})
    counts.push_back({name, ""});
  return {"detection",
          title,
          counts,
          {{e.frames, e.alerts, e.true_positive, e.false_positive, e.false_negative,
            e.true_negative, NumberOrNull(e.precision), NumberOrNull(e.recall)}}};
}

// One row per known obstacle.
ReportTable ObstacleTable(const ObstacleEvaluation& e) {
  std::vector<std::vector<nlohmann::json>> rows;
  for (const ObstacleTruth& o : e.obstacles)
    rows.push_back(
        {o.index, NumberOrNull(o.min_distance_m), o.within_clearance ? "yes" : "no", o.alerts});
  return {"obstacles",
          fmt::format("Each obstacle: the trajectory's closest approach and the alerts attributed "
                      "to it (nearest measured point within {} m of its surface)",
                      e.attribution_m),
          {{"obstacle", ""},
           {"closest approach", "m"},
           {"within clearance", ""},
           {"alerts attributed", ""}},
          rows};
}

nlohmann::json RunDetails(const std::string& dataset_name, const StereoObstacleRun& run,
                          int alerts) {
  const StereoPipelineOptions& o = run.options;
  const DisparityOptions& d = o.disparity;
  const StereoStageTimings mean = MeanStageTimings(run);
  nlohmann::json json;
  json["dataset"] = dataset_name;
  json["pose_source"] = run.pose_source;
  json["frames"] = run.frames.size();
  json["frames_without_pose"] = run.frames_without_pose;
  json["frames_missing_image"] = run.frames_missing_image;
  json["alert_count"] = alerts;
  json["timing_s"] = {{"rectification", mean.rectification_ms * kMsToS},
                      {"disparity", mean.disparity_ms * kMsToS},
                      {"point_cloud", mean.point_cloud_ms * kMsToS},
                      {"total", mean.total_ms * kMsToS},
                      {"obstacle_check", mean.obstacle_check_ms * kMsToS}};
  json["d_min_px"] = run.limits.d_min_px;
  json["max_range_m"] = run.limits.max_range_m;
  json["max_range_unrounded_m"] = run.limits.max_range_unrounded_m;
  json["settings"] = {{"matcher", StereoMatcherTypeName(d.matcher)},
                      {"block_size_px", d.block_size_px},
                      {"num_disparities", d.num_disparities},
                      {"uniqueness_ratio", d.uniqueness_ratio},
                      {"texture_threshold", d.texture_threshold},
                      {"delta_z_m", o.delta_z_m},
                      {"delta_d_px", o.delta_d_px},
                      {"clearance_m", o.alert.clearance_m},
                      {"min_cluster_points", o.alert.min_cluster_points},
                      {"voxel_m", o.alert.voxel_m},
                      {"memory_s", o.alert.memory_s},
                      {"pixel_stride", o.pixel_stride}};
  return json;
}

void AddEvaluationDetails(const ObstacleEvaluation& e, nlohmann::json* json) {
  (*json)["precision"] = JsonNumber(e.precision);
  (*json)["recall"] = JsonNumber(e.recall);
  (*json)["true_positive"] = e.true_positive;
  (*json)["false_positive"] = e.false_positive;
  (*json)["false_negative"] = e.false_negative;
  (*json)["true_negative"] = e.true_negative;
  (*json)["obstacles_within_clearance"] = e.obstacles_within_clearance;
  (*json)["obstacles_alerted"] = e.obstacles_alerted;
  nlohmann::json obstacles = nlohmann::json::array();
  for (const ObstacleTruth& t : e.obstacles)
    obstacles.push_back({{"index", t.index},
                         {"min_distance_m", t.min_distance_m},
                         {"within_clearance", t.within_clearance},
                         {"alerts", t.alerts}});
  (*json)["obstacles"] = obstacles;
}

std::string EvaluationFindings(const ObstacleEvaluation& e) {
  return fmt::format(
      "Truth: the true distance from the vehicle to the nearest obstacle or room surface at each "
      "frame (ground truth, map.yaml). Largest true distance of a false alert: {}; smallest true "
      "distance of a missed frame: {} (the clearance is {} m). {} of {} obstacles that came "
      "within the clearance raised an alert.\n",
      Metres(e.false_alert_max_true_distance_m), Metres(e.missed_min_true_distance_m),
      e.clearance_m, e.obstacles_alerted, e.obstacles_within_clearance);
}

}  // namespace

Report ObstacleReport(const std::string& dataset_name, const StereoObstacleRun& run,
                      const std::optional<ObstacleEvaluation>& evaluation) {
  int alerts = 0;
  for (const ObstacleFrame& f : run.frames) alerts += f.check.alert;
  Report report;
  report.kind = "obstacles";
  report.title = "Stereo obstacle detection: " + dataset_name;
  report.provenance.input = dataset_name;
  report.provenance.settings = {{"pose_source", run.pose_source}};
  const std::string setup = fmt::format(
      "PIXHAWK paper (Meier et al. 2012) sec. 4: rectification, block matching, eq. (2)-(6), "
      "alert when a cluster of at least N points lies within the clearance. Pose source: `{}`. "
      "{} stereo frames processed ({} without a pose, {} with an image missing). Point cloud "
      "generation covers eq. (2), (5) and (6) for every pixel with d >= d_min.\n\n",
      run.pose_source, run.frames.size(), run.frames_without_pose, run.frames_missing_image);
  report.sections.push_back({"Setup", setup + SettingsMarkdown(run), true});
  report.tables.push_back(TimingTable(run));
  report.sections.push_back(
      {"Alerts", fmt::format("{} alerts in {} frames (alerts.csv; per-frame times and distances in "
                             "frames.csv).\n",
                             alerts, run.frames.size())});
  report.details = RunDetails(dataset_name, run, alerts);
  if (evaluation) {
    report.tables.push_back(DetectionTable(*evaluation));
    report.tables.push_back(ObstacleTable(*evaluation));
    report.sections.push_back({"Against the known obstacles", EvaluationFindings(*evaluation)});
    AddEvaluationDetails(*evaluation, &report.details);
  } else {
    report.sections.push_back(
        {"Against the known obstacles",
         "The dataset does not describe its obstacles (no obstacle_count in map.yaml "
         "parameters), so precision and recall are not computed.\n"});
  }
  report.files["alerts.csv"] = ObstacleAlertsCsv(run);
  report.files["frames.csv"] = ObstacleFramesCsv(run, evaluation);
  return report;
}

}  // namespace mavloc
