// AprilTag detection messages that Debian does not package, written by hand for ros::serialization
// with the same field layout as their .msg files (the ROS1 wire format: little-endian scalars,
// uint32-length-prefixed strings and variable arrays, fixed arrays without a length). The MD5 sums
// below are ROS's (genmsg: MD5 of the field list with nested types replaced by their MD5); the
// reader compares them with the MD5 and definition the bag's connection header holds.
//
// apriltag_msgs/ApriltagArrayStamped (versatran01/apriltag, used by TagSLAM): std_msgs/Header
// header, Apriltag[] apriltags; Apriltag: int32 id, string family, int32 hamming, int32 border,
// int32 bits, geometry_msgs/Point center, geometry_msgs/Point[4] corners (pixels in x, y).
// Corner order: message corner k is mavloc's / libapriltag's corner k (bottom-left of the tag
// first, counter-clockwise as the camera sees it), the order of TagSLAM's object corners
// (-s/2,-s/2), (s/2,-s/2), (s/2,s/2), (-s/2,s/2) (tagslam src/tag2.cpp). Checked on TagSLAM's
// test_22 (rosbag_real_test.cc): tag 3 projected through TagSLAM's own /tf poses and cameras.yaml
// lands on the detected corners with 0.37 px RMS in this order, 27-44 px in the 7 other orders.
//
// apriltag_ros/AprilTagDetectionArray (AprilRobotics/apriltag_ros, release 3.x): std_msgs/Header
// header, AprilTagDetection[] detections; AprilTagDetection: int32[] id, float64[] size,
// geometry_msgs/PoseWithCovarianceStamped pose (the tag, or a bundle, in the camera frame, solved
// by PnP with K and no distortion from its corners: x right, y up, z out of the tag). It carries
// no pixel corners.
#pragma once

#include <ros/message_traits.h>
#include <ros/serialization.h>
#include <boost/array.hpp>
#include <cstdint>
#include <string>
#include <vector>

#include "datasets/io/rosbag/ros_messages.h"

namespace mavloc::ros1 {

template <class T>
using RosVector = std::vector<T, RosAllocator<T>>;
using PointMsg = geometry_msgs::Point_<Alloc>;

struct ApriltagMsg {
  int32_t id = 0;
  std::string family;
  int32_t hamming = 0;
  int32_t border = 0;
  int32_t bits = 0;
  PointMsg center;
  boost::array<PointMsg, 4> corners;
};

struct ApriltagArrayStampedMsg {
  HeaderMsg header;
  RosVector<ApriltagMsg> apriltags;
};

struct AprilTagDetectionMsg {
  RosVector<int32_t> id;
  RosVector<double> size;
  PoseWithCovarianceStampedMsg pose;
};

struct AprilTagDetectionArrayMsg {
  HeaderMsg header;
  RosVector<AprilTagDetectionMsg> detections;
};

inline constexpr char kApriltagArrayStampedMd5[] = "179c9ccf1becf89d2541dd94fbd5accd";
inline constexpr char kAprilTagDetectionArrayMd5[] = "2b6c03434883a5c9897c13b5594dbd91";

// The definitions as rosbag stores them (comments removed).
const char* ApriltagArrayStampedDefinition();
const char* AprilTagDetectionArrayDefinition();

// The definition's field lines without comments, blank lines and surplus spaces, "Header" spelled
// "std_msgs/Header": two definitions of the same layout compare equal.
std::vector<std::string> CanonicalDefinitionLines(const std::string& definition);

}  // namespace mavloc::ros1

namespace ros::message_traits {

template <>
struct IsMessage<mavloc::ros1::ApriltagArrayStampedMsg> : TrueType {};
template <>
struct HasHeader<mavloc::ros1::ApriltagArrayStampedMsg> : TrueType {};
template <>
struct MD5Sum<mavloc::ros1::ApriltagArrayStampedMsg> {
  static const char* value() { return mavloc::ros1::kApriltagArrayStampedMd5; }
  static const char* value(const mavloc::ros1::ApriltagArrayStampedMsg&) { return value(); }
};
template <>
struct DataType<mavloc::ros1::ApriltagArrayStampedMsg> {
  static const char* value() { return "apriltag_msgs/ApriltagArrayStamped"; }
  static const char* value(const mavloc::ros1::ApriltagArrayStampedMsg&) { return value(); }
};
template <>
struct Definition<mavloc::ros1::ApriltagArrayStampedMsg> {
  static const char* value() { return mavloc::ros1::ApriltagArrayStampedDefinition(); }
  static const char* value(const mavloc::ros1::ApriltagArrayStampedMsg&) { return value(); }
};

template <>
struct IsMessage<mavloc::ros1::AprilTagDetectionArrayMsg> : TrueType {};
template <>
struct HasHeader<mavloc::ros1::AprilTagDetectionArrayMsg> : TrueType {};
template <>
struct MD5Sum<mavloc::ros1::AprilTagDetectionArrayMsg> {
  static const char* value() { return mavloc::ros1::kAprilTagDetectionArrayMd5; }
  static const char* value(const mavloc::ros1::AprilTagDetectionArrayMsg&) { return value(); }
};
template <>
struct DataType<mavloc::ros1::AprilTagDetectionArrayMsg> {
  static const char* value() { return "apriltag_ros/AprilTagDetectionArray"; }
  static const char* value(const mavloc::ros1::AprilTagDetectionArrayMsg&) { return value(); }
};
template <>
struct Definition<mavloc::ros1::AprilTagDetectionArrayMsg> {
  static const char* value() { return mavloc::ros1::AprilTagDetectionArrayDefinition(); }
  static const char* value(const mavloc::ros1::AprilTagDetectionArrayMsg&) { return value(); }
};

}  // namespace ros::message_traits

namespace ros::serialization {

template <>
struct Serializer<mavloc::ros1::ApriltagMsg> {
  template <typename Stream, typename T>
  inline static void allInOne(Stream& stream, T m) {
    stream.next(m.id);
    stream.next(m.family);
    stream.next(m.hamming);
    stream.next(m.border);
    stream.next(m.bits);
    stream.next(m.center);
    stream.next(m.corners);
  }
  ROS_DECLARE_ALLINONE_SERIALIZER
};

template <>
struct Serializer<mavloc::ros1::ApriltagArrayStampedMsg> {
  template <typename Stream, typename T>
  inline static void allInOne(Stream& stream, T m) {
    stream.next(m.header);
    stream.next(m.apriltags);
  }
  ROS_DECLARE_ALLINONE_SERIALIZER
};

template <>
struct Serializer<mavloc::ros1::AprilTagDetectionMsg> {
  template <typename Stream, typename T>
  inline static void allInOne(Stream& stream, T m) {
    stream.next(m.id);
    stream.next(m.size);
    stream.next(m.pose);
  }
  ROS_DECLARE_ALLINONE_SERIALIZER
};

template <>
struct Serializer<mavloc::ros1::AprilTagDetectionArrayMsg> {
  template <typename Stream, typename T>
  inline static void allInOne(Stream& stream, T m) {
    stream.next(m.header);
    stream.next(m.detections);
  }
  ROS_DECLARE_ALLINONE_SERIALIZER
};

}  // namespace ros::serialization
