// Trajectory alignment (Umeyama, "Least-squares estimation of transformation parameters between
// two point patterns", PAMI 1991), as in evo and OpenVINS ov_eval:
// - none:   identity;
// - se3:    rotation + translation;
// - sim3:   rotation + translation + scale;
// - posyaw: translation + rotation about the gravity axis z only (4 DoF), the unobservable gauge
//           of visual-inertial estimation; roll and pitch of the estimate are left untouched.
// The result S maps estimate coordinates into ground-truth coordinates:
//   p_gt ~= s R p_est + t,  R_gt ~= R R_est.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "core/pose.h"

namespace mavloc {

enum class AlignmentMode { kNone, kSe3, kSim3, kPosYaw };

std::optional<AlignmentMode> ParseAlignmentMode(const std::string& name);
std::string AlignmentModeName(AlignmentMode mode);

struct Similarity {
  double scale = 1.0;
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  Eigen::Vector3d Apply(const Eigen::Vector3d& p) const { return scale * (R * p) + t; }
};

// Aligns points p_est onto p_gt (same size, >= 3 points for se3/sim3, >= 2 for posyaw). Returns
// nullopt for too few points or a degenerate configuration (all points coincident).
// se3/sim3 follow evo/core/geometry.py umeyama_alignment, including its refusal of a degenerate
// cross-covariance (fewer than 2 singular values above machine epsilon: collinear points);
// posyaw follows rpg_trajectory_evaluation align_umeyama(yaw_only) / ov_eval align_posyaw:
// theta = atan2(S_yx - S_xy, S_xx + S_yy), S = sum (p_gt - mu_gt)(p_est - mu_est)^T.
std::optional<Similarity> AlignPoints(const std::vector<Eigen::Vector3d>& p_est,
                                      const std::vector<Eigen::Vector3d>& p_gt, AlignmentMode mode);

// Alignment from the first pose pair only (rpg_trajectory_evaluation alignSE3Single /
// alignPositionYawSingle, ov_eval se3single / posyawsingle), used when one frame is to be aligned:
//   se3:    R = R_gt0 R_est0^T;  posyaw: R = Rz(theta) with theta maximising
//           trace(Rz(theta) R_est0 R_gt0^T);  t = p_gt0 - R p_est0. sim3 needs >= 2 frames
//           (nullopt), none gives identity.
std::optional<Similarity> AlignFirstPose(const Pose& T_W_B_est0, const Pose& T_W_B_gt0,
                                         AlignmentMode mode);

// evo's align_origin (trajectory.py PosePath3D.align_origin): T = T_gt0 T_est0^-1, applied from the
// left to every estimated pose, so that the first poses coincide.
Similarity AlignOrigin(const Pose& T_W_B_est0, const Pose& T_W_B_gt0);

// S * T: the estimate's pose mapped by the alignment (p' = s R p + t, R' = R R_est).
Pose ApplySimilarity(const Similarity& S, const Pose& T_W_B);
// The same with q_S = Quaternion(S.R) computed once by the caller (for many poses).
Pose ApplySimilarity(const Similarity& S, const Eigen::Quaterniond& q_S, const Pose& T_W_B);

}  // namespace mavloc
