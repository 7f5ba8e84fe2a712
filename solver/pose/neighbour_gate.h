// A check across frames for per-frame poses: a pose whose position lies more than gate_m from
// where its neighbouring posed frames put it is refused. Per-frame PnP on a loose map fails in runs
// of single far tags whose planar pose flips (the camera tilts and its position swings by metres);
// no per-frame test sees that, but the frames around it do. Offline and non-causal: the poses after
// a frame count as much as those before it.
//
// The neighbours are up to frames / 2 posed frames on each side, within window_s / 2 in time (a
// log whose tags are seen in short runs seconds apart has no neighbours across its gaps; the rig
// may have moved anywhere in between). Inside a run (three or more neighbours on both sides) the
// frame is compared with the component-wise median of as many neighbours after it as before it,
// which holds while fewer than half of them are wrong and on which a steady motion is centred.
// Next to a gap or an end of the log the neighbours lie on one side and their median lags behind a
// moving vehicle: the frame is then compared with the median of p_k + s (t_i - t_k), s the repeated
// median slope (Siegel 1982), when there are five neighbours or more; with fewer it is kept.
//
// The gate assumes the vehicle moves less than gate_m relative to that prediction: for a steady
// turn of centripetal acceleration a, the median over a window of half-width h lags by about
// a h^2 / 8, 0.03 m for a hand-held rig (0.5 m/s^2, h = 0.75 s) and 0.16 m for an aggressive flight
// (5 m/s^2) at 20 Hz (20 frames, h = 0.5 s). The default gate, 0.2 m, is the tightest round one
// above that lag and above the noise of a per-frame PnP on tags metres away (a few centimetres);
// it refuses no frame of the synthetic tag scenarios or of EuRoC's hand-waved aprilgrid log.
// Options (tag-pnp): neighbour_gate_m (0.2; 0: off),
// neighbour_frames (20, >= 2), neighbour_window_s (1.5 s; 0: no bound in time).
#pragma once

#include <string>
#include <vector>

#include "core/pose.h"
#include "core/time.h"
#include "solver/estimator.h"

namespace mavloc {

struct NeighbourGateOptions {
  double gate_m = 0.2;    // 0: off
  int frames = 20;        // neighbours considered, half on each side
  double window_s = 1.5;  // neighbours within window_s / 2 of the frame; 0: no bound
  bool enabled() const { return gate_m > 0.0; }
};

NeighbourGateOptions ParseNeighbourGateOptions(const EstimatorOptions& options);

// times_s, positions_W: the posed frames in time order. Returns, per frame, true when it is
// refused. A frame with no neighbour on one side within the window is kept (nothing to compare
// with). Throws std::invalid_argument when the two sizes differ.
std::vector<bool> NeighbourGateRefusals(const std::vector<double>& times_s,
                                        const std::vector<Eigen::Vector3d>& positions_W,
                                        const NeighbourGateOptions& options);

// The failure reason a refused frame is counted under.
std::string NeighbourGateReason(const NeighbourGateOptions& options);

}  // namespace mavloc
