// A ROS1 bag opened for reading with rosbag::Bag, and the message loop every reader shares.
// A whole-file bzip2 bag is first decompressed (streaming) into a temporary file in the system's
// temporary folder, removed when the OpenedBag is destroyed or the command is interrupted
// (core/interrupt.h). rosbag_storage's exceptions become InputErrors naming the file, the topic
// and the message index, or the byte where a truncated or corrupt bag stops (from ScanBagRecords,
// bag_records.h). The ROS libraries' own console output is silenced, so a bad bag gives one line
// on stderr.
#pragma once

#include <rosbag/bag.h>
#include <rosbag/view.h>

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "core/interrupt.h"
#include "datasets/io/rosbag/ros_messages.h"

namespace mavloc::ros1 {

class OpenedBag {
 public:
  explicit OpenedBag(const std::string& path);
  ~OpenedBag();
  OpenedBag(const OpenedBag&) = delete;
  OpenedBag& operator=(const OpenedBag&) = delete;

  rosbag::Bag& bag() { return bag_; }
  const std::string& path() const { return path_; }                // as the user gave it
  const std::string& opened_path() const { return opened_path_; }  // the plain bag read
  bool whole_file_bzip2() const { return !temporary_path_.empty(); }

  // The datatype of `topic` ("sensor_msgs/Imu"); InputError when the bag has no such topic (the
  // message lists the topics it has) or its connections disagree on the type.
  std::string TopicType(const std::string& topic);
  // The MD5 sum and definition the connection header of `topic` holds.
  std::string TopicMd5(const std::string& topic);
  std::string TopicDefinition(const std::string& topic);

  // Calls visit(message, index) for every message on `topic` in bag-time order (index 0, 1, ...).
  // Exceptions from rosbag or ros::serialization, and InputErrors without a location, are rethrown
  // as InputError "<file>: topic <topic>, message <index>: <what>". Progress goes to stderr
  // (core/progress.h) every 10% of long topics.
  void ForEachMessage(const std::string& topic,
                      const std::function<void(const rosbag::MessageInstance&, uint64_t)>& visit);

  // "<file>: topic <topic>, message <index>: <message>" as an InputError.
  [[noreturn]] void Fail(const std::string& topic, uint64_t index,
                         const std::string& message) const;

 private:
  std::vector<const rosbag::ConnectionInfo*> Connections(const std::string& topic);

  std::string path_;
  std::string opened_path_;
  std::string temporary_path_;
  // Registers temporary_path_ with the interrupt cleanup (core/interrupt.h) from before the file
  // is created until after the destructor has removed it.
  std::unique_ptr<TemporaryPathGuard> temporary_guard_;
  rosbag::Bag bag_;
};

// Deserializes `message` as M after checking its MD5 sum against M's; `what` names the expected
// type in the error. No array of the message may hold more elements than the message has bytes
// (MessageElementLimit, ros_messages.h): a corrupt length is a StreamOverrunException, not an
// allocation of gigabytes.
template <class M>
boost::shared_ptr<M> Instantiate(const OpenedBag& bag, const std::string& topic, uint64_t index,
                                 const rosbag::MessageInstance& message) {
  const MessageElementLimit limit(message.size());
  boost::shared_ptr<M> decoded = message.instantiate<M>();
  if (!decoded) {
    bag.Fail(topic, index,
             "message type " + message.getDataType() + " (md5 " + message.getMD5Sum() +
                 ") does not match " + ros::message_traits::DataType<M>::value() + " (md5 " +
                 ros::message_traits::MD5Sum<M>::value() + ")");
  }
  return decoded;
}

}  // namespace mavloc::ros1
