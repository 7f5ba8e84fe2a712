#include "solver/estimators/pixhawk_kf_estimator.h"

#include <cmath>

#include "core/errors.h"
#include "core/rotation.h"
#include "solver/pixhawk/attitude_check.h"
#include "solver/pose/corner_pnp.h"
#include "solver/pose/tags_camera.h"

namespace mavloc {

PixhawkKfEstimator::PixhawkKfEstimator(const EstimatorOptions& options)
    : options_(options),
      upright_(ParseUpright2pSettings(options)),
      board_(ParseBoardInitOptions(options)) {
  if (!options.Has("min_inlier_ratio")) upright_.min_inlier_ratio = 0.5;
  source_ = options.GetString("source", "upright-2p");
  if (source_ != "upright-2p" && source_ != "pnp")
    throw InputError("option 'source=" + source_ + "': expected upright-2p or pnp");
  attitude_check_rad_ = options.GetDouble("attitude_check_deg", 5.0) * kDeg;
  use_measured_dt_ = options.GetBool("use_measured_dt", true);
  kf_.position_sigma_m = options.GetDouble("position_sigma_m", kf_.position_sigma_m);
  kf_.yaw_sigma_rad = options.GetDouble("yaw_sigma_deg", kf_.yaw_sigma_rad / kDeg) * kDeg;
  kf_.position_accel_density =
      options.GetDouble("position_accel_density", kf_.position_accel_density);
  kf_.yaw_accel_density = options.GetDouble("yaw_accel_density", kf_.yaw_accel_density);
  kf_.coast_limit_s = options.GetDouble("coast_limit_s", kf_.coast_limit_s);
  if (!(kf_.position_sigma_m > 0 && kf_.yaw_sigma_rad > 0 && kf_.position_accel_density > 0 &&
        kf_.yaw_accel_density > 0 && kf_.coast_limit_s > 0))
    throw InputError("pixhawk-kf: noise options and coast_limit_s must be > 0");
}

Applicability PixhawkKfEstimator::AppliesTo(const Dataset& dataset) const {
  if (dataset.tags.empty()) return Applicability::No("needs tags0 corner observations");
  if (dataset.map.tags.empty()) return Applicability::No("needs tags (markers) in map.yaml");
  const std::string camera = TagsCameraMissing(dataset);
  if (!camera.empty()) return Applicability::No(camera);
  const std::string missing = RollPitchSourceMissing(dataset, upright_.source);
  if (!missing.empty()) return Applicability::No(missing);
  const std::string board = BoardWorldMissing(dataset);
  if (!board.empty()) return Applicability::No(board);
  return Applicability::Yes();
}

Estimate PixhawkKfEstimator::Run(const Dataset& dataset) {
  return RunInWorldFrame(dataset, board_, [&](const Dataset& dataset_W, const BoardWorld* board) {
    return RunInWorld(dataset_W, board);
  });
}

Estimate PixhawkKfEstimator::RunInWorld(const Dataset& dataset, const BoardWorld* board) {
  Estimate estimate;
  estimate.quantities = MakeQuantityTable({"x", "y", "z", "yaw", "vx", "vy", "vz"});
  const CameraSensor& camera = *TagsCamera(dataset);
  RollPitchSource source(dataset, upright_.source, options_);
  PixhawkKf kf(kf_);
  const TimeNs nominal_period_ns =
      SecondsToNs(1.0 / (camera.rate_hz > 0.0 ? camera.rate_hz : 30.0));
  TimeNs filter_time = 0;  // the filter's clock (the nominal one when use_measured_dt is false)
  bool first = true;

  for (const TagFrame& frame : GroupTagFrames(dataset)) {
    const TimeNs t_exposure = source.ExposureTime(frame.t_ns);
    if (board != nullptr && frame.t_ns < board->t_init_end_ns) {
      estimate.CountFailure("frame inside the gravity initialisation window");
      continue;
    }
    filter_time = use_measured_dt_ || first ? t_exposure : filter_time + nominal_period_ns;
    first = false;
    const auto roll_pitch = source.At(t_exposure);

    // The measurement of this frame, if any.
    std::optional<Pose> measurement;
    if (frame.observations.empty()) {
      estimate.CountFailure("no marker in view (predicted)");
    } else if (!roll_pitch) {
      estimate.CountFailure("no IMU attitude at the exposure time (predicted)");
    } else if (source_ == "upright-2p") {
      const Upright2pFrameResult r = Upright2pFrame(frame, dataset, *roll_pitch, upright_);
      if (r.ok) {
        measurement = r.pose.T_W_B;
      } else {
        estimate.CountRejection("rejected: " + r.reason + " (predicted)");
      }
    } else {
      const CornerPnpResult r = CornerPnp(frame.observations, dataset.map.tags, camera);
      if (!r.ok) {
        estimate.CountRejection("rejected: " + r.reason + " (predicted)");
      } else if (attitude_check_rad_ > 0.0 &&
                 !CheckAttitude(r.T_W_B.q, roll_pitch->roll_rad, roll_pitch->pitch_rad,
                                attitude_check_rad_)
                      .accepted) {
        estimate.CountRejection("rejected: roll/pitch disagree with the IMU (predicted)");
      } else {
        measurement = r.T_W_B;
      }
    }

    if (measurement) {
      kf.Update(filter_time, measurement->p, EulerFromQuaternion(measurement->q).yaw);
    } else {
      kf.Predict(filter_time);
    }
    if (!kf.tracking()) continue;
    const Eigen::Vector3d p = kf.position(), v = kf.velocity();
    estimate.quantities.Append(t_exposure, {p.x(), p.y(), p.z(), kf.yaw(), v.x(), v.y(), v.z()});
    if (roll_pitch) {
      const Pose T_W_B(QuaternionFromEuler({roll_pitch->roll_rad, roll_pitch->pitch_rad, kf.yaw()}),
                       p);
      estimate.poses.push_back({t_exposure, T_W_B});
    }
  }
  return estimate;
}

}  // namespace mavloc
