// pixhawk-kf: PIXHAWK's localization pipeline (Meier et al. 2012, 3.3 and 5.1): per frame a vision
// pose, outlier rejection, and the 4 x 1-D constant-velocity Kalman filters on x, y, z and yaw
// (solver/pixhawk/pixhawk_kf.h) with the measured inter-frame dt; a rejected or missing
// measurement makes the filter only predict for that frame.
// Options:
//   source = upright-2p (default: RANSAC known-vertical pose, as the paper feeds the filter) | pnp
//     (vision-only pose);
//   attitude_check_deg (5; 0 = off): with source=pnp, reject a pose whose roll or pitch differs
//     from the IMU's by more than this (3.3; solver/pixhawk/attitude_check.h). With upright-2p the
//     pose's roll and pitch are the IMU's, so there the check cannot apply and frames are
//     rejected when RANSAC fails or keeps fewer than min_inlier_ratio (0.5) of the corners;
//   position_sigma_m (0.02), yaw_sigma_deg (1), position_accel_density (0.5 m^2/s^3),
//     yaw_accel_density (0.05 rad^2/s^3), coast_limit_s (0.5): the filters (pixhawk_kf.h);
//   use_measured_dt (true; false = every processed frame is taken as one nominal camera period
//     apart, to show why the measured dt matters when frames are dropped);
//   and upright-2p's options and the attitude-source options (roll_pitch_source.h).
//   gravity_init_s (2), gravity_min_tags (2): the board initialisation window (below).
// Output at each frame while tracking: x, y, z, yaw, vx, vy, vz, and the pose with the IMU's
// roll and pitch.
// On a board map (MapFrame::kBoard) the map is first put into the gravity-aligned W of
// core/board_frame.h from the PnP poses and IMU of the first gravity_init_s seconds
// (solver/board/board_world.h). The filter is causal: it starts with the first frame at the end of
// that window (the frames inside it are counted as "frame inside the gravity initialisation
// window"), so no measurement it uses precedes the T_W_M it is expressed with. The estimate carries
// T_W_M and board_roll, board_pitch.
#pragma once

#include "solver/board/board_world.h"
#include "solver/estimator.h"
#include "solver/estimators/upright_2p_estimator.h"
#include "solver/pixhawk/pixhawk_kf.h"

namespace mavloc {

class PixhawkKfEstimator : public Estimator {
 public:
  explicit PixhawkKfEstimator(const EstimatorOptions& options);
  std::string name() const override { return "pixhawk-kf"; }
  Applicability AppliesTo(const Dataset& dataset) const override;
  Estimate Run(const Dataset& dataset) override;

 private:
  Estimate RunInWorld(const Dataset& dataset, const BoardWorld* board);

  EstimatorOptions options_;
  Upright2pSettings upright_;
  BoardInitOptions board_;
  PixhawkKfOptions kf_;
  std::string source_;
  double attitude_check_rad_;
  bool use_measured_dt_;
};

}  // namespace mavloc
