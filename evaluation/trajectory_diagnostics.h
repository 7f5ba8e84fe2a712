// Diagnostics that evo, rpg_trajectory_evaluation and ov_eval do not give: they explain a large
// error instead of only reporting it.
// - Constant rotation offset: after alignment, R_est = R_gt R_off for every pair when the estimate
//   tracks another body frame (camera instead of IMU). R_off is estimated as the chordal L2 mean
//   on SO(3) of the per-pair R_gt,i^T R_est,i (Hartley et al., "Rotation Averaging", IJCV 2013,
//   sec. 5.3: the projection of the arithmetic mean onto SO(3)), then refined by Gauss-Newton on
//   the geodesic L2 mean (Karcher mean). The rotation noise is the RMS geodesic spread of the
//   per-pair offsets about that mean; the offset is reported when its angle exceeds
//   max(min_rotation_offset_deg, rotation_offset_sigma_factor * noise).
//   Note: with Se3/Sim3 alignment the offset is only visible when the motion is not a pure
//   translation of one point; alignment fits positions, not orientations, so R_off survives it.
// - Time offset: |omega|(t) of both trajectories, averaged over a baseline b as
//   |Log(R(t - b/2)^T R(t + b/2))| / b with R slerped (a body-frame rate magnitude, so a constant
//   body-frame offset does not change it; the same b for both, so a noisy high-rate truth and a
//   low-rate estimate are differentiated alike), on uniform grids; the shift tau minimising the
//   mean squared difference between |omega_est|(t) and |omega_gt|(t + tau) over +-max search,
//   coarse to fine (b = grid spacing, down to the estimate's period, shifts down to 1/8 of it),
//   refined by a parabola through the three best costs. Sign: tau is to be added to the
//   estimate's stamps (the convention of the protocol's time_offset_s and evo's --t_offset).
//   Its standard deviation from the curvature kappa of the cost and the residual cost c* over
//   N samples: sigma = sqrt(2 c* / (N kappa)). Reported when |tau| exceeds one median sample
//   period of the estimate and 3 sigma.
// - Alignment conditioning: Umeyama (se3, sim3) fixes a rotation only when the truth positions it
//   fits spread in at least two directions, posyaw (a yaw) when they spread in one. The RMS
//   extents are the singular values of the centred positions over sqrt(n); below
//   min_alignment_extent_m in the direction the mode needs, the alignment's rotation is fitted to
//   noise and the errors after it mean nothing.
// - Scale: a Sim3 scale s with |s - 1| > max_scale_deviation for an estimator declared metric.
// - Too few pairs: fewer than min_pairs associated (or fewer than a fraction of the estimate),
//   with the stamp ranges of both inputs and their median spacing.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/pose.h"
#include "evaluation/association.h"

namespace mavloc {

struct DiagnosticOptions {
  bool metric_estimator = true;       // a Sim3 scale far from 1 is then a fault
  double max_scale_deviation = 0.05;  // |s - 1| above this is reported
  double min_rotation_offset_deg = 1.0;
  double rotation_offset_sigma_factor = 5.0;
  double max_time_offset_search_s = 1.0;  // the shift search window +-
  size_t min_pairs = 10;
  double min_alignment_extent_m = 0.05;  // RMS extent the alignment's rotation needs
  double min_pair_fraction = 0.5;        // pairs / estimate poses below this is reported
};

struct RotationOffsetDiagnostic {
  bool evaluated = false;
  bool detected = false;
  double angle_deg = 0.0;
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();  // unit axis of R_off, in the body frame B
  Eigen::Matrix3d R_off = Eigen::Matrix3d::Identity();
  double noise_deg = 0.0;  // RMS geodesic spread of the per-pair offsets about R_off
};

struct TimeOffsetDiagnostic {
  bool evaluated = false;
  bool detected = false;
  double offset_s = 0.0;           // add to the estimate's stamps
  double sigma_s = 0.0;            // its standard deviation (0 when not available)
  double estimate_period_s = 0.0;  // median spacing of the estimate's stamps
  double cost_at_zero = 0.0;       // mean squared |omega| difference at tau = 0 [rad^2/s^2]
  double cost_at_offset = 0.0;     // at tau = offset_s
};

struct ScaleDiagnostic {
  bool evaluated = false;  // only for Sim3 alignment
  bool detected = false;
  double scale = 1.0;
};

struct AlignmentConditionDiagnostic {
  bool evaluated = false;  // se3, sim3 and posyaw fitted to more than one pair
  bool detected = false;
  std::string mode;
  Eigen::Vector3d extents_m = Eigen::Vector3d::Zero();  // RMS extents, largest first
};

struct PairCountDiagnostic {
  bool detected = false;
  size_t pairs = 0;
  size_t estimate_count = 0;
  size_t truth_count = 0;
  TimeNs estimate_first_ns = 0, estimate_last_ns = 0;
  TimeNs truth_first_ns = 0, truth_last_ns = 0;
  double estimate_median_dt_s = 0.0;
  double truth_median_dt_s = 0.0;
};

struct TrajectoryDiagnostics {
  RotationOffsetDiagnostic rotation_offset;
  TimeOffsetDiagnostic time_offset;
  ScaleDiagnostic scale;
  PairCountDiagnostic pair_count;
  AlignmentConditionDiagnostic alignment_condition;
  // One line per detected fault, with its likely cause (empty when none).
  std::vector<std::string> Messages() const;
};

// The conditioning of an alignment fitted to these truth positions (AlignmentConditionDiagnostic).
AlignmentConditionDiagnostic DiagnoseAlignmentCondition(const std::vector<Eigen::Vector3d>& p_gt,
                                                        const std::string& mode, bool needs_two,
                                                        const DiagnosticOptions& options);

// Median spacing of sorted stamps in seconds (0 for fewer than 2).
double MedianSpacingSeconds(const std::vector<StampedPose>& poses);

// Each diagnostic on its own (EvaluateTrajectory calls them all).
// pairs: after alignment (T_W_B_est already mapped by the alignment).
RotationOffsetDiagnostic DiagnoseRotationOffset(const PairedPoses& aligned_pairs,
                                                const DiagnosticOptions& options);
// estimate and truth as given; estimate_time_offset_s (the protocol's offset) is added to the
// estimate's stamps first, so the result is the offset still left.
TimeOffsetDiagnostic DiagnoseTimeOffset(const std::vector<StampedPose>& estimate,
                                        const std::vector<StampedPose>& truth,
                                        const DiagnosticOptions& options,
                                        double estimate_time_offset_s = 0.0);
ScaleDiagnostic DiagnoseScale(bool sim3, double scale, const DiagnosticOptions& options);
PairCountDiagnostic DiagnosePairCount(size_t pairs, const std::vector<StampedPose>& estimate,
                                      const std::vector<StampedPose>& truth,
                                      const DiagnosticOptions& options);

}  // namespace mavloc
