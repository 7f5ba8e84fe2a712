// mavloc's hand-written AprilTag message types: their MD5 sums are ROS's (genmsg's MD5 text: the
// field list with nested message types replaced by their MD5, computed here with Boost's MD5), and
// the canonical form of a definition ignores comments and spacing.
#include "datasets/io/rosbag/rosbag_tag_messages.h"

#include <gtest/gtest.h>

#include <boost/uuid/detail/md5.hpp>
#include <cstdio>

namespace mavloc::ros1 {
namespace {

std::string Md5Hex(const std::string& text) {
  boost::uuids::detail::md5 hash;
  hash.process_bytes(text.data(), text.size());
  boost::uuids::detail::md5::digest_type digest;
  hash.get_digest(digest);
  std::string hex;
  for (const auto word : digest) {  // four 32-bit words, most significant byte first
    char bytes[9];
    std::snprintf(bytes, sizeof(bytes), "%08x", static_cast<unsigned>(word));
    hex += bytes;
  }
  return hex;
}

// MD5 sums of the Debian message types the texts below refer to (their generated headers).
const std::string kHeaderMd5 = ros::message_traits::MD5Sum<HeaderMsg>::value();
const std::string kPointMd5 = ros::message_traits::MD5Sum<PointMsg>::value();
const std::string kPoseWithCovarianceStampedMd5 =
    ros::message_traits::MD5Sum<PoseWithCovarianceStampedMsg>::value();

TEST(RosbagTagMessages, Md5SumsFollowGenmsg) {
  EXPECT_EQ(Md5Hex("float64 x\nfloat64 y\nfloat64 z"), kPointMd5);  // the method itself
  const std::string apriltag = Md5Hex(
      "int32 id\nstring family\nint32 hamming\nint32 border\n"
      "int32 bits\n" +
      kPointMd5 + " center\n" + kPointMd5 + " corners");
  EXPECT_EQ(Md5Hex(kHeaderMd5 + " header\n" + apriltag + " apriltags"), kApriltagArrayStampedMd5);
  const std::string detection =
      Md5Hex("int32[] id\nfloat64[] size\n" + kPoseWithCovarianceStampedMd5 + " pose");
  EXPECT_EQ(Md5Hex(kHeaderMd5 + " header\n" + detection + " detections"),
            kAprilTagDetectionArrayMd5);
}

TEST(RosbagTagMessages, CanonicalDefinitionIgnoresCommentsAndSpacing) {
  const auto a = CanonicalDefinitionLines("# comment\nHeader  header \n\nint32 id   # the id\n");
  const auto b = CanonicalDefinitionLines("std_msgs/Header header\nint32 id");
  EXPECT_EQ(a, b);
  ASSERT_EQ(a.size(), 2u);
  EXPECT_EQ(a[1], "int32 id");
  const auto ours = CanonicalDefinitionLines(ApriltagArrayStampedDefinition());
  EXPECT_EQ(ours.front(), "std_msgs/Header header");
  EXPECT_EQ(ours[1], "Apriltag[] apriltags");
}

}  // namespace
}  // namespace mavloc::ros1
