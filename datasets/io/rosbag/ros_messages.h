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
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/CompressedImage.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/Imu.h>
#include <tf2_msgs/TFMessage.h>
#include <memory>
#include <string>

#include "core/time.h"

namespace mavloc::ros1 {

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
