// Logs from the MAV ecosystem, ROS1 bags and PX4 ULog files: what they hold, and their streams as
// mavloc data (IMU samples, trajectories). The format is detected from the file's first bytes
// ("#ROSBAG V2.0" or ULog's magic "ULog" 0x01 0x12 0x35), never from the file name. The readers of
// each format live in datasets/io/rosbag/ and datasets/io/ulog/; this header is the one interface
// the CLI uses.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "core/dataset.h"
#include "core/imu.h"
#include "core/time.h"

namespace mavloc {

enum class LogFormat { kRosbag, kUlog };

// One topic of a log. For ULog, a multi-instance topic is listed once per instance (instance > 0
// for the second and later ones, as pyulog lists them).
struct LogTopicSummary {
  std::string topic;  // "/imu/data" for bags, "sensor_combined" for ULog
  std::string type;   // "sensor_msgs/Imu"; for ULog the message format name
  int instance = 0;
  uint64_t messages = 0;
  TimeNs t_first_ns = 0;  // stamp of the first and last message (log time)
  TimeNs t_last_ns = 0;
};

struct LogSummary {
  std::string path;
  LogFormat format = LogFormat::kRosbag;
  TimeNs t_start_ns = 0;
  TimeNs t_end_ns = 0;
  std::vector<LogTopicSummary> topics;  // sorted by topic name, then instance
  // Anything a user should know: compressed chunks, ULog dropouts (count and total ms),
  // appended data, unsupported message types.
  std::vector<std::string> notes;
};

// A trajectory read from one log topic, converted to mavloc's conventions (T_W_B with the parent
// frame as W and the child frame as B, positions in metres, stamps in ns).
struct LogTrajectory {
  std::string source;  // "file:topic" for messages
  std::string type;    // message type it was read from
  std::string parent_frame;
  std::string child_frame;
  std::vector<GroundTruthState> states;  // v_W set only when has_velocity
  // What the messages carry: vehicle_attitude has no position (p = 0, has_position false),
  // vehicle_local_position no attitude (identity, has_attitude false). Comparisons use only
  // what is carried.
  bool has_position = true;
  bool has_attitude = true;
  bool has_velocity = false;
  // Per state, the pose covariance in [p; theta] order (ROS order: x y z rotX rotY rotZ), or empty
  // when the messages carry none (or carry only zeros / -1 "unknown").
  std::vector<Eigen::Matrix<double, 6, 6>> covariance;
  // What the reader dropped or skipped, one line each without a "note: " prefix: for ULog the
  // counted drops (repeated or earlier stamps, PX4's "invalid" markers, corrupt stamps) and the
  // scan's notes on truncated or corrupt messages; empty for a bag (its reader refuses instead of
  // dropping, and skips only a /tf transform republished unchanged).
  std::vector<std::string> notes;
};

// "LOG:TOPIC" (e.g. "flight.ulg:vehicle_attitude", "flight.ulg:vehicle_imu:1" for the second
// instance of a multi-instance ULog topic, "run.bag:/odom", "run.bag:/tf:world:body" for a
// parent/child pair of /tf). Returns nullopt when `spec` is not of this form: no prefix of it
// before a ':' is an existing regular file that starts like a bag or a ULog file.
struct LogTopicSpec {
  std::string path;
  std::string topic;
  int instance = 0;       // ULog multi-instance topics
  std::string tf_parent;  // only for tf2_msgs/TFMessage topics
  std::string tf_child;
};
std::optional<LogTopicSpec> ParseLogTopicSpec(const std::string& spec);

// nullopt when the file is neither a bag nor a ULog file (or cannot be opened).
std::optional<LogFormat> DetectLogFormat(const std::string& path);

// Throw InputError naming the file, the topic and the byte offset or message index on a missing
// topic, an unsupported type or a truncated/corrupt log.
LogSummary SummarizeLog(const std::string& path);
std::vector<ImuSample> ReadLogImu(const std::string& path, const std::string& topic);

// The streaming form of ReadLogImu: `visit` gets each sample as it is read, nothing is kept
// (memory does not grow with the log); the same checks and InputErrors, thrown at the first bad
// message (the samples before it have been visited by then). For ULog, `notes` (when not null)
// gets what the reader dropped, as ReadUlogImu's notes.
void ForEachLogImuSample(const std::string& path, const std::string& topic,
                         const std::function<void(const ImuSample&)>& visit,
                         std::vector<std::string>* notes = nullptr);
// Its ROS1 bag part (datasets/io/rosbag/rosbag_imu.cc; ReadRosbagImu of rosbag_reader.h collects
// it).
void ForEachRosbagImuSample(const std::string& path, const std::string& topic,
                            const std::function<void(const ImuSample&)>& visit);
LogTrajectory ReadLogTrajectory(const LogTopicSpec& spec);

}  // namespace mavloc
