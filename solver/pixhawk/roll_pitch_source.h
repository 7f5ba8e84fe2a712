// Where the PIXHAWK estimators take the IMU's roll and pitch from, per image (sections 2.1, 3.2,
// 5): an attitude filter runs on imu0 and its outputs feed an AttitudeBuffer; each image reads the
// attitude interpolated at its exposure time, taken as the image's stamp minus a known transfer
// delay (image_delay_ms, 0 with hardware-triggered exposure stamps).
//
// Options (`--option key=value` of pnp, upright-2p and pixhawk-kf):
//   attitude = ekf (default): the gravity EKF of the three-point paper on imu0
//              (solver/attitude/gravity_ekf.h, its options as in gravity-ekf: accel_dynamics_sigma,
//              gyro_noise_density, accel_noise_density, estimate_gyro_bias);
//            = truth: the ground-truth roll and pitch plus a synthetic error, for controlled
//              sweeps of the IMU attitude error: a first-order Gauss-Markov process per axis,
//              stationary sigma attitude_error_deg (0), correlation time attitude_error_tau_s (1),
//              seed attitude_error_seed (1). Needs ground truth: an experiment, not a localizer.
//   image_delay_ms (0): subtracted from every image stamp before the lookup (and from the
//   output stamp), the compensation of a known mean transfer delay.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "core/dataset.h"
#include "solver/estimator.h"
#include "solver/pixhawk/attitude_buffer.h"

namespace mavloc {

struct RollPitchSourceOptions {
  std::string attitude = "ekf";
  double attitude_error_deg = 0.0;
  double attitude_error_tau_s = 1.0;
  uint64_t attitude_error_seed = 1;
  double image_delay_ms = 0.0;
};

// Parses the options above; throws InputError for malformed or unknown values.
RollPitchSourceOptions ParseRollPitchSourceOptions(const EstimatorOptions& options);
// Why the source cannot run on a dataset (empty when it can).
std::string RollPitchSourceMissing(const Dataset& dataset, const RollPitchSourceOptions& options);

class RollPitchSource {
 public:
  // Runs the attitude filter (or builds the perturbed truth) over the whole dataset.
  RollPitchSource(const Dataset& dataset, const RollPitchSourceOptions& options,
                  const EstimatorOptions& filter_options);

  // The exposure time of an image stamped t_stamp_ns.
  TimeNs ExposureTime(TimeNs t_stamp_ns) const;
  // The attitude at an exposure time. Queries must not go back in time by more than the buffer
  // span; samples up to the query are moved into the buffer first (the IMU data arrives before
  // the image, sect. 2.1). nullopt outside the attitude stream.
  std::optional<StampedRollPitch> At(TimeNs t_exposure_ns);

 private:
  TimeNs delay_ns_ = 0;
  std::vector<StampedRollPitch> series_;
  size_t next_ = 0;
  AttitudeBuffer buffer_;
};

// The frames of a dataset's tags0 stream: the stamps of the tags' camera's frames (cameras[0]; or,
// without its frames, the distinct tag stamps), each with its observations.
struct TagFrame {
  TimeNs t_ns = 0;
  std::vector<TagObservation> observations;
};
std::vector<TagFrame> GroupTagFrames(const Dataset& dataset);

// Corner correspondences of a frame: world corners and undistorted normalized image coordinates
// (tags not in the map, and corners that do not undistort, are skipped).
void FrameCorners(const std::vector<TagObservation>& observations, const WorldMap& map,
                  const CameraModel& model, std::vector<Eigen::Vector3d>* X_W,
                  std::vector<Eigen::Vector2d>* xy_C);

}  // namespace mavloc
