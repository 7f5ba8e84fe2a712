#include "solver/estimators/tag_ekf_reacquire.h"

namespace mavloc {

// The ranges (frames >= 2, sigmas > 0) are checked when the estimator is created
// (solver/estimator_registry.cc, OptionRanges).
ReacquireOptions ParseReacquireOptions(const EstimatorOptions& options) {
  ReacquireOptions out;
  out.enabled = options.GetBool("reacquire", out.enabled);
  out.frames = options.GetInt("reacquire_frames", out.frames);
  out.position_sigma_m = options.GetDouble("reacquire_pos_sigma", out.position_sigma_m);
  out.velocity_sigma_m_s = options.GetDouble("reacquire_vel_sigma", out.velocity_sigma_m_s);
  out.attitude_sigma_rad = options.GetDouble("reacquire_att_sigma", out.attitude_sigma_rad);
  return out;
}

std::optional<ReacquiredState> ReacquireState(const std::vector<StampedPose>& pnp_poses,
                                              TimeNs now_ns, const TagEkfVector& x_now,
                                              const TagEkfMatrix& P_now,
                                              const ReacquireOptions& options) {
  if (pnp_poses.size() < 2) return std::nullopt;
  // Least-squares line p(t) = p_mean + v (t - t_mean) through the PnP positions.
  const TimeNs t_ref_ns = pnp_poses.front().t_ns;
  double t_mean_s = 0.0;
  Eigen::Vector3d p_mean = Eigen::Vector3d::Zero();
  for (const auto& pose : pnp_poses) {
    t_mean_s += NsToSeconds(pose.t_ns - t_ref_ns);
    p_mean += pose.T_W_B.p;
  }
  const double n = static_cast<double>(pnp_poses.size());
  t_mean_s /= n;
  p_mean /= n;
  double s_tt = 0.0;
  Eigen::Vector3d s_tp = Eigen::Vector3d::Zero();
  for (const auto& pose : pnp_poses) {
    const double dt_s = NsToSeconds(pose.t_ns - t_ref_ns) - t_mean_s;
    s_tt += dt_s * dt_s;
    s_tp += dt_s * (pose.T_W_B.p - p_mean);
  }
  if (!(s_tt > 0.0)) return std::nullopt;
  const Eigen::Vector3d v_W = s_tp / s_tt;
  const StampedPose& last = pnp_poses.back();
  ReacquiredState out;
  out.x = x_now;  // biases kept
  out.x.segment<3>(kTagEkfPos) = last.T_W_B.p + NsToSeconds(now_ns - last.t_ns) * v_W;
  out.x.segment<3>(kTagEkfVel) = v_W;
  out.x.segment<3>(kTagEkfAtt) = Euler123FromRotation(last.T_W_B.R());
  // Pose and velocity uncorrelated with each other and with the biases; the biases' block kept.
  out.P = TagEkfMatrix::Zero();
  out.P.block<6, 6>(kTagEkfAccelBias, kTagEkfAccelBias) =
      P_now.block<6, 6>(kTagEkfAccelBias, kTagEkfAccelBias);
  for (int i = 0; i < 3; ++i) {
    out.P(kTagEkfPos + i, kTagEkfPos + i) = options.position_sigma_m * options.position_sigma_m;
    out.P(kTagEkfVel + i, kTagEkfVel + i) = options.velocity_sigma_m_s * options.velocity_sigma_m_s;
    out.P(kTagEkfAtt + i, kTagEkfAtt + i) = options.attitude_sigma_rad * options.attitude_sigma_rad;
  }
  return out;
}

}  // namespace mavloc
