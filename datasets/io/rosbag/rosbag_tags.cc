// AprilTag detection arrays -> TagObservation (rosbag_reader.h, rosbag_tag_messages.h).
#include <fmt/format.h>

#include "core/errors.h"
#include "core/tag_geometry.h"
#include "datasets/io/rosbag/opened_bag.h"
#include "datasets/io/rosbag/rosbag_reader.h"
#include "datasets/io/rosbag/rosbag_tag_messages.h"

namespace mavloc {

namespace {

// The bag's MD5 sum and definition of `topic` against mavloc's definition of M.
template <class M>
void CheckDefinition(ros1::OpenedBag& bag, const std::string& topic) {
  const std::string md5 = bag.TopicMd5(topic);
  const char* expected_md5 = ros::message_traits::MD5Sum<M>::value();
  if (md5 == expected_md5) return;
  const auto ours = ros1::CanonicalDefinitionLines(ros::message_traits::Definition<M>::value());
  const auto theirs = ros1::CanonicalDefinitionLines(bag.TopicDefinition(topic));
  std::string difference = "the definitions agree but the MD5 sums do not";
  for (size_t i = 0; i < std::max(ours.size(), theirs.size()); ++i) {
    const std::string a = i < theirs.size() ? theirs[i] : "(end)";
    const std::string b = i < ours.size() ? ours[i] : "(end)";
    if (a != b) {
      difference =
          fmt::format("definition line {}: bag has '{}', mavloc expects '{}'", i + 1, a, b);
      break;
    }
  }
  throw InputError(
      bag.path(), 0, "",
      fmt::format("topic {}: {} in the bag has md5 {}, mavloc reads md5 {}; {}", topic,
                  ros::message_traits::DataType<M>::value(), md5, expected_md5, difference));
}

void ReadApriltagArrays(ros1::OpenedBag& bag, const std::string& topic, int camera_index,
                        std::vector<TagObservation>* tags) {
  CheckDefinition<ros1::ApriltagArrayStampedMsg>(bag, topic);
  bag.ForEachMessage(topic, [&](const rosbag::MessageInstance& message, uint64_t index) {
    const auto msg = ros1::Instantiate<ros1::ApriltagArrayStampedMsg>(bag, topic, index, message);
    for (const ros1::ApriltagMsg& tag : msg->apriltags) {
      TagObservation observation;
      observation.t_ns = ros1::ToNs(msg->header.stamp);
      observation.tag_id = tag.id;
      observation.camera = camera_index;
      for (int k = 0; k < 4; ++k) {
        // Message corner k is mavloc's corner k: on TagSLAM's logs (MIT detector) the known
        // tags projected through TagSLAM's reference poses land on the message's corners in
        // this order (0.2-0.4 px median, tests 21/22), 26-37 px off in the reversed one, and the
        // camera is always on the tags' +z side (import-tagslam helper's check).
        const ros1::PointMsg& corner = tag.corners[static_cast<size_t>(k)];
        observation.corners_px[static_cast<size_t>(k)] = {corner.x, corner.y};
        if (!observation.corners_px[static_cast<size_t>(k)].allFinite()) {
          bag.Fail(topic, index, fmt::format("tag {}: corner {} is not finite", tag.id, k));
        }
      }
      tags->push_back(observation);
    }
  });
}

void ReadAprilTagDetectionArrays(ros1::OpenedBag& bag, const std::string& topic, int camera_index,
                                 const std::optional<CameraModel>& camera,
                                 std::vector<TagObservation>* tags) {
  CheckDefinition<ros1::AprilTagDetectionArrayMsg>(bag, topic);
  if (!camera) {
    throw InputError(bag.path(), 0, "",
                     fmt::format("topic {}: apriltag_ros/AprilTagDetectionArray has no pixel "
                                 "corners; a camera model is needed to project the tag poses",
                                 topic));
  }
  // apriltag_ros solved the pose with K and zero distortion: project with K alone.
  const CameraModel pinhole(camera->width(), camera->height(), camera->intrinsics());
  bag.ForEachMessage(topic, [&](const rosbag::MessageInstance& message, uint64_t index) {
    const auto msg = ros1::Instantiate<ros1::AprilTagDetectionArrayMsg>(bag, topic, index, message);
    for (const ros1::AprilTagDetectionMsg& detection : msg->detections) {
      if (detection.id.size() != 1 || detection.size.size() != 1) continue;  // a bundle
      const auto& pose = detection.pose.pose.pose;
      const Pose T_C_T(Eigen::Quaterniond(pose.orientation.w, pose.orientation.x,
                                          pose.orientation.y, pose.orientation.z)
                           .normalized(),
                       Eigen::Vector3d(pose.position.x, pose.position.y, pose.position.z));
      if (!T_C_T.q.coeffs().allFinite() || !T_C_T.p.allFinite() || detection.size[0] <= 0.0) {
        bag.Fail(topic, index, fmt::format("tag {}: pose or size is invalid", detection.id[0]));
      }
      TagObservation observation;
      observation.t_ns = ros1::ToNs(msg->header.stamp);
      observation.tag_id = detection.id[0];
      observation.camera = camera_index;
      const auto corners_T = TagCornersInTagFrame(detection.size[0]);
      bool visible = true;
      for (size_t k = 0; k < 4; ++k) {
        const auto uv = pinhole.Project(T_C_T * corners_T[k]);
        if (!uv) {
          visible = false;
          break;
        }
        observation.corners_px[k] = *uv;
      }
      if (!visible) {
        bag.Fail(topic, index, fmt::format("tag {} is behind the camera", detection.id[0]));
      }
      tags->push_back(observation);
    }
  });
}

}  // namespace

std::vector<TagObservation> ReadRosbagTags(const std::string& path, const std::string& topic,
                                           int camera_index,
                                           const std::optional<CameraModel>& camera) {
  ros1::OpenedBag bag(path);
  const std::string type = bag.TopicType(topic);
  std::vector<TagObservation> tags;
  if (type == "apriltag_msgs/ApriltagArrayStamped") {
    ReadApriltagArrays(bag, topic, camera_index, &tags);
  } else if (type == "apriltag_ros/AprilTagDetectionArray") {
    ReadAprilTagDetectionArrays(bag, topic, camera_index, camera, &tags);
  } else {
    throw InputError(path, 0, "",
                     fmt::format("topic {} is {}: not a tag detection type "
                                 "(apriltag_msgs/ApriltagArrayStamped, "
                                 "apriltag_ros/AprilTagDetectionArray)",
                                 topic, type));
  }
  return tags;
}

}  // namespace mavloc
