// One entry point for evaluating an estimated trajectory against a ground truth, with the metrics
// of the three tools this field uses, each defined as that tool defines it:
// - evo (github.com/MichaelGrupp/evo): association (evo/core/sync.py), alignment
//   (evo/core/trajectory.py: Umeyama with n, correct_scale, only_scale; align_origin), APE and
//   RPE (evo/core/metrics.py) with the pair selection of evo/core/filters.py;
// - rpg_trajectory_evaluation (github.com/uzh-rpg/rpg_trajectory_evaluation): relative error over
//   sub-trajectories of length d along the truth's path (compute_trajectory_errors.py), in % of d
//   and deg/m, with yaw drift; the KITTI odometry benchmark uses the same segment error;
// - OpenVINS ov_eval: posyaw (4-DoF) alignment, where evo has none.
// Every choice, and where mavloc departs from a tool, is written next to the function that makes
// it (association.h, alignment.h, trajectory_metrics.h, relative_error.h,
// trajectory_diagnostics.h). Frames: W is the ground truth's world, B the tracked body; pose
// T_W_B. After alignment S (Similarity, alignment.h) the estimate is T_est' = S * T_est, i.e.
// p' = s R p + t, R' = R R_est (evo's scale-then-transform).
//
// Statistics (ErrorStatistics, as evo's get_all_statistics prints them) over errors e_1..e_n:
//   rmse = sqrt(sum e_i^2 / n), mean = sum e_i / n, median (mean of the two middle values for
//   even n, numpy.median), std = sqrt(sum (e_i - mean)^2 / n) (population, numpy.std),
//   min, max, sse = sum e_i^2.
//
// APE (absolute pose error, evo_ape), per associated pair i after alignment:
//   E_i = T_gt,i^-1 T_est',i
//   translation      e_i = || p_est',i - p_gt,i ||                [m]   (evo: translation_part)
//   rotation angle   e_i = | angle(R_E,i) |, angle from trace     [deg] (evo: rotation_angle_deg)
//   rotation part    e_i = || R_E,i - I_3 ||_F                   [-]   (evo: rotation_part)
//   full             e_i = || E_i - I_4 ||_F                     [-]   (evo: full_transformation)
//   (the translation of E_i is R_gt,i^T (p_est' - p_gt), same norm as evo's translation_part).
//
// RPE (relative pose error, evo_rpe), for index pairs (i, j) chosen by the delta (below):
//   E_ij = (T_gt,i^-1 T_gt,j)^-1 (T_est,i^-1 T_est,j)
//   with the same four error functions of E_ij. Alignment does not change E_ij except through the
//   Sim3 scale, which evo applies to the estimate before RPE too (so does mavloc).
//   Pair selection (evo/core/metrics.py id_pairs_from_delta -> evo/core/filters.py), on the
//   path of the aligned estimate as evo does by default (on the truth's with
//   RpeDelta::pairs_from_reference, evo's --pairs_from_reference):
//   - frames, consecutive: ids 0, d, 2d, ... < n; pairs (ids[k], ids[k+1]);
//     all_pairs: (i, i + d) for every i with i + d < n;
//   - metres, consecutive: walking the path from pose 0, an index is kept each time the path
//     accumulated since the last kept index (or since pose 0) reaches d; pairs of successive kept
//     indices (pose 0 itself is not kept); all_pairs: for each i, the j > i whose path length
//     from i is closest to d (first on ties), kept when |path(i, j) - d| <= rel_delta_tol * d;
//   - seconds (mavloc; evo has no time unit): the same as metres with the pairs' stamps as the
//     abscissa.
//
// Relative error over sub-trajectory lengths (rpg_trajectory_evaluation, KITTI):
//   for each length d and each start frame i (every associated frame, as rpg; KITTI steps 10
//   frames), the end frame j >= i whose distance along the truth is closest to dist(i) + d,
//   accepted within max_length_diff_fraction * d (rpg: 0.2 d). The segment error, expressed in W
//   as rpg does, E_w = R_est,j (dT_gt^-1 dT_est) R_est,j^T with dT = T_i^-1 T_j (scale applied to
//   the estimate's translation), gives: translation ||t(E)|| [m] and 100 ||t(E)|| / d [%];
//   rotation angle(E) [deg] and angle / d [deg/m]; yaw |yaw(E)| [deg] (ZYX Euler of E) and tilt
//   sqrt(pitch^2 + roll^2) [deg]. Default lengths: floor(f * L) for f = 0.1..0.5 of the truth's
//   path length L over the pairs (rpg's compute_boxplot_distances), lengths < 1e-9 m skipped.
//
// Yaw drift (mavloc): e_yaw,i = yaw of the world-frame error R_est',i R_gt,i^T (ZYX Euler; an
// estimate whose world turned by delta about gravity gives Rz(delta)), unwrapped over i; the
// least-squares slopes of e_yaw against the truth's path length [deg/m] and against time
// [deg/s], and the last minus the first yaw error [deg].
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "core/pose.h"
#include "evaluation/alignment.h"
#include "evaluation/association.h"
#include "evaluation/relative_error.h"
#include "evaluation/trajectory_diagnostics.h"
#include "evaluation/trajectory_metrics.h"

namespace mavloc {

struct EvaluationProtocol {
  // Association (association.h). evo_ape/evo_rpe: nearest with max_diff 0.01 s.
  AssociationMode association = AssociationMode::kNearest;
  double max_dt_s = 0.01;
  // Added to every estimate stamp before association (evo's --t_offset, applied to traj_est).
  double time_offset_s = 0.0;

  // Alignment (alignment.h): mode, and the first n_to_align associated pairs used to estimate it
  // (-1: all pairs; evo's --n_to_align; n_to_align = 1 with se3/posyaw aligns the first poses as
  // rpg/ov_eval do, since Umeyama needs >= 3 points). align_origin (evo's --align_origin):
  // T_gt,0 T_est,0^-1; as in evo it excludes any other alignment (mode must be none).
  AlignmentMode alignment = AlignmentMode::kSe3;
  long n_to_align = -1;
  bool align_origin = false;

  // The APE pose relation reported as the headline (all four are always computed).
  PoseRelation ape_relation = PoseRelation::kTranslation;

  // RPE deltas (evo_rpe --delta --delta_unit --all_pairs); default evo's 1 frame.
  std::vector<RpeDelta> rpe_deltas{RpeDelta{}};

  // Relative error (rpg): explicit lengths in metres, or when empty floor(f * L) for these
  // fractions of the truth's path length L.
  std::vector<double> relative_lengths_m;
  std::vector<double> relative_length_fractions{0.1, 0.2, 0.3, 0.4, 0.5};
  double max_length_diff_fraction = 0.2;  // rpg: max_dist_diff = 0.2 * d
  // Keep the per-pair errors (APE over time with the pairs' stamps, RPE per selected pair) and the
  // relative error of every segment, for CSVs, figures and boxplots; false keeps only counts and
  // statistics (a million-pose trajectory has millions of segments).
  bool keep_series = true;

  // Diagnostics (trajectory_diagnostics.h); metric_estimator: a Sim3 scale far from 1 is a fault.
  DiagnosticOptions diagnostics;
};

// Per-pair APE errors in pair order (the pairs' stamps in pair_t_ns).
struct ApeSeries {
  std::vector<double> translation_m;
  std::vector<double> rotation_deg;
  std::vector<double> rotation_part;
  std::vector<double> full;
};

struct YawDrift {
  bool valid = false;
  double rate_deg_per_m = 0.0;  // slope of the unwrapped yaw error against path length
  double rate_deg_per_s = 0.0;  // against time
  double final_deg = 0.0;       // yaw error at the last pair minus at the first
};

struct TrajectoryEvaluation {
  EvaluationProtocol protocol;  // echoed, with defaults resolved (relative lengths filled in)
  size_t estimate_count = 0;
  size_t truth_count = 0;
  size_t pair_count = 0;
  double truth_path_length_m = 0.0;  // along the associated truth poses
  double duration_s = 0.0;           // between the first and last pair

  // Alignment applied to the estimate (identity for none) and the number of pairs it used.
  Similarity alignment;
  size_t aligned_pairs = 0;

  // APE statistics (evo) and per-pair values over time.
  ErrorStatistics ape_translation_m;
  ErrorStatistics ape_rotation_deg;
  ErrorStatistics ape_rotation_part;
  ErrorStatistics ape_full;
  std::vector<TimeNs> pair_t_ns;  // estimate stamps of the pairs (time offset applied)
  ApeSeries ape;                  // empty when !protocol.keep_series

  std::vector<RpeDeltaResult> rpe;              // one per protocol.rpe_deltas entry
  std::vector<RelativeErrorAtLength> relative;  // one per relative length
  YawDrift yaw_drift;
  TrajectoryDiagnostics diagnostics;

  // The statistics of the headline APE relation.
  const ErrorStatistics& HeadlineApe() const;
};

// Evaluates estimate against truth (both sorted by time, stamps unique). Throws nothing; returns
// nullopt with *why set when nothing can be computed (no pair associated, or the alignment is
// degenerate); in that case *diagnostics_out (if given) still carries the pair-count diagnostic
// with both stamp ranges, so the caller can say why.
std::optional<TrajectoryEvaluation> EvaluateTrajectory(
    const std::vector<StampedPose>& estimate, const std::vector<StampedPose>& truth,
    const EvaluationProtocol& protocol, std::string* why = nullptr,
    TrajectoryDiagnostics* diagnostics_out = nullptr);

}  // namespace mavloc
