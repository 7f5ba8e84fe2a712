#include "solver/estimators/upright_2p_estimator.h"

#include <cmath>

#include "core/errors.h"
#include "core/random.h"
#include "solver/pose/tags_camera.h"

namespace mavloc {

Upright2pSettings ParseUpright2pSettings(const EstimatorOptions& options) {
  Upright2pSettings s;
  s.pose.inlier_threshold_px = options.GetDouble("threshold_px", s.pose.inlier_threshold_px);
  s.pose.ransac = options.GetBool("ransac", s.pose.ransac);
  s.pose.max_iterations = options.GetInt("max_iterations", s.pose.max_iterations);
  s.pose.min_inliers = options.GetInt("min_inliers", s.pose.min_inliers);
  s.min_inlier_ratio = options.GetDouble("min_inlier_ratio", s.min_inlier_ratio);
  if (!(s.pose.inlier_threshold_px > 0.0) || s.pose.max_iterations < 1)
    throw InputError("options threshold_px must be > 0 and max_iterations >= 1");
  if (s.min_inlier_ratio < 0.0 || s.min_inlier_ratio > 1.0)
    throw InputError("option min_inlier_ratio must be in [0, 1]");
  s.source = ParseRollPitchSourceOptions(options);
  return s;
}

Upright2pFrameResult Upright2pFrame(const TagFrame& frame, const Dataset& dataset,
                                    const StampedRollPitch& roll_pitch,
                                    const Upright2pSettings& settings) {
  Upright2pFrameResult out;
  const CameraSensor& camera = *TagsCamera(dataset);
  std::vector<Eigen::Vector3d> X_W;
  std::vector<Eigen::Vector2d> xy_C;
  FrameCorners(frame.observations, dataset.map, camera.model, &X_W, &xy_C);
  if (X_W.size() < 4) {
    out.reason = "fewer than 4 corners";
    return out;
  }
  UprightPoseOptions pose_options = settings.pose;
  pose_options.seed = SplitMix64(static_cast<uint64_t>(frame.t_ns));  // reproducible per frame
  const double focal_px = std::sqrt(camera.model.fu() * camera.model.fv());
  out.pose = EstimateUprightPose(X_W, xy_C, roll_pitch.roll_rad, roll_pitch.pitch_rad, camera.T_B_C,
                                 focal_px, pose_options);
  if (!out.pose.ok) {
    out.reason = out.pose.reason;
    return out;
  }
  if (out.pose.num_inliers < settings.min_inlier_ratio * static_cast<double>(X_W.size())) {
    out.reason = "too few inliers";
    return out;
  }
  out.ok = true;
  return out;
}

Upright2pEstimator::Upright2pEstimator(const EstimatorOptions& options)
    : options_(options),
      settings_(ParseUpright2pSettings(options)),
      board_(ParseBoardInitOptions(options)) {}

Applicability Upright2pEstimator::AppliesTo(const Dataset& dataset) const {
  if (dataset.tags.empty()) return Applicability::No("needs tags0 corner observations");
  if (dataset.map.tags.empty()) return Applicability::No("needs tags (markers) in map.yaml");
  const std::string camera = TagsCameraMissing(dataset);
  if (!camera.empty()) return Applicability::No(camera);
  const std::string missing = RollPitchSourceMissing(dataset, settings_.source);
  if (!missing.empty()) return Applicability::No(missing);
  const std::string board = BoardWorldMissing(dataset);
  if (!board.empty()) return Applicability::No(board);
  return Applicability::Yes();
}

Estimate Upright2pEstimator::Run(const Dataset& dataset) {
  return RunInWorldFrame(dataset, board_, [&](const Dataset& dataset_W, const BoardWorld*) {
    return RunInWorld(dataset_W);
  });
}

Estimate Upright2pEstimator::RunInWorld(const Dataset& dataset) {
  Estimate estimate;
  estimate.quantities = MakeQuantityTable(PoseQuantityNames(/*with_velocity=*/false));
  RollPitchSource source(dataset, settings_.source, options_);
  for (const TagFrame& frame : GroupTagFrames(dataset)) {
    if (frame.observations.empty()) {
      estimate.CountFailure("no marker in view");
      continue;
    }
    const TimeNs t_exposure = source.ExposureTime(frame.t_ns);
    const auto roll_pitch = source.At(t_exposure);
    if (!roll_pitch) {
      estimate.CountFailure("no IMU attitude at the exposure time");
      continue;
    }
    const Upright2pFrameResult result = Upright2pFrame(frame, dataset, *roll_pitch, settings_);
    if (!result.ok) {
      estimate.CountFailure(result.reason);
      continue;
    }
    estimate.quantities.Append(t_exposure, PoseQuantityValues(result.pose.T_W_B));
    estimate.poses.push_back({t_exposure, result.pose.T_W_B});
  }
  return estimate;
}

}  // namespace mavloc
