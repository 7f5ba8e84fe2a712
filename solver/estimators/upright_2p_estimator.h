// upright-2p: PIXHAWK's IMU-aided marker pose (Meier et al. 2012, 3.2, fig. 15): per frame, the
// IMU roll and pitch at the exposure time (attitude filter on imu0 -> buffer -> interpolation,
// solver/pixhawk/roll_pitch_source.h) rotate the corner rays into the levelled frame (eq. 1); the
// known-vertical 2-point solver of Kukelova et al. (ACCV 2010) runs inside RANSAC and x, y, z,
// yaw are refined by least squares over all inlier corners (solver/pixhawk/upright_pose.h).
// Output at each frame: x, y, z, roll, pitch (the IMU's), yaw and the pose.
// On a board map (MapFrame::kBoard) the map is first put into the gravity-aligned W of
// core/board_frame.h from the first gravity_init_s seconds of PnP poses and IMU
// (solver/board/board_world.h); the IMU's roll and pitch are relative to gravity, so they hold in
// that W, and every frame (the window's included) is solved there. The estimate carries T_W_M and
// board_roll, board_pitch.
// Options: threshold_px (4), ransac (true; false = no outlier rejection), max_iterations (200),
// min_inliers (3), min_inlier_ratio (0: no ratio required), and the attitude-source options of
// roll_pitch_source.h (attitude, attitude_error_deg, attitude_error_tau_s, image_delay_ms, EKF
// options), gravity_init_s (2), gravity_min_tags (2).
#pragma once

#include <optional>

#include "solver/board/board_world.h"
#include "solver/estimator.h"
#include "solver/pixhawk/roll_pitch_source.h"
#include "solver/pixhawk/upright_pose.h"

namespace mavloc {

struct Upright2pSettings {
  UprightPoseOptions pose;
  RollPitchSourceOptions source;
  double min_inlier_ratio = 0.0;
};
Upright2pSettings ParseUpright2pSettings(const EstimatorOptions& options);

// The upright-2p pose of one frame, or a failure reason. `roll_pitch` is the IMU attitude at the
// frame's exposure time; the map must be in W (the tags' camera: cameras[0]).
struct Upright2pFrameResult {
  bool ok = false;
  std::string reason;
  UprightPoseResult pose;
};
Upright2pFrameResult Upright2pFrame(const TagFrame& frame, const Dataset& dataset,
                                    const StampedRollPitch& roll_pitch,
                                    const Upright2pSettings& settings);

class Upright2pEstimator : public Estimator {
 public:
  explicit Upright2pEstimator(const EstimatorOptions& options);
  std::string name() const override { return "upright-2p"; }
  Applicability AppliesTo(const Dataset& dataset) const override;
  Estimate Run(const Dataset& dataset) override;

 private:
  Estimate RunInWorld(const Dataset& dataset);

  EstimatorOptions options_;
  Upright2pSettings settings_;
  BoardInitOptions board_;
};

}  // namespace mavloc
