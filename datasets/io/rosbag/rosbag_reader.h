// ROS1 bags (format 2.0, http://wiki.ros.org/Bags/Format/2.0) read through Debian's rosbag_storage
// (rosbag::Bag, rosbag::View) and deserialized with ros::serialization: the generated headers of
// Debian's message packages for sensor_msgs, geometry_msgs, nav_msgs and tf2_msgs, and mavloc's
// own message structs (checked against the MD5 sum and definition the bag's connection header
// holds) for the AprilTag arrays Debian lacks. Uncompressed, bz2 and lz4 chunks are read by
// rosbag_storage; a whole-file bzip2 ("run.bag.bz2", as TagSLAM ships its bags) is decompressed,
// streaming, into a temporary file that is removed afterwards.
//
// Every reader streams (one message in memory at a time) and throws InputError naming the file,
// the topic and the message index (0-based, in bag-time order on that topic), or the byte offset
// when the bag itself is truncated or corrupt. Stamps: header.stamp of the message where it has one
// (IMU, poses, odometry, tags, images), bag (receive) time in the summary.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "core/camera_model.h"
#include "core/dataset.h"
#include "core/imu.h"
#include "datasets/io/log_reader.h"

namespace mavloc {

// True when `path` starts with "#ROSBAG V2.0", or is a bzip2 file whose decompressed bytes do.
// (DetectLogFormat can use it: a whole-file .bag.bz2 starts with "BZh", not the bag magic.)
bool IsRosbagFile(const std::string& path);

// Topics (connection topic and datatype, messages counted per topic over all its connections),
// first/last bag time per topic and of the whole bag; notes: chunk compression kinds
// ("chunks: 12 bz2"), whole-file bzip2, message types mavloc cannot read.
LogSummary SummarizeRosbag(const std::string& path);

// sensor_msgs/Imu -> samples at header.stamp; angular_velocity [rad/s] and linear_acceleration
// [m/s^2] copied unchanged (REP 103: the IMU frame is the message's frame_id, which mavloc calls
// B). Samples are returned in bag order; non-increasing stamps are an InputError.
std::vector<ImuSample> ReadRosbagImu(const std::string& path, const std::string& topic);

// geometry_msgs/PoseStamped, geometry_msgs/PoseWithCovarianceStamped, nav_msgs/Odometry, or
// tf2_msgs/TFMessage (spec.tf_parent / spec.tf_child required: the transforms whose header.frame_id
// is the parent and child_frame_id the child, a direct edge; leading '/' ignored in frame names).
// T_W_B = (position, orientation) of the message, W = header.frame_id, B = child frame.
// Odometry's twist is in the child frame (REP 147, nav_msgs/Odometry comments): v_W = R_W_B v_B,
// has_velocity = true. Covariance (PoseWithCovariance*, Odometry's pose) is copied in ROS order
// (x y z rotX rotY rotZ) when present and not all zero (and not -1 "unknown"); it is then filled
// for every state.
LogTrajectory ReadRosbagTrajectory(const LogTopicSpec& spec);

// apriltag_msgs/ApriltagArrayStamped (TagSLAM) or apriltag_ros/AprilTagDetectionArray ->
// observations stamped with header.stamp, camera = camera_index, corners in mavloc's order
// (core/tag_geometry.h, libapriltag's; each layout's mapping is in rosbag_tag_messages.h). The
// bag's MD5 sum and definition of the type must equal mavloc's (InputError showing the first
// differing definition line otherwise).
// apriltag_ros's messages carry no pixel corners, only the tag pose in the camera frame, solved
// from the corners with K and no distortion: the corners are recovered by projecting the tag's
// corners (size from the message) with `camera`'s K (its distortion is ignored, as apriltag_ros
// ignored it); `camera` is required for that layout. Detections of tag bundles (more than one id)
// are skipped.
std::vector<TagObservation> ReadRosbagTags(const std::string& path, const std::string& topic,
                                           int camera_index,
                                           const std::optional<CameraModel>& camera = {});

// sensor_msgs/CameraInfo (the first message): K -> (fu, fv, cu, cv), distortion_model "plumb_bob"
// or "rational_polynomial" (only when k3..k6 are zero) -> radial-tangential (k1 k2 p1 p2),
// "equidistant" -> equidistant (k1..k4); an empty model or all-zero D -> none.
CameraModel ReadRosbagCameraInfo(const std::string& path, const std::string& topic);

// sensor_msgs/Image (mono8, mono16, bgr8, rgb8, bgra8, rgba8) or sensor_msgs/CompressedImage
// (jpeg/png, decoded with OpenCV) -> one PNG per message, "<out_dir>/<header.stamp ns>.png" (the
// EuRoC naming), written atomically one message at a time; colour is kept (BGR in the PNG).
// out_dir must exist. Returns the frames (absolute image paths) in bag order.
std::vector<CameraFrame> ExportRosbagImages(const std::string& path, const std::string& topic,
                                            const std::string& out_dir);

}  // namespace mavloc
