// The ROS1 message types mavloc reads, as Debian's generated headers (sensor_msgs, geometry_msgs,
// nav_msgs, tf2_msgs) instantiated with an allocator that C++20 accepts.
//
// The generated message templates (gencpp) name their string and vector allocators through
// `ContainerAllocator::template rebind<T>::other`, which std::allocator lost in C++20; RosAllocator
// is std::allocator plus that member template, so the same headers compile under C++20 and
// deserialize the same bytes (ros::serialization does not depend on the allocator).
#pragma once

#include <geometry_msgs/PoseStamped.h>
#include <geometry_msgs/PoseWithCovarianceStamped.h>
#include <nav_msgs/Odometry.h>
#include <ros/serialization.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/CompressedImage.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/Imu.h>
#include <tf2_msgs/TFMessage.h>
#include <algorithm>
#include <cstddef>
#include <limits>
#include <memory>
#include <string>
#include <type_traits>

#include "core/time.h"

namespace mavloc::ros1 {

// ros::serialization reads an array's uint32 length and resizes the vector before it checks that
// the message holds that many elements, so one corrupt length (4e9 tags) asks for hundreds of
// gigabytes. Every element of a ROS1 array takes at least MinimumWireBytes<T>() bytes on the wire
// (the serialized length of an empty element: 1 for uint8, 8 for float64, 368 for an
// AprilTagDetection), so while a message of n bytes is deserialized (OpenedBag::ForEachMessage
// sets the limit) no message container can hold more than n / MinimumWireBytes elements:
// RosAllocator refuses a larger allocation with the StreamOverrunException that a short message
// gives. Bounding by bytes rather than by a count of 1 byte per element matters for nested types:
// a vector of n AprilTagDetections would otherwise allocate n times their ~450 bytes.
inline thread_local std::size_t message_element_limit = std::numeric_limits<std::size_t>::max();

// The fewest bytes one element of type T takes on the wire (at least 1).
template <class T>
std::size_t MinimumWireBytes() {
  if constexpr (std::is_arithmetic_v<T>) {
    return sizeof(T);
  } else {
    static const std::size_t bytes =
        std::max<std::size_t>(1, ros::serialization::serializationLength(T()));
    return bytes;
  }
}

// Sets message_element_limit for one message's deserialization.
class MessageElementLimit {
 public:
  explicit MessageElementLimit(std::size_t message_bytes) : previous_(message_element_limit) {
    message_element_limit = message_bytes;
  }
  ~MessageElementLimit() { message_element_limit = previous_; }
  MessageElementLimit(const MessageElementLimit&) = delete;
  MessageElementLimit& operator=(const MessageElementLimit&) = delete;

 private:
  std::size_t previous_;
};

template <class T>
struct RosAllocator : std::allocator<T> {
  using value_type = T;
  RosAllocator() = default;
  template <class U>
  RosAllocator(const RosAllocator<U>& /*other*/) noexcept {}
  template <class U>
  struct rebind {
    using other = RosAllocator<U>;
  };
  T* allocate(std::size_t count) {
    // count - 1: a string allocates room for its terminating null.
    if (count > 0 && count - 1 > message_element_limit / MinimumWireBytes<T>()) {
      throw ros::serialization::StreamOverrunException(
          "an array of " + std::to_string(count) + " elements in a message of " +
          std::to_string(message_element_limit) + " bytes (an element takes at least " +
          std::to_string(MinimumWireBytes<T>()) + " bytes)");
    }
    return std::allocator<T>::allocate(count);
  }
};

using Alloc = RosAllocator<void>;
using ImuMsg = sensor_msgs::Imu_<Alloc>;
using ImageMsg = sensor_msgs::Image_<Alloc>;
using CompressedImageMsg = sensor_msgs::CompressedImage_<Alloc>;
using CameraInfoMsg = sensor_msgs::CameraInfo_<Alloc>;
using PoseStampedMsg = geometry_msgs::PoseStamped_<Alloc>;
using PoseWithCovarianceStampedMsg = geometry_msgs::PoseWithCovarianceStamped_<Alloc>;
using OdometryMsg = nav_msgs::Odometry_<Alloc>;
using TfMessageMsg = tf2_msgs::TFMessage_<Alloc>;
using HeaderMsg = std_msgs::Header_<Alloc>;

// ROS time (uint32 sec, uint32 nsec since the epoch) in nanoseconds.
inline TimeNs ToNs(const ros::Time& stamp) {
  return static_cast<TimeNs>(stamp.sec) * kNsPerSecond + static_cast<TimeNs>(stamp.nsec);
}

// A message string (custom allocator) as std::string.
template <class S>
std::string ToStdString(const S& text) {
  return std::string(text.begin(), text.end());
}

}  // namespace mavloc::ros1
