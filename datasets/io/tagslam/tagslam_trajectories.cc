#include "datasets/io/tagslam/tagslam_trajectories.h"

namespace mavloc {

std::string TagslamBodyTopic(const std::string& body) { return "/tagslam/odom/body_" + body; }

std::vector<StampedPose> OdometryOfBody(const LogTrajectory& odometry, const Pose& T_B_S) {
  const Pose T_S_B = T_B_S.Inverse();
  std::vector<StampedPose> out;
  out.reserve(odometry.states.size());
  for (const GroundTruthState& s : odometry.states) out.push_back({s.t_ns, s.T_W_B * T_S_B});
  return out;
}

std::vector<StampedPose> PosesOf(const LogTrajectory& trajectory) {
  std::vector<StampedPose> out;
  out.reserve(trajectory.states.size());
  for (const GroundTruthState& s : trajectory.states) out.push_back({s.t_ns, s.T_W_B});
  return out;
}

}  // namespace mavloc
