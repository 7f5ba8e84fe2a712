// tag-ekf: the AprilTag paper's 15-state continuous-discrete EKF (solver/tag_ekf/tag_ekf.h) on a
// dataset: prediction with every imu0 sample (100 Hz in the paper), and for every cam0 frame of
// tags0 one pose measurement per tag (eq. 4) from a per-tag PnP on its 4 corners
// (solver/pose/corner_pnp.h), applied sequentially. The measurements of the image exposed at t
// become available at t + delay_s (Fig. 4); with compensate_delay they are applied at t and the
// state re-propagated to the present (Fig. 3), otherwise to the present state as they are.
// The reported state at each output time is the filter's present (real-time) estimate.
//
// Output: x, y, z, vx, vy, vz, roll, pitch, yaw (mavloc's Rz Ry Rx angles, converted from the
// filter's 1-2-3 angles), bgx..baz, and the covariance of the first nine (for NEES).
//
// Options (`--option key=value`):
//   delay_s            processing delay (default: scenario.yaml's processing_delay_s, else 0)
//   compensate_delay   1 (Fig. 3-4) / 0 (naive)
//   use_tags           1 / 0 (0: prediction only, the paper's "no tags" run of Fig. 13)
//   init               truth | zero | perturbed | window (default: window on a board map, else
//                      scenario.yaml's filter_init, else truth). window: the filter starts at the
//                      last frame of the initial window (the first gravity_init_s seconds from the
//                      first frame with a tag of the map), with that frame's whole-frame PnP pose,
//                      the velocity of a quadratic fit of the window's last second of PnP
//                      positions, zero biases (solver/board/pnp_initial_state.h); it needs no
//                      ground truth. truth and perturbed need ground truth in the filter's W, so
//                      not on a board map.
//   gravity_init_s, gravity_min_tags: the initial window (default 2 s) and the map tags a frame
//                      must see to be used in it (default 2; solver/board/board_world.h)
//   init_seed          seed of the perturbed initial state (default 1)
//   init_pos_sigma, init_vel_sigma, init_att_sigma, init_ba_sigma, init_bg_sigma: the initial
//                      standard deviations (P0; and the perturbation for init=perturbed);
//                      defaults 0.313 m (mean error norm 0.5 m, V-B), 0.1 m/s, 0.05 rad,
//                      0.05 m/s^2, 0.005 rad/s (init=window: 0.02 m, 0.1 m/s, 0.02 rad, same
//                      biases: the PnP start is far better than V-B's)
//   init_p0_scale      P0 = diag((scale * sigma)^2) (default 1: P0 matches the initial errors)
//   rate_hz            output rate (default 100; never above the IMU rate)
//   gate_chi2          per-tag innovation gate (default 22.46; 0 disables)
//   accel_var, gyro_var, accel_bias_var, gyro_bias_var, position_var, attitude_var: Table I
//   camera             default: the tags' camera (cameras[0])
//   reacquire          1 (default) / 0: after reacquire_frames (default 5) consecutive frames whose
//                      every tag was gated out, restart from their whole-frame PnP
//                      (tag_ekf_reacquire.h; reacquire_pos_sigma 0.05 m, reacquire_vel_sigma
//                      0.5 m/s, reacquire_att_sigma 0.05 rad); 0 is the paper's filter, which
//                      never recovers from lost lock. Each reset is an event line of the report;
//                      their count is the parameter tag_ekf_resets.
//
// On a board map (MapFrame::kBoard) the map is first put into the gravity-aligned W of
// core/board_frame.h from the PnP poses and IMU of the initial window (solver/board/board_world.h),
// and the filter starts at the window's end (init=window): it stays causal, no measurement it
// uses precedes the T_W_M it is expressed with. The estimate carries T_W_M and board_roll,
// board_pitch.
#pragma once

#include <optional>
#include <string>
#include <utility>

#include "solver/board/board_world.h"
#include "solver/estimator.h"
#include "solver/estimators/tag_ekf_reacquire.h"
#include "solver/tag_ekf/tag_ekf.h"

namespace mavloc {

class TagEkfEstimator : public Estimator {
 public:
  explicit TagEkfEstimator(const EstimatorOptions& options);
  std::string name() const override { return "tag-ekf"; }
  Applicability AppliesTo(const Dataset& dataset) const override;
  Estimate Run(const Dataset& dataset) override;

 private:
  std::string InitMode(const Dataset& dataset) const;
  // init=window uses [window_begin, window_end] (the board initialisation's window on a board map)
  // or, when unset, the first gravity_init_s seconds from the first frame with a map tag.
  Estimate RunInWorld(const Dataset& dataset,
                      std::optional<std::pair<TimeNs, TimeNs>> window = std::nullopt);

  EstimatorOptions options_;
  BoardInitOptions board_;
  ReacquireOptions reacquire_;
};

}  // namespace mavloc
