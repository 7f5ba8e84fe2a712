// Pose-carrying messages -> LogTrajectory (rosbag_reader.h). Conventions: REP 103 (frames),
// REP 105 and nav_msgs/Odometry.msg (pose in header.frame_id, twist in child_frame_id),
// geometry_msgs/PoseWithCovariance.msg (row-major 6x6, order x y z rotX rotY rotZ).
#include <fmt/format.h>

#include <algorithm>
#include <optional>

#include "core/errors.h"
#include "datasets/io/rosbag/opened_bag.h"
#include "datasets/io/rosbag/ros_messages.h"
#include "datasets/io/rosbag/rosbag_reader.h"

namespace mavloc {

namespace {

using Covariance = Eigen::Matrix<double, 6, 6>;

std::string FrameName(const std::string& frame) {
  return frame.rfind('/', 0) == 0 ? frame.substr(1) : frame;
}

// Accumulates states and checks what every message must satisfy.
class TrajectoryBuilder {
 public:
  TrajectoryBuilder(ros1::OpenedBag& bag, const std::string& topic, LogTrajectory* trajectory)
      : bag_(bag), topic_(topic), trajectory_(trajectory) {}

  template <class PoseMsg, class CovarianceArray>
  void Add(uint64_t index, TimeNs t_ns, const std::string& parent, const std::string& child,
           const PoseMsg& pose, const CovarianceArray* covariance) {
    const Eigen::Quaterniond q_W_B(pose.orientation.w, pose.orientation.x, pose.orientation.y,
                                   pose.orientation.z);
    const Eigen::Vector3d p_W_B(pose.position.x, pose.position.y, pose.position.z);
    if (!q_W_B.coeffs().allFinite() || !p_W_B.allFinite()) {
      bag_.Fail(topic_, index, "position or orientation is not finite");
    }
    if (q_W_B.norm() < 0.5 || q_W_B.norm() > 1.5) {
      bag_.Fail(topic_, index,
                fmt::format("orientation is not a unit quaternion (norm {:.6g})", q_W_B.norm()));
    }
    if (trajectory_->states.empty()) {
      trajectory_->parent_frame = parent;
      trajectory_->child_frame = child;
    } else if (parent != trajectory_->parent_frame || child != trajectory_->child_frame) {
      bag_.Fail(topic_, index,
                fmt::format("frames change from {} -> {} to {} -> {}", trajectory_->parent_frame,
                            trajectory_->child_frame, parent, child));
    } else if (skip_repeats_ && t_ns == trajectory_->states.back().t_ns &&
               trajectory_->states.back().T_W_B.p == p_W_B &&
               trajectory_->states.back().T_W_B.q.coeffs() == q_W_B.normalized().coeffs()) {
      return;  // /tf republishes a transform unchanged: the same state twice
    } else if (t_ns <= trajectory_->states.back().t_ns) {
      bag_.Fail(topic_, index,
                fmt::format("header.stamp {} ns does not increase (previous {} ns)", t_ns,
                            trajectory_->states.back().t_ns));
    }
    GroundTruthState state;
    state.t_ns = t_ns;
    state.T_W_B = Pose(q_W_B.normalized(), p_W_B);
    trajectory_->states.push_back(state);
    Covariance P = Covariance::Zero();
    if (covariance != nullptr) {
      for (int i = 0; i < 36; ++i) P(i / 6, i % 6) = (*covariance)[static_cast<size_t>(i)];
      if (!P.allFinite()) bag_.Fail(topic_, index, "covariance is not finite");
      // All zero: not filled in; -1 in the first entry: "unknown" (REP 145 style sentinel).
      has_covariance_ = has_covariance_ || (!P.isZero(0.0) && P(0, 0) != -1.0);
    }
    trajectory_->covariance.push_back(P);
  }

  // Drop a message that repeats the previous stamp and pose exactly (tf broadcasters do).
  void SkipRepeats() { skip_repeats_ = true; }

  void Finish() {
    if (!has_covariance_) trajectory_->covariance.clear();
    if (trajectory_->states.empty()) {
      throw InputError(bag_.path(), 0, "", fmt::format("topic {} has no usable messages", topic_));
    }
  }

 private:
  ros1::OpenedBag& bag_;
  const std::string& topic_;
  LogTrajectory* trajectory_;
  bool has_covariance_ = false;
  bool skip_repeats_ = false;
};

}  // namespace

LogTrajectory ReadRosbagTrajectory(const LogTopicSpec& spec) {
  ros1::OpenedBag bag(spec.path);
  const std::string& topic = spec.topic;
  LogTrajectory trajectory;
  trajectory.source = spec.path + ":" + topic;
  trajectory.type = bag.TopicType(topic);
  TrajectoryBuilder builder(bag, topic, &trajectory);
  const std::string& type = trajectory.type;
  if (type == "geometry_msgs/PoseStamped") {
    bag.ForEachMessage(topic, [&](const rosbag::MessageInstance& message, uint64_t index) {
      const auto msg = ros1::Instantiate<ros1::PoseStampedMsg>(bag, topic, index, message);
      builder.Add(index, ros1::ToNs(msg->header.stamp),
                  FrameName(ros1::ToStdString(msg->header.frame_id)), "", msg->pose,
                  static_cast<const boost::array<double, 36>*>(nullptr));
    });
  } else if (type == "geometry_msgs/PoseWithCovarianceStamped") {
    bag.ForEachMessage(topic, [&](const rosbag::MessageInstance& message, uint64_t index) {
      const auto msg =
          ros1::Instantiate<ros1::PoseWithCovarianceStampedMsg>(bag, topic, index, message);
      builder.Add(index, ros1::ToNs(msg->header.stamp),
                  FrameName(ros1::ToStdString(msg->header.frame_id)), "", msg->pose.pose,
                  &msg->pose.covariance);
    });
  } else if (type == "nav_msgs/Odometry") {
    trajectory.has_velocity = true;
    bag.ForEachMessage(topic, [&](const rosbag::MessageInstance& message, uint64_t index) {
      const auto msg = ros1::Instantiate<ros1::OdometryMsg>(bag, topic, index, message);
      builder.Add(
          index, ros1::ToNs(msg->header.stamp), FrameName(ros1::ToStdString(msg->header.frame_id)),
          FrameName(ros1::ToStdString(msg->child_frame_id)), msg->pose.pose, &msg->pose.covariance);
      // The twist is expressed in child_frame_id (nav_msgs/Odometry.msg): v_W = R_W_B v_B.
      const auto& linear = msg->twist.twist.linear;
      const Eigen::Vector3d v_B(linear.x, linear.y, linear.z);
      if (!v_B.allFinite()) bag.Fail(topic, index, "twist is not finite");
      trajectory.states.back().v_W = trajectory.states.back().T_W_B.q * v_B;
    });
  } else if (type == "tf2_msgs/TFMessage" || type == "tf/tfMessage") {
    if (spec.tf_parent.empty() || spec.tf_child.empty()) {
      throw InputError(spec.path, 0, "",
                       fmt::format("topic {} is {}: name a parent and child frame "
                                   "(\"{}:{}:PARENT:CHILD\")",
                                   topic, type, spec.path, topic));
    }
    const std::string parent = FrameName(spec.tf_parent);
    const std::string child = FrameName(spec.tf_child);
    // Only the direct edge parent -> child is read; chains of transforms are not composed.
    builder.SkipRepeats();
    bag.ForEachMessage(topic, [&](const rosbag::MessageInstance& message, uint64_t index) {
      const auto msg = ros1::Instantiate<ros1::TfMessageMsg>(bag, topic, index, message);
      for (const auto& transform : msg->transforms) {
        if (FrameName(ros1::ToStdString(transform.header.frame_id)) != parent ||
            FrameName(ros1::ToStdString(transform.child_frame_id)) != child) {
          continue;
        }
        geometry_msgs::Pose_<ros1::Alloc> pose;
        pose.position.x = transform.transform.translation.x;
        pose.position.y = transform.transform.translation.y;
        pose.position.z = transform.transform.translation.z;
        pose.orientation = transform.transform.rotation;
        builder.Add(index, ros1::ToNs(transform.header.stamp), parent, child, pose,
                    static_cast<const boost::array<double, 36>*>(nullptr));
      }
    });
    if (trajectory.states.empty()) {
      throw InputError(spec.path, 0, "",
                       fmt::format("topic {} has no transform {} -> {} (only direct edges are "
                                   "read)",
                                   topic, parent, child));
    }
  } else {
    throw InputError(
        spec.path, 0, "",
        fmt::format("topic {} is {}: not a trajectory type (geometry_msgs/PoseStamped, "
                    "geometry_msgs/PoseWithCovarianceStamped, nav_msgs/Odometry, "
                    "tf2_msgs/TFMessage)",
                    topic, type));
  }
  builder.Finish();
  return trajectory;
}

}  // namespace mavloc
