// The trajectories a TagSLAM test folder holds besides the tags, expressed for the rig body B of
// the imported dataset, for comparisons with mavloc's estimates:
//   - TagSLAM's optimised trajectory, reference.bag's /tagslam/odom/body_<body> (nav_msgs/Odometry
//     with header.frame_id = map). TagSLAM's publishBodyOdom (src/tag_slam.cpp) writes the body's
//     optimised pose T_map_body and names the body's odom_frame_id as child_frame_id, so the pose
//     is T_W_B whatever the child frame is called. An estimate, not ground truth.
//   - the logged odometry of the rig (its odom_topic, e.g. VIO), in its own odometry frame O and
//     for the sensor frame S the odometry tracks. TagSLAM relates it to the body through
//     T_body_odom: the body's motion between two messages is
//     T_body_odom * (T_O_S(t1)^-1 T_O_S(t2)) * T_body_odom^-1 (src/odometry_processor.cpp), i.e.
//     T_body_odom = T_B_S. So the body's trajectory in O is T_O_B(t) = T_O_S(t) * T_body_odom^-1.
//     O is not W: compare after an se3 alignment.
#pragma once

#include <string>
#include <vector>

#include "core/pose.h"
#include "datasets/io/log_reader.h"

namespace mavloc {

// The topic of TagSLAM's optimised trajectory of a body ("/tagslam/odom/body_rig").
std::string TagslamBodyTopic(const std::string& body);

// T_O_B(t) = T_O_S(t) * T_B_S^-1 for every state of the odometry (T_W_B of the trajectory = T_O_S).
std::vector<StampedPose> OdometryOfBody(const LogTrajectory& odometry, const Pose& T_B_S);

// The poses of a trajectory read from a log (T_W_B as the messages give it).
std::vector<StampedPose> PosesOf(const LogTrajectory& trajectory);

}  // namespace mavloc
