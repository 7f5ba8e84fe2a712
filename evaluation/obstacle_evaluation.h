// Stereo obstacle detection over a dataset and its evaluation against the known obstacles
// (PIXHAWK paper, Meier et al. 2012, sec. 4 and 7.3).
//
// RunStereoObstacleDetection runs the per-frame pipeline (frontends/stereo/stereo_pipeline.h) on
// every synchronous cam0/cam1 pair, with the body pose of each frame taken from a pose source
// (ground truth or an estimator) interpolated at the frame time.
//
// EvaluateObstacleAlerts compares the alerts with the truth of a stereo-obstacles room
// (datasets/rendering/stereo_room_renderer.h), at the true vehicle position of each frame:
// - per frame: a frame is truly positive when the true distance from the vehicle (body origin) to
//   the nearest obstacle or room surface is below the clearance; precision = TP / (TP + FP),
//   recall = TP / (TP + FN) over the processed frames;
// - per obstacle: an obstacle "comes within the clearance" when the ground-truth trajectory passes
//   it closer than the clearance; it "raises an alert" when at least one alert's nearest measured
//   point lies within attribution_m of that obstacle's surface.
#pragma once

#include <Eigen/Core>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "core/dataset.h"
#include "datasets/rendering/stereo_room_renderer.h"
#include "frontends/stereo/stereo_pipeline.h"

namespace mavloc {

struct ObstacleFrame {
  TimeNs t_ns = 0;
  Eigen::Vector3d p_W_vehicle = Eigen::Vector3d::Zero();  // from the pose source
  ObstacleCheck check;
  size_t cloud_points = 0;
  StereoStageTimings timings;
};

struct StereoObstacleRun {
  std::string pose_source;
  RectifiedStereoGeometry geometry;
  StereoRangeLimits limits;
  StereoPipelineOptions options;
  std::vector<ObstacleFrame> frames;
  int frames_without_pose = 0;   // frame time outside the pose source's span
  int frames_missing_image = 0;  // cam0 or cam1 image absent on disk
  int opencv_threads = 1;
};

// Throws InputError when the dataset has no cam0/cam1 pair, no image of them on disk, or a
// calibration the pipeline cannot rectify.
StereoObstacleRun RunStereoObstacleDetection(const Dataset& dataset,
                                             const std::vector<StampedPose>& T_W_B_source,
                                             const std::string& pose_source_name,
                                             const StereoPipelineOptions& options);

struct ObstacleTruth {
  int index = 0;
  double min_distance_m = 0.0;  // over the ground-truth trajectory
  bool within_clearance = false;
  int alerts = 0;  // alerts attributed to it
};

struct ObstacleEvaluation {
  double clearance_m = 0.75;
  double attribution_m = 0.15;
  int frames = 0;
  int alerts = 0;
  int true_positive = 0, false_positive = 0, false_negative = 0, true_negative = 0;
  double precision = 0.0;  // NaN when there is no alert
  double recall = 0.0;     // NaN when no frame is truly positive
  // Largest true distance among false alerts, smallest among missed frames (how far from the
  // clearance the disagreements are); NaN when there are none.
  double false_alert_max_true_distance_m = 0.0;
  double missed_min_true_distance_m = 0.0;
  std::vector<double> true_distance_m;  // per processed frame
  std::vector<ObstacleTruth> obstacles;
  int obstacles_within_clearance = 0;
  int obstacles_alerted = 0;  // of those within the clearance
};

ObstacleEvaluation EvaluateObstacleAlerts(const StereoObstacleRun& run, const StereoRoom& room,
                                          const std::vector<StampedPose>& ground_truth,
                                          double attribution_m = 0.15);

// alerts.csv: one row per alert (timestamp, vehicle position, nearest obstacle distance).
std::string ObstacleAlertsCsv(const StereoObstacleRun& run);
// frames.csv: every processed frame with its stage timings (and the true distance when known).
std::string ObstacleFramesCsv(const StereoObstacleRun& run,
                              const std::optional<ObstacleEvaluation>& evaluation);
// The per-frame stage times averaged over the processed frames (zero without frames).
StereoStageTimings MeanStageTimings(const StereoObstacleRun& run);

}  // namespace mavloc
