// A filter's initial state from the per-frame PnP poses of an initial window (solver/board/
// frame_pnp.h), for filters that start once the window is over (tag-ekf's init=window, on board
// logs where no true initial state exists): the pose of the window's last frame; the velocity from
// a least-squares quadratic fit of the positions of the last fit_s seconds, p(t) = a + b t + c t^2
// (t relative to the last frame), v = b; the biases are left to the caller (zero).
#pragma once

#include <Eigen/Core>
#include <optional>
#include <vector>

#include "core/pose.h"

namespace mavloc {

struct PnpInitialState {
  TimeNs t_ns = 0;  // the last pose's stamp
  Pose T_W_B;
  Eigen::Vector3d v_W = Eigen::Vector3d::Zero();
  int num_poses_fitted = 0;
};

// nullopt without poses. With 1 pose the velocity is zero, with 2 a finite difference.
std::optional<PnpInitialState> InitialStateFromPoses(const std::vector<StampedPose>& T_W_B,
                                                     double fit_s = 1.0);

}  // namespace mavloc
