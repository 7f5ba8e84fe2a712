// mavloc obstacles: the PIXHAWK stereo obstacle detection (Meier et al. 2012, sec. 4, 7.3) on a
// dataset's cam0/cam1 images, with the vehicle pose from the ground truth or an estimator; writes
// alerts.csv, frames.csv, report.md (Table-1-style timing) and report.json (alert count, and
// precision / recall where map.yaml describes the obstacles).
#include <cstdio>
#include <set>

#include "cli/commands.h"
#include "cli/option_checks.h"
#include "cli/output_folder.h"
#include "core/errors.h"
#include "core/key_values.h"
#include "core/progress.h"
#include "datasets/io/euroc_io.h"
#include "evaluation/association.h"
#include "evaluation/estimator_option_ranges.h"
#include "evaluation/obstacle_evaluation.h"
#include "evaluation/obstacle_report.h"
#include "evaluation/report/report_folder.h"
#include "evaluation/report_figures.h"
#include "solver/estimator.h"

namespace mavloc::cli {
namespace {

// Pipeline settings from --set key=value; unknown keys are an error (a typo must not pass).
StereoPipelineOptions PipelineOptions(const KeyValues& settings) {
  static const std::set<std::string> kKeys = {
      "matcher",  "block_size",  "num_disparities", "uniqueness_ratio",   "texture_threshold",
      "delta_z",  "delta_d",     "clearance",       "min_cluster_points", "voxel",
      "memory_s", "keep_radius", "pixel_stride",    "speckle_window",     "speckle_range"};
  for (const auto& [key, value] : settings) {
    if (kKeys.count(key) == 0) {
      std::string known;
      for (const auto& k : kKeys) known += (known.empty() ? "" : ", ") + k;
      throw InputError("--set " + key + "=" + value + ": obstacles has no setting '" + key +
                       "' (known: " + known + ")");
    }
  }
  StereoPipelineOptions o;
  const std::string matcher = GetStringSetting(settings, "matcher", "bm");
  if (!ParseStereoMatcherType(matcher, &o.disparity.matcher))
    throw InputError("obstacles --set matcher: expected bm or sgbm, got '" + matcher + "'");
  o.disparity.block_size_px = GetIntSetting(settings, "block_size", o.disparity.block_size_px);
  o.disparity.num_disparities =
      GetIntSetting(settings, "num_disparities", o.disparity.num_disparities);
  o.disparity.uniqueness_ratio =
      GetIntSetting(settings, "uniqueness_ratio", o.disparity.uniqueness_ratio);
  o.disparity.texture_threshold =
      GetIntSetting(settings, "texture_threshold", o.disparity.texture_threshold);
  o.disparity.speckle_window_size =
      GetIntSetting(settings, "speckle_window", o.disparity.speckle_window_size);
  o.disparity.speckle_range_px =
      GetIntSetting(settings, "speckle_range", o.disparity.speckle_range_px);
  o.delta_z_m = GetDoubleSetting(settings, "delta_z", o.delta_z_m);
  o.delta_d_px = GetDoubleSetting(settings, "delta_d", o.delta_d_px);
  o.pixel_stride = GetIntSetting(settings, "pixel_stride", o.pixel_stride);
  o.alert.clearance_m = GetDoubleSetting(settings, "clearance", o.alert.clearance_m);
  o.alert.min_cluster_points =
      GetIntSetting(settings, "min_cluster_points", o.alert.min_cluster_points);
  o.alert.voxel_m = GetDoubleSetting(settings, "voxel", o.alert.voxel_m);
  o.alert.memory_s = GetDoubleSetting(settings, "memory_s", o.alert.memory_s);
  o.alert.keep_radius_m = GetDoubleSetting(settings, "keep_radius", o.alert.keep_radius_m);
  const std::string problem = ValidateStereoPipelineOptions(o);
  if (!problem.empty()) throw InputError("obstacles --set: " + problem);
  return o;
}

std::vector<StampedPose> PoseSource(const Dataset& dataset, const std::string& source,
                                    const KeyValues& estimator_options) {
  if (source == "gt") {
    if (dataset.ground_truth.empty())
      throw InputError(dataset.root, 0, "", "--pose-source gt: the dataset has no ground truth");
    return GroundTruthPoses(dataset);
  }
  const EstimatorEntry* entry = FindEstimator(source);
  if (entry == nullptr)
    throw InputError("--pose-source: '" + source +
                     "' is neither gt nor an estimator (mavloc list)");
  auto estimator = entry->create(EstimatorOptions(estimator_options));
  const Applicability applicability = estimator->AppliesTo(dataset);
  if (!applicability.applies)
    throw InputError("--pose-source " + source + " does not apply: " + applicability.reason);
  ReportProgress("obstacles", "running " + source + " for the vehicle poses");
  const Estimate estimate = estimator->Run(dataset);
  if (estimate.poses.empty()) throw InputError("--pose-source " + source + " gives no 6-DoF poses");
  return estimate.poses;
}

}  // namespace

void RegisterObstacles(CLI::App& app, int* exit_code) {
  auto* command = app.add_subcommand(
      "obstacles",
      "PIXHAWK stereo obstacle detection on cam0/cam1: alerts within the clearance, Table-1 "
      "timing, precision/recall against map.yaml obstacles");
  struct Args {
    std::string dataset, report, pose_source = "gt";
    std::vector<std::string> settings, options;
    bool force = false;
  };
  auto args = std::make_shared<Args>();
  command->add_option("--dataset", args->dataset, "Dataset folder with cam0/cam1 images")
      ->required();
  command->add_option("--report", args->report, "Report folder (created)")
      ->check(OutputFolder())
      ->required();
  command->add_flag("--force", args->force,
                    "Replace an existing --report folder (a mavloc report)");
  command
      ->add_option("--pose-source", args->pose_source,
                   "Vehicle poses for eq. (6): gt or an estimator name")
      ->capture_default_str();
  command->add_option(
      "--set", args->settings,
      "Pipeline setting key=value (repeatable): matcher (bm|sgbm), block_size, num_disparities, "
      "uniqueness_ratio, texture_threshold, speckle_window, speckle_range, delta_z, delta_d, "
      "pixel_stride, clearance, min_cluster_points, voxel, memory_s, keep_radius");
  command->add_option("--option", args->options,
                      "Estimator option key=value for --pose-source ESTIMATOR (repeatable)");
  command->callback([args, exit_code] {
    const StereoPipelineOptions options = PipelineOptions(ParseKeyValues(args->settings, "--set"));
    const KeyValues estimator_options = ParseKeyValues(args->options, "--option");
    if (args->pose_source == "gt" && !estimator_options.empty())
      throw InputError("--option " + args->options.front() +
                       ": estimator options need --pose-source ESTIMATOR (the poses come from the "
                       "ground truth)");
    if (const EstimatorEntry* entry = FindEstimator(args->pose_source))
      CheckEstimatorOptionValues(*entry, EstimatorOptions(estimator_options));
    // The report folder is checked before any work and written whole (cli/output_folder.h).
    StagedFolder report(args->report, FolderKind::kReport, args->force);
    ReportProgress("obstacles", "reading " + args->dataset);
    const Dataset dataset = ReadEurocDataset(args->dataset);
    const std::vector<StampedPose> poses =
        PoseSource(dataset, args->pose_source, estimator_options);
    const StereoObstacleRun run =
        RunStereoObstacleDetection(dataset, poses, args->pose_source, options);
    std::string reason;
    const std::optional<StereoRoom> room =
        StereoRoomFromMapParameters(dataset.map.parameters, &reason);
    if (!room && !reason.empty()) throw InputError(args->dataset + "/map.yaml", 0, "", reason);
    std::optional<ObstacleEvaluation> evaluation;
    if (room && !dataset.ground_truth.empty())
      evaluation = EvaluateObstacleAlerts(run, *room, GroundTruthPoses(dataset));
    WriteReport(report.path(), ObstacleReport(dataset.name, run, evaluation));
    const FigureOutcome figures = WriteReportFigures(report.path(), report.ForUser(report.path()));
    report.Commit();
    int alerts = 0;
    for (const ObstacleFrame& frame : run.frames) alerts += frame.check.alert;
    std::printf("wrote %s: %d alerts in %zu frames", args->report.c_str(), alerts,
                run.frames.size());
    if (evaluation) {
      std::printf(", precision %.3f, recall %.3f, %d/%d close obstacles alerted",
                  evaluation->precision, evaluation->recall, evaluation->obstacles_alerted,
                  evaluation->obstacles_within_clearance);
    }
    std::printf("\n%s\n", report.ForUser(DescribeFigureOutcome(figures)).c_str());
    *exit_code = 0;
  });
}

}  // namespace mavloc::cli
