// Relative error over sub-trajectory lengths, as rpg_trajectory_evaluation defines it
// (Zhang & Scaramuzza, "A Tutorial on Quantitative Trajectory Evaluation for Visual(-Inertial)
// Odometry", IROS 2018, sec. IV-B; src/rpg_trajectory_evaluation/compute_trajectory_errors.py
// compute_relative_error and trajectory_utils.py compute_comparison_indices_length), which is the
// KITTI odometry benchmark's segment error (Geiger et al., CVPR 2012, devkit evaluate_odometry.cpp)
// with a start at every frame instead of every 10th.
//
// Sampling (rpg): dist(i) is the truth's accumulated path length at pair i. For every start i, the
// end j is the index in [i, n) minimising |dist(j) - (dist(i) + d)|, kept when that difference is
// strictly below max_length_diff = fraction * d (rpg: 0.2 d; the first index reaching the minimum
// wins, as rpg's strict '<' keeps the first). rpg then pairs the k-th start that found an end with
// the k-th end found (its list drops the starts without one), which equals start i -> end(i)
// whenever the starts with an end form a prefix 0..K (the usual case: only the last starts have no
// end); mavloc always pairs start i with end(i). rpg computes nothing when fewer than 2 segments
// fit; mavloc then returns an empty result too. ov_eval differs: an absolute 0.5 m tolerance
// instead of 0.2 d, and no division by d.
// Segment error (rpg, in the world frame of the estimate's end pose):
//   dT_est = T_est,i^-1 T_est,j (its translation times the Sim3 scale), dT_gt = T_gt,i^-1 T_gt,j,
//   E_c = dT_gt^-1 dT_est,  E_w = Rot(T_est,j) E_c Rot(T_est,j)^-1.
//   translation_m = ||t(E_w)|| (= ||t(E_c)||), translation_percent = 100 translation_m / d,
//   rotation_deg = angle(R(E_w)) (= angle of E_c), rotation_deg_per_m = rotation_deg / d,
//   yaw_deg = |yaw| and tilt_deg = sqrt(pitch^2 + roll^2) of R(E_w) as ZYX Euler angles (rpg's
//   'rzyx'), the part of the error that gravity can and cannot observe.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "evaluation/association.h"
#include "evaluation/trajectory_metrics.h"

namespace mavloc {

struct RelativeErrorAtLength {
  double length_m = 0.0;
  // Per segment, in start order (for boxplots).
  std::vector<TimeNs> start_t_ns;
  std::vector<double> translation_m;
  std::vector<double> translation_percent;
  std::vector<double> rotation_deg;
  std::vector<double> rotation_deg_per_m;
  std::vector<double> yaw_deg;
  std::vector<double> tilt_deg;
  // Their statistics.
  ErrorStatistics translation_m_stats;
  ErrorStatistics translation_percent_stats;
  ErrorStatistics rotation_deg_stats;
  ErrorStatistics rotation_deg_per_m_stats;
  ErrorStatistics yaw_deg_stats;
  ErrorStatistics tilt_deg_stats;
  size_t segments = 0;  // also when the per-segment values were dropped (their statistics kept)
  size_t count() const { return segments; }
};

// Accumulated path length of the truth positions: dist(0) = 0, dist(i) = dist(i-1) + |p_i -
// p_(i-1)| (rpg get_distance_from_start).
std::vector<double> AccumulatedDistances(const PairedPoses& pairs);

// The default lengths (rpg trajectory.py compute_boxplot_distances): each fraction f of the
// truth's path length L truncated to 2 decimals, trunc(100 f L) / 100 metres, L being the path
// length of the whole truth given (rpg: of the raw ground truth, not only of the matched poses);
// lengths that truncate to 0 are dropped.
std::vector<double> DefaultRelativeLengths(double path_length_m,
                                           const std::vector<double>& fractions);

// For every start index, the end index (or -1) as rpg's compute_comparison_indices_length.
std::vector<long> SegmentEndIndices(const std::vector<double>& distances, double length_m,
                                    double max_length_diff_m);

// Relative errors of one length. scale multiplies the estimate's relative translation (rpg uses
// the unaligned estimate with the Sim3 scale of the alignment; with pairs already aligned, pass
// scale 1 and R_raw_aligned). Empty (count() == 0) when fewer than 2 segments fit, as rpg.
// R_raw_aligned: the rotation from the frame of the pairs' estimate to the estimate's own world,
// in which rpg expresses E_w (yaw and tilt depend on it; the other values do not): the transpose
// of the alignment's rotation when the pairs hold the aligned estimate, identity for raw ones.
// keep_segments false keeps the length, the segment count and the statistics alone,
// each series released once its statistics are taken.
RelativeErrorAtLength ComputeRelativeError(
    const PairedPoses& pairs, const std::vector<double>& distances, double length_m,
    double max_length_diff_fraction = 0.2, double scale = 1.0,
    const Eigen::Matrix3d& R_raw_aligned = Eigen::Matrix3d::Identity(), bool keep_segments = true);

}  // namespace mavloc
