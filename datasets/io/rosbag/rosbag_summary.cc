// What a bag holds (rosbag_reader.h): topics from the connection records, counts and bag-time
// ranges from rosbag's index (no message is read), chunk compression from the record walk.
#include <fmt/format.h>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <set>

#include "core/errors.h"
#include "core/input_file.h"
#include "datasets/io/rosbag/bag_records.h"
#include "datasets/io/rosbag/bzip2_file.h"
#include "datasets/io/rosbag/opened_bag.h"
#include "datasets/io/rosbag/ros_messages.h"
#include "datasets/io/rosbag/rosbag_reader.h"

namespace mavloc {

namespace {

constexpr char kBagMagic[] = "#ROSBAG V2.0";

// The message types some reader of rosbag_reader.h accepts.
bool IsReadable(const std::string& type) {
  static const std::set<std::string> kTypes = {"sensor_msgs/Imu",
                                               "sensor_msgs/Image",
                                               "sensor_msgs/CompressedImage",
                                               "sensor_msgs/CameraInfo",
                                               "geometry_msgs/PoseStamped",
                                               "geometry_msgs/PoseWithCovarianceStamped",
                                               "nav_msgs/Odometry",
                                               "tf2_msgs/TFMessage",
                                               "tf/tfMessage",
                                               "apriltag_msgs/ApriltagArrayStamped",
                                               "apriltag_ros/AprilTagDetectionArray"};
  return kTypes.count(type) > 0;
}

}  // namespace

bool IsRosbagFile(const std::string& path) {
  const size_t n = std::strlen(kBagMagic);
  if (!NotARegularFile(path).empty()) return false;  // a pipe would block the open
  std::ifstream in(path, std::ios::binary);
  std::string start(n, '\0');
  if (!in.read(start.data(), static_cast<std::streamsize>(n))) return false;
  if (start == kBagMagic) return true;
  return ros1::ReadBzip2Prefix(path, n) == kBagMagic;
}

LogSummary SummarizeRosbag(const std::string& path) {
  ros1::OpenedBag bag(path);
  LogSummary summary;
  summary.path = path;
  summary.format = LogFormat::kRosbag;
  rosbag::View all(bag.bag());
  if (all.size() > 0) {
    summary.t_start_ns = ros1::ToNs(all.getBeginTime());
    summary.t_end_ns = ros1::ToNs(all.getEndTime());
  }
  std::set<std::string> topics;
  for (const rosbag::ConnectionInfo* connection : all.getConnections()) {
    topics.insert(connection->topic);
  }
  for (const std::string& topic : topics) {  // std::set: sorted by name
    LogTopicSummary entry;
    entry.topic = topic;
    entry.type = bag.TopicType(topic);
    rosbag::View view(bag.bag(), rosbag::TopicQuery(topic));
    entry.messages = view.size();
    if (entry.messages > 0) {
      entry.t_first_ns = ros1::ToNs(view.getBeginTime());
      entry.t_last_ns = ros1::ToNs(view.getEndTime());
    }
    if (!IsReadable(entry.type)) {
      summary.notes.push_back(fmt::format("{}: {} is not read by mavloc", topic, entry.type));
    }
    summary.topics.push_back(entry);
  }
  if (bag.whole_file_bzip2()) {
    summary.notes.push_back("whole-file bzip2: decompressed to a temporary file to be read");
  }
  const ros1::BagRecordScan scan = ros1::ScanBagRecords(bag.opened_path());
  std::string chunks;
  for (const auto& [compression, count] : scan.chunks_by_compression) {
    chunks += fmt::format("{}{} {}", chunks.empty() ? "" : ", ", count, compression);
  }
  summary.notes.push_back(fmt::format("chunks: {}", chunks.empty() ? "none" : chunks));
  return summary;
}

}  // namespace mavloc
