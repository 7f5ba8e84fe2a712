// Timestamp association between an estimate and the ground truth.
// - Nearest: each estimate stamp is paired with the nearest ground-truth stamp within max_dt.
// - Interpolated: the ground truth is interpolated at each estimate stamp that lies inside the
//   ground truth's span and within max_dt of a ground-truth sample: positions and scalars linearly,
//   rotations by slerp, angle quantities along the shorter arc.
#pragma once

#include <vector>

#include "core/dataset.h"
#include "core/pose.h"
#include "core/quantities.h"
#include "evaluation/paired_poses.h"

namespace mavloc {

enum class AssociationMode { kNearest, kInterpolate };

// Pairs estimated poses with ground truth. Estimates outside the ground truth span, or farther
// than max_dt_s from a ground truth sample, are dropped.
std::vector<PosePair> AssociatePoses(const std::vector<StampedPose>& estimate,
                                     const std::vector<StampedPose>& ground_truth, double max_dt_s,
                                     AssociationMode mode = AssociationMode::kInterpolate);

// The association of trajectory evaluation (trajectory_evaluation.h), with the stamps of the
// estimate shifted by time_offset_s first (evo's --t_offset, added to the estimate's stamps).
// - kNearest follows evo/core/sync.py associate_trajectories + matching_time_indices exactly:
//   the SHORTER of the two trajectories is walked (the estimate when both have the same length),
//   each of its stamps is paired with the nearest stamp of the other (the earlier one on a tie:
//   numpy.argmin keeps the first minimum) when |dt| <= max_dt_s. A stamp of the longer one may
//   thus be used by several pairs, as in evo. Pairs come in the order of the walked trajectory.
//   mavloc compares integer nanoseconds, evo float seconds: a gap of exactly max_dt_s always
//   matches here, in evo it depends on rounding.
// - kInterpolate (mavloc, like ov_eval's and TUM's interpolating tools): every estimate stamp
//   inside the truth's span with a truth sample within max_dt_s is paired with the truth
//   interpolated there (positions linearly, rotations by slerp).
// Both run as a linear merge of the two sorted stamp sequences (O(n + m)). Inputs must be sorted
// by time. pair.t_ns is the estimate's stamp plus the offset (truth time).
struct AssociationOptions {
  AssociationMode mode = AssociationMode::kNearest;
  double max_dt_s = 0.01;  // evo's default --t_max_diff
  double time_offset_s = 0.0;
  // Nearest mode only: false leaves `pairs` empty and fills the two index lists alone (what a
  // caller that only needs positions uses; saves 120 bytes per pair).
  bool make_pairs = true;
  // false leaves the two index lists empty (what a caller of the pairs alone uses).
  bool make_indices = true;
};
struct AssociationResult {
  std::vector<PosePair> pairs;
  std::vector<size_t> estimate_index;  // per pair, the estimate pose used
  std::vector<size_t> truth_index;     // per pair, the truth pose used (the lower node when
                                       // interpolated)
};
AssociationResult AssociateTrajectories(const std::vector<StampedPose>& estimate,
                                        const std::vector<StampedPose>& truth,
                                        const AssociationOptions& options);
// The same association as pairs by index (paired_poses.h), which read estimate and truth in
// place: both must outlive the result. make_pairs and make_indices are ignored.
PairedPoses AssociatePairs(const std::vector<StampedPose>& estimate,
                           const std::vector<StampedPose>& truth,
                           const AssociationOptions& options);

// The ground truth's named quantities at the given stamps (same rule), as a table with the
// requested names. Rows that cannot be associated are dropped (so the result's t_ns is a subset).
QuantityTable TruthQuantitiesAt(const QuantityTable& truth, const std::vector<TimeNs>& t_ns,
                                double max_dt_s,
                                AssociationMode mode = AssociationMode::kInterpolate);

// Ground truth as named quantities: x, y, z, roll, pitch, yaw, vx, vy, vz, bias components, and
// the dataset's extra truth quantities (interpolated to the ground-truth stamps).
QuantityTable GroundTruthQuantities(const Dataset& dataset);
std::vector<StampedPose> GroundTruthPoses(const Dataset& dataset);

}  // namespace mavloc
