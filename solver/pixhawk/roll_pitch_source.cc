#include "solver/pixhawk/roll_pitch_source.h"

#include <cmath>
#include <map>

#include "core/errors.h"
#include "core/random.h"
#include "core/rotation.h"
#include "core/tag_geometry.h"
#include "solver/attitude/gravity_ekf.h"
#include "solver/estimators/gravity_ekf_estimator.h"
#include "solver/pose/tags_camera.h"

namespace mavloc {

RollPitchSourceOptions ParseRollPitchSourceOptions(const EstimatorOptions& options) {
  RollPitchSourceOptions out;
  out.attitude = options.GetString("attitude", out.attitude);
  if (out.attitude != "ekf" && out.attitude != "truth")
    throw InputError("option 'attitude=" + out.attitude + "': expected ekf or truth");
  out.attitude_error_deg = options.GetDouble("attitude_error_deg", out.attitude_error_deg);
  out.attitude_error_tau_s = options.GetDouble("attitude_error_tau_s", out.attitude_error_tau_s);
  out.attitude_error_seed = static_cast<uint64_t>(options.GetInt("attitude_error_seed", 1));
  out.image_delay_ms = options.GetDouble("image_delay_ms", out.image_delay_ms);
  if (out.attitude_error_deg < 0.0 || out.attitude_error_tau_s <= 0.0)
    throw InputError("options attitude_error_deg must be >= 0 and attitude_error_tau_s > 0");
  return out;
}

std::string RollPitchSourceMissing(const Dataset& dataset, const RollPitchSourceOptions& options) {
  if (options.attitude == "ekf" && dataset.imu.samples.size() < 2)
    return "needs imu0 samples for the attitude filter";
  if (options.attitude == "truth" && dataset.ground_truth.size() < 2)
    return "attitude=truth needs ground truth";
  return "";
}

RollPitchSource::RollPitchSource(const Dataset& dataset, const RollPitchSourceOptions& options,
                                 const EstimatorOptions& filter_options)
    : delay_ns_(SecondsToNs(1e-3 * options.image_delay_ms)), buffer_(400) {
  if (options.attitude == "ekf") {
    const auto estimates =
        EstimateRollPitch(dataset.imu.samples, GravityEkfOptionsFor(dataset, filter_options));
    series_.reserve(estimates.size());
    for (const auto& e : estimates) series_.push_back({e.t_ns, e.roll_rad, e.pitch_rad});
    return;
  }
  // Truth + first-order Gauss-Markov error e_k = a e_{k-1} + sqrt(1 - a^2) sigma n_k.
  Rng rng(options.attitude_error_seed);
  const double sigma = options.attitude_error_deg * M_PI / 180.0;
  Eigen::Vector2d error{sigma * rng.Gaussian(), sigma * rng.Gaussian()};
  TimeNs previous = 0;
  for (size_t k = 0; k < dataset.ground_truth.size(); ++k) {
    const GroundTruthState& gt = dataset.ground_truth[k];
    if (k > 0) {
      const double a = std::exp(-NsToSeconds(gt.t_ns - previous) / options.attitude_error_tau_s);
      const double s = std::sqrt(std::max(0.0, 1.0 - a * a)) * sigma;
      error = a * error + Eigen::Vector2d{s * rng.Gaussian(), s * rng.Gaussian()};
    }
    previous = gt.t_ns;
    const EulerRpy rpy = EulerFromQuaternion(gt.T_W_B.q);
    series_.push_back({gt.t_ns, WrapAngle(rpy.roll + error.x()), rpy.pitch + error.y()});
  }
}

TimeNs RollPitchSource::ExposureTime(TimeNs t_stamp_ns) const { return t_stamp_ns - delay_ns_; }

std::optional<StampedRollPitch> RollPitchSource::At(TimeNs t_exposure_ns) {
  // Move every sample up to (and one past) the query into the buffer.
  while (next_ < series_.size() && (buffer_.empty() || buffer_.newest_ns() < t_exposure_ns)) {
    buffer_.Push(series_[next_++]);
  }
  return buffer_.At(t_exposure_ns);
}

std::vector<TagFrame> GroupTagFrames(const Dataset& dataset) {
  std::map<TimeNs, TagFrame> frames;
  const CameraSensor* cam0 = TagsCamera(dataset);
  if (cam0) {
    for (const auto& f : cam0->frames) frames[f.t_ns].t_ns = f.t_ns;
  }
  for (const auto& obs : dataset.tags) {
    TagFrame& frame = frames[obs.t_ns];
    frame.t_ns = obs.t_ns;
    frame.observations.push_back(obs);
  }
  std::vector<TagFrame> out;
  out.reserve(frames.size());
  for (auto& [t, frame] : frames) out.push_back(std::move(frame));
  return out;
}

void FrameCorners(const std::vector<TagObservation>& observations, const WorldMap& map,
                  const CameraModel& model, std::vector<Eigen::Vector3d>* X_W,
                  std::vector<Eigen::Vector2d>* xy_C) {
  X_W->clear();
  xy_C->clear();
  for (const auto& obs : observations) {
    const auto it = map.tags.find(obs.tag_id);
    if (it == map.tags.end()) continue;
    const auto corners_W = TagCornersInWorld(it->second);
    for (int k = 0; k < 4; ++k) {
      const auto xy = model.PixelToNormalized(obs.corners_px[k]);
      if (!xy) continue;
      X_W->push_back(corners_W[k]);
      xy_C->push_back(*xy);
    }
  }
}

}  // namespace mavloc
