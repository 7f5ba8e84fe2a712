// A check across frames for per-frame poses: a pose whose position lies more than gate_m from the
// component-wise median position of its neighbouring posed frames (as many before it as after it
// in time, up to frames / 2 on each side, fewer near the ends; itself left out) is refused.
// Per-frame PnP on a loose map fails in runs of single far tags whose planar pose flips (the camera
// tilts and its position swings by metres); no per-frame test sees that, but the frames around it
// do. The median keeps the check robust while fewer than half of the neighbours are wrong. Offline
// and non-causal: the poses after a frame count as much as those before it. The gate assumes the
// vehicle moves less than gate_m relative to the median of its neighbours over the window, so
// frames and gate_m go together with the frame rate and the speed (6 Hz and a hand-held rig: 20
// frames, 0.3 m). Options (tag-pnp): neighbour_gate_m (0: off), neighbour_frames (20, >= 2).
#pragma once

#include <string>
#include <vector>

#include "core/pose.h"
#include "core/time.h"
#include "solver/estimator.h"

namespace mavloc {

struct NeighbourGateOptions {
  double gate_m = 0.0;  // 0: off
  int frames = 20;      // neighbours considered, half on each side
  bool enabled() const { return gate_m > 0.0; }
};

NeighbourGateOptions ParseNeighbourGateOptions(const EstimatorOptions& options);

// positions_W: the posed frames in time order. Returns, per frame, true when it is refused. The
// first and the last frame are kept (no neighbour on one side: nothing to compare with).
std::vector<bool> NeighbourGateRefusals(const std::vector<Eigen::Vector3d>& positions_W,
                                        const NeighbourGateOptions& options);

// The failure reason a refused frame is counted under.
std::string NeighbourGateReason(const NeighbourGateOptions& options);

}  // namespace mavloc
