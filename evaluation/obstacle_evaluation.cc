#include "evaluation/obstacle_evaluation.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <opencv2/core/utility.hpp>

#include "core/errors.h"
#include "core/numbers.h"
#include "core/progress.h"
#include "evaluation/association.h"
#include "evaluation/json_number.h"
#include "frontends/image_io.h"

namespace mavloc {
namespace {

constexpr double kPoseMaxDtS = 0.1;

// The source poses interpolated at the given times (positions linearly, rotations by slerp);
// times outside the source's span map to nothing.
std::map<TimeNs, Pose> PosesAt(const std::vector<TimeNs>& t_ns,
                               const std::vector<StampedPose>& source) {
  std::vector<StampedPose> stubs;
  for (const TimeNs t : t_ns) stubs.push_back({t, Pose()});
  std::map<TimeNs, Pose> poses;
  for (const PosePair& pair :
       AssociatePoses(stubs, source, kPoseMaxDtS, AssociationMode::kInterpolate))
    poses[pair.t_ns] = pair.T_W_B_gt;
  return poses;
}

double DistanceToRoomSurfaces(const StereoRoom& room, const Eigen::Vector3d& p_W) {
  return std::max(0.0, std::min((p_W - room.min_W).minCoeff(), (room.max_W - p_W).minCoeff()));
}

double Ratio(int numerator, int denominator) {
  return denominator > 0 ? static_cast<double>(numerator) / denominator : kNaN;
}

std::string Num(double value, int digits = 3) {
  return std::isfinite(value) ? fmt::format("{:.{}f}", value, digits) : "nan";
}

}  // namespace

StereoStageTimings MeanStageTimings(const StereoObstacleRun& run) {
  StereoStageTimings mean;
  if (run.frames.empty()) return mean;
  for (const ObstacleFrame& f : run.frames) {
    mean.rectification_ms += f.timings.rectification_ms;
    mean.disparity_ms += f.timings.disparity_ms;
    mean.point_cloud_ms += f.timings.point_cloud_ms;
    mean.total_ms += f.timings.total_ms;
    mean.obstacle_check_ms += f.timings.obstacle_check_ms;
  }
  const double n = static_cast<double>(run.frames.size());
  mean.rectification_ms /= n;
  mean.disparity_ms /= n;
  mean.point_cloud_ms /= n;
  mean.total_ms /= n;
  mean.obstacle_check_ms /= n;
  return mean;
}

StereoObstacleRun RunStereoObstacleDetection(const Dataset& dataset,
                                             const std::vector<StampedPose>& T_W_B_source,
                                             const std::string& pose_source_name,
                                             const StereoPipelineOptions& options) {
  const CameraSensor* cam0 = dataset.Camera("cam0");
  const CameraSensor* cam1 = dataset.Camera("cam1");
  if (cam0 == nullptr || cam1 == nullptr)
    throw InputError(dataset.root, 0, "", "stereo obstacle detection needs cam0 and cam1");
  std::string reason;
  std::optional<StereoPipeline> pipeline = StereoPipeline::Create(
      StereoCalibration::FromCameras(*cam0, *cam1), cam0->T_B_C, options, &reason);
  if (!pipeline) throw InputError(dataset.root, 0, "cam0/cam1", "cannot set up stereo: " + reason);

  StereoObstacleRun run;
  run.pose_source = pose_source_name;
  run.geometry = pipeline->geometry();
  run.limits = pipeline->range_limits();
  run.options = options;
  run.opencv_threads = cv::getNumThreads();

  std::map<TimeNs, std::string> right_paths;
  for (const CameraFrame& frame : cam1->frames) right_paths[frame.t_ns] = frame.image_path;
  std::vector<std::pair<TimeNs, std::pair<std::string, std::string>>> pairs;
  std::vector<TimeNs> times;
  for (const CameraFrame& frame : cam0->frames) {
    const auto it = right_paths.find(frame.t_ns);
    if (it == right_paths.end()) continue;
    pairs.push_back({frame.t_ns, {frame.image_path, it->second}});
    times.push_back(frame.t_ns);
  }
  const std::map<TimeNs, Pose> poses = PosesAt(times, T_W_B_source);
  for (size_t i = 0; i < pairs.size(); ++i) {
    const auto& [t_ns, paths] = pairs[i];
    const auto pose = poses.find(t_ns);
    if (pose == poses.end()) {
      ++run.frames_without_pose;
      continue;
    }
    if (paths.first.empty() || paths.second.empty() || !std::filesystem::exists(paths.first) ||
        !std::filesystem::exists(paths.second)) {
      ++run.frames_missing_image;
      continue;
    }
    const cv::Mat left = LoadGrayImage(paths.first);
    const cv::Mat right = LoadGrayImage(paths.second);
    const std::optional<StereoFrameResult> result =
        pipeline->Process(t_ns, left, right, pose->second);
    if (!result)
      throw InputError(paths.first, 0, "", "image size does not match the cam0/cam1 calibration");
    ObstacleFrame frame;
    frame.t_ns = t_ns;
    frame.p_W_vehicle = pose->second.p;
    frame.check = result->obstacle;
    frame.cloud_points = result->points_W.size();
    frame.timings = result->timings;
    run.frames.push_back(frame);
    if (i % 25 == 0) ReportProgress("obstacles", fmt::format("frame {}/{}", i + 1, pairs.size()));
  }
  if (run.frames.empty()) {
    throw InputError(
        dataset.root, 0, "",
        run.frames_missing_image > 0
            ? "no cam0/cam1 image pair on disk (for a synthetic dataset: simulate with "
              "--render)"
            : "no cam0/cam1 frame lies within the pose source's time span");
  }
  return run;
}

ObstacleEvaluation EvaluateObstacleAlerts(const StereoObstacleRun& run, const StereoRoom& room,
                                          const std::vector<StampedPose>& ground_truth,
                                          double attribution_m) {
  ObstacleEvaluation e;
  e.clearance_m = run.options.alert.clearance_m;
  e.attribution_m = attribution_m;
  for (size_t i = 0; i < room.obstacles.size(); ++i) {
    ObstacleTruth truth;
    truth.index = static_cast<int>(i);
    truth.min_distance_m = std::numeric_limits<double>::infinity();
    for (const StampedPose& gt : ground_truth)
      truth.min_distance_m =
          std::min(truth.min_distance_m, DistanceToObstacle(room.obstacles[i], gt.T_W_B.p));
    truth.within_clearance = truth.min_distance_m < e.clearance_m;
    e.obstacles.push_back(truth);
  }
  std::vector<TimeNs> times;
  for (const ObstacleFrame& frame : run.frames) times.push_back(frame.t_ns);
  const std::map<TimeNs, Pose> true_poses = PosesAt(times, ground_truth);
  e.false_alert_max_true_distance_m = kNaN;
  e.missed_min_true_distance_m = kNaN;
  for (const ObstacleFrame& frame : run.frames) {
    const auto pose = true_poses.find(frame.t_ns);
    if (pose == true_poses.end()) {
      e.true_distance_m.push_back(kNaN);
      continue;
    }
    const Eigen::Vector3d& p_W = pose->second.p;
    double distance = DistanceToRoomSurfaces(room, p_W);
    for (const RoomObstacle& obstacle : room.obstacles)
      distance = std::min(distance, DistanceToObstacle(obstacle, p_W));
    e.true_distance_m.push_back(distance);
    ++e.frames;
    const bool truly_close = distance < e.clearance_m;
    const bool alert = frame.check.alert;
    e.alerts += alert;
    if (alert && truly_close) ++e.true_positive;
    if (alert && !truly_close) {
      ++e.false_positive;
      e.false_alert_max_true_distance_m =
          std::isnan(e.false_alert_max_true_distance_m)
              ? distance
              : std::max(e.false_alert_max_true_distance_m, distance);
    }
    if (!alert && truly_close) {
      ++e.false_negative;
      e.missed_min_true_distance_m = std::isnan(e.missed_min_true_distance_m)
                                         ? distance
                                         : std::min(e.missed_min_true_distance_m, distance);
    }
    if (!alert && !truly_close) ++e.true_negative;
    if (alert) {
      for (size_t i = 0; i < room.obstacles.size(); ++i) {
        if (DistanceToObstacle(room.obstacles[i], frame.check.nearest_point_W) < attribution_m)
          ++e.obstacles[i].alerts;
      }
    }
  }
  e.precision = Ratio(e.true_positive, e.true_positive + e.false_positive);
  e.recall = Ratio(e.true_positive, e.true_positive + e.false_negative);
  for (const ObstacleTruth& truth : e.obstacles) {
    e.obstacles_within_clearance += truth.within_clearance;
    e.obstacles_alerted += truth.within_clearance && truth.alerts > 0;
  }
  return e;
}

std::string ObstacleAlertsCsv(const StereoObstacleRun& run) {
  std::string csv =
      "#timestamp [ns],p_W_x [m],p_W_y [m],p_W_z [m],nearest_obstacle_distance [m],"
      "cluster_points\n";
  for (const ObstacleFrame& f : run.frames) {
    if (!f.check.alert) continue;
    csv += fmt::format("{},{:.4f},{:.4f},{:.4f},{:.4f},{}\n", f.t_ns, f.p_W_vehicle.x(),
                       f.p_W_vehicle.y(), f.p_W_vehicle.z(), f.check.nearest_distance_m,
                       f.check.largest_cluster_points);
  }
  return csv;
}

std::string ObstacleFramesCsv(const StereoObstacleRun& run,
                              const std::optional<ObstacleEvaluation>& evaluation) {
  std::string csv =
      "#timestamp [ns],p_W_x [m],p_W_y [m],p_W_z [m],alert,nearest_measured_distance [m],"
      "nearest_x [m],nearest_y [m],nearest_z [m],true_distance [m],cloud_points,rectification "
      "[ms],disparity [ms],point_cloud [ms],"
      "total [ms],obstacle_check [ms]\n";
  for (size_t i = 0; i < run.frames.size(); ++i) {
    const ObstacleFrame& f = run.frames[i];
    const double truth = evaluation ? evaluation->true_distance_m[i] : kNaN;
    const bool near = std::isfinite(f.check.nearest_distance_m);
    const Eigen::Vector3d& q = f.check.nearest_point_W;
    csv += fmt::format(
        "{},{:.4f},{:.4f},{:.4f},{},{},{},{},{},{},{},{:.3f},{:.3f},{:.3f},{:.3f},{:.3f}\n", f.t_ns,
        f.p_W_vehicle.x(), f.p_W_vehicle.y(), f.p_W_vehicle.z(), f.check.alert ? 1 : 0,
        Num(f.check.nearest_distance_m, 4), near ? Num(q.x(), 4) : "nan",
        near ? Num(q.y(), 4) : "nan", near ? Num(q.z(), 4) : "nan", Num(truth, 4), f.cloud_points,
        f.timings.rectification_ms, f.timings.disparity_ms, f.timings.point_cloud_ms,
        f.timings.total_ms, f.timings.obstacle_check_ms);
  }
  return csv;
}

}  // namespace mavloc
