// libFuzzer target for the ROS1 bag reader (datasets/io/rosbag/rosbag_reader.h): the input is a
// bag (or a whole-file bzip2 bag); after the summary, every topic is read with the reader of its
// message type, as `mavloc log-info` and the import commands would.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>

#include "datasets/io/log_reader.h"
#include "datasets/io/rosbag/rosbag_reader.h"
#include "fuzz/fuzz_support.h"

namespace {

void ReadTopic(const std::string& path, const mavloc::LogTopicSummary& topic) {
  const std::string& type = topic.type;
  if (type == "sensor_msgs/Imu") {
    (void)mavloc::ReadRosbagImu(path, topic.topic);
  } else if (type == "geometry_msgs/PoseStamped" ||
             type == "geometry_msgs/PoseWithCovarianceStamped" || type == "nav_msgs/Odometry" ||
             type == "tf2_msgs/TFMessage") {
    mavloc::LogTopicSpec spec;
    spec.path = path;
    spec.topic = topic.topic;
    if (type == "tf2_msgs/TFMessage") {
      spec.tf_parent = "world";
      spec.tf_child = "body";
    }
    (void)mavloc::ReadRosbagTrajectory(spec);
  } else if (type == "apriltag_msgs/ApriltagArrayStamped" ||
             type == "apriltag_ros/AprilTagDetectionArray") {
    const mavloc::CameraModel camera(752, 480, Eigen::Vector4d(458.0, 457.0, 367.0, 248.0));
    (void)mavloc::ReadRosbagTags(path, topic.topic, 0, camera);
  } else if (type == "sensor_msgs/CameraInfo") {
    (void)mavloc::ReadRosbagCameraInfo(path, topic.topic);
  } else if (type == "sensor_msgs/Image" || type == "sensor_msgs/CompressedImage") {
    const std::string images = mavloc::fuzz::ScratchFolder() + "/images";
    std::filesystem::remove_all(images);
    std::filesystem::create_directories(images);
    (void)mavloc::ExportRosbagImages(path, topic.topic, images);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = mavloc::fuzz::WriteScratchFile("log.bag", data, size);
  mavloc::LogSummary summary;
  bool summarized = false;
  mavloc::fuzz::ExpectInputErrorOnly([&] {
    summary = mavloc::SummarizeRosbag(path);
    summarized = true;
  });
  if (!summarized) return 0;
  for (const mavloc::LogTopicSummary& topic : summary.topics)
    mavloc::fuzz::ExpectInputErrorOnly([&] { ReadTopic(path, topic); });
  return 0;
}
