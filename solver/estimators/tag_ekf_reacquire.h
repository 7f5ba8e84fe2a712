// tag-ekf's re-acquisition after lost lock. The paper's filter (solver/tag_ekf/tag_ekf.h) gates
// every tag whose innovation exceeds the chi-square bound; after a gap in the tag sightings on a
// real log its state can have drifted further than its covariance admits, and from then on every
// tag is gated out and the filter never recovers. Lost lock is declared after `frames` consecutive
// frames whose every map tag was gated out; the filter then restarts from the whole-frame PnP of
// those frames: position and attitude from the last frame's PnP, velocity from a least-squares
// line through their PnP positions, the biases kept with their covariance, and the pose and
// velocity covariance reset to the re-acquisition sigmas.
#pragma once

#include <optional>
#include <vector>

#include "core/pose.h"
#include "solver/estimator.h"
#include "solver/tag_ekf/tag_ekf.h"

namespace mavloc {

struct ReacquireOptions {
  bool enabled = true;               // reacquire (0: the paper's filter, which never recovers)
  int frames = 5;                    // reacquire_frames: consecutive fully gated frames
  double position_sigma_m = 0.05;    // reacquire_pos_sigma
  double velocity_sigma_m_s = 0.5;   // reacquire_vel_sigma
  double attitude_sigma_rad = 0.05;  // reacquire_att_sigma
};

// From `--option reacquire=0|1, reacquire_frames=N (>= 2), reacquire_pos_sigma,
// reacquire_vel_sigma, reacquire_att_sigma (> 0)`; throws InputError naming a bad option.
ReacquireOptions ParseReacquireOptions(const EstimatorOptions& options);

struct ReacquiredState {
  TagEkfVector x;
  TagEkfMatrix P;
};

// The state at now_ns from the PnP poses T_W_B of the gated frames (sorted by time), keeping the
// biases of x_now and their covariance in P_now. nullopt with fewer than two poses or when they
// all share one stamp.
std::optional<ReacquiredState> ReacquireState(const std::vector<StampedPose>& pnp_poses,
                                              TimeNs now_ns, const TagEkfVector& x_now,
                                              const TagEkfMatrix& P_now,
                                              const ReacquireOptions& options);

}  // namespace mavloc
