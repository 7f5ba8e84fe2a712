// Real ROS1 bags of ../shared/data (../shared/data/SOURCES.md): robot_localization's test1.bag /
// test2.bag (IMU, bz2 chunks) and TagSLAM's whole-file-bzip2 bags (apriltag_msgs tag detections,
// odometry, /tf). Counts are checked against rosbag's own index (rosbag::View::size, what `rosbag
// info` prints), units against gravity, and the corner order against TagSLAM's own tag map and
// trajectory.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>

#include "core/errors.h"
#include "core/tag_geometry.h"
#include "datasets/io/rosbag/ros_messages.h"
#include "datasets/io/rosbag/rosbag_reader.h"
#include "tests/test_support.h"

namespace fs = std::filesystem;

namespace mavloc {
namespace {

// A LogTopicSpec (designated fields: the struct grows).
LogTopicSpec Spec(const std::string& path, const std::string& topic,
                  const std::string& tf_parent = "", const std::string& tf_child = "") {
  LogTopicSpec spec;
  spec.path = path;
  spec.topic = topic;
  spec.tf_parent = tf_parent;
  spec.tf_child = tf_child;
  return spec;
}

#define REQUIRE_FILE(path) \
  if (!fs::exists(path)) GTEST_SKIP() << path << " is absent (../shared/data)"

std::string RosBag(const std::string& name) {
  return testing::SharedDataDir() + "/ros_bags/" + name;
}
std::string TagSlam(const std::string& test, const std::string& file) {
  return testing::SharedDataDir() + "/tagslam/" + test + "/" + file;
}

// Message count and first/last header stamps of an IMU topic, straight from rosbag.
struct IndexFacts {
  uint64_t messages = 0;
  TimeNs first_stamp_ns = 0;
  TimeNs last_stamp_ns = 0;
};
IndexFacts ImuFacts(const std::string& path, const std::string& topic) {
  rosbag::Bag bag(path);
  rosbag::View view(bag, rosbag::TopicQuery(topic));
  IndexFacts facts;
  facts.messages = view.size();
  for (const rosbag::MessageInstance& message : view) {
    const TimeNs t_ns = ros1::ToNs(message.instantiate<ros1::ImuMsg>()->header.stamp);
    if (facts.first_stamp_ns == 0) facts.first_stamp_ns = t_ns;
    facts.last_stamp_ns = t_ns;
  }
  return facts;
}

void ExpectImuLog(const std::string& path, uint64_t expected_messages, double expected_rate_hz) {
  const IndexFacts facts = ImuFacts(path, "/imu/data");
  EXPECT_EQ(facts.messages, expected_messages);
  const auto samples = ReadRosbagImu(path, "/imu/data");
  ASSERT_EQ(samples.size(), facts.messages);
  EXPECT_EQ(samples.front().t_ns, facts.first_stamp_ns);
  EXPECT_EQ(samples.back().t_ns, facts.last_stamp_ns);
  const double rate_hz = static_cast<double>(samples.size() - 1) /
                         NsToSeconds(samples.back().t_ns - samples.front().t_ns);
  EXPECT_NEAR(rate_hz, expected_rate_hz, 0.05 * expected_rate_hz);
  // Units: m/s^2 (a ground robot's specific force is gravity, ~9.81) and rad/s (ground robots
  // turn at well under 2 rad/s; deg/s would read ~57 times more).
  double accel_norm_sum = 0.0, gyro_max = 0.0;
  for (const ImuSample& s : samples) {
    accel_norm_sum += s.accel_m_s2.norm();
    gyro_max = std::max(gyro_max, s.gyro_rad_s.norm());
  }
  EXPECT_NEAR(accel_norm_sum / samples.size(), 9.81, 0.3);
  EXPECT_LT(gyro_max, 3.0);
  EXPECT_GT(gyro_max, 0.05);  // it does turn
}

TEST(RosbagReal, Test1ImuMatchesTheIndex) {
  REQUIRE_FILE(RosBag("test1.bag"));
  ExpectImuLog(RosBag("test1.bag"), 11865, 30.0);
}

TEST(RosbagReal, Test2ImuMatchesTheIndex) {
  REQUIRE_FILE(RosBag("test2.bag"));
  ExpectImuLog(RosBag("test2.bag"), 3061, 50.0);
}

TEST(RosbagReal, Test1Summary) {
  REQUIRE_FILE(RosBag("test1.bag"));
  const LogSummary summary = SummarizeRosbag(RosBag("test1.bag"));
  ASSERT_EQ(summary.topics.size(), 3u);
  EXPECT_EQ(summary.topics[0].topic, "/fix");
  EXPECT_EQ(summary.topics[0].type, "sensor_msgs/NavSatFix");
  EXPECT_EQ(summary.topics[0].messages, 989u);
  EXPECT_EQ(summary.topics[1].topic, "/husky_velocity_controller/odom");
  EXPECT_EQ(summary.topics[1].messages, 3952u);
  EXPECT_EQ(summary.topics[2].topic, "/imu/data");
  EXPECT_EQ(summary.topics[2].messages, 11865u);
  EXPECT_EQ(summary.t_start_ns, 1432235498025043042);
  EXPECT_EQ(summary.t_end_ns, 1432235893332159182);
  const std::string notes = fmt::format("{}", fmt::join(summary.notes, "; "));
  EXPECT_NE(notes.find("/fix: sensor_msgs/NavSatFix is not read"), std::string::npos) << notes;
  EXPECT_NE(notes.find("bz2"), std::string::npos) << notes;
}

TEST(RosbagReal, TruncatedCopyNamesTheByteOffset) {
  REQUIRE_FILE(RosBag("test2.bag"));
  const std::string cut = testing::MakeTempDir() + "/test2_cut.bag";
  fs::copy_file(RosBag("test2.bag"), cut);
  fs::resize_file(cut, 300000);
  try {
    ReadRosbagImu(cut, "/imu/data");
    FAIL() << "no error";
  } catch (const InputError& error) {
    const std::string what = error.what();
    EXPECT_NE(what.find(cut + ": a record at byte "), std::string::npos) << what;
    EXPECT_NE(what.find("is cut off (truncated file) of 300000 bytes"), std::string::npos) << what;
  }
}

TEST(RosbagReal, TagSlamTopicsAndCounts) {
  REQUIRE_FILE(TagSlam("test_11", "tag_detections.bag.bz2"));
  struct Expected {
    std::string test;
    std::map<std::string, uint64_t> topics;
  };
  const std::vector<Expected> expected = {
      {"test_11",
       {{"/fla/ovc_node/left/tags", 4500},
        {"/fla/ovc_node/right/tags", 4500},
        {"/fla/vio/odom", 4500}}},
      {"test_21",
       {{"/left_tof/tags", 431},
        {"/right_tof/tags", 431},
        {"/t265/fisheye1/tags", 431},
        {"/t265/fisheye2/tags", 431},
        {"/vio_node/odom", 2596}}},
      {"test_22", {{"/camera/odom/sample", 115}, {"/detector/tags/left", 115}}}};
  for (const Expected& e : expected) {
    const LogSummary summary = SummarizeRosbag(TagSlam(e.test, "tag_detections.bag.bz2"));
    std::map<std::string, uint64_t> topics;
    for (const auto& topic : summary.topics) {
      topics[topic.topic] = topic.messages;
      const bool is_tags = topic.topic.find("tags") != std::string::npos;
      EXPECT_EQ(topic.type, is_tags ? "apriltag_msgs/ApriltagArrayStamped" : "nav_msgs/Odometry");
    }
    EXPECT_EQ(topics, e.topics) << e.test;
  }
}

// Ids listed in a TagSLAM tagslam.yaml ("- id: N").
std::set<int> MapTagIds(const std::string& yaml_path) {
  std::ifstream in(yaml_path);
  std::set<int> ids;
  std::string line;
  while (std::getline(in, line)) {
    const auto at = line.find("- id:");
    if (at != std::string::npos) ids.insert(std::stoi(line.substr(at + 5)));
  }
  return ids;
}

// Opposite sides of a tag seen by a camera have nearly the same length (a square under mild
// perspective), and mavloc's order runs counter-clockwise as the camera sees the tag: negative
// shoelace area in pixel coordinates (v down).
void ExpectSquareCorners(const std::vector<TagObservation>& tags, const std::string& what) {
  int consistent_sides = 0, counter_clockwise = 0;
  for (const TagObservation& tag : tags) {
    const auto& c = tag.corners_px;
    const double d01 = (c[1] - c[0]).norm(), d12 = (c[2] - c[1]).norm();
    const double d23 = (c[3] - c[2]).norm(), d30 = (c[0] - c[3]).norm();
    const bool opposite_agree = std::abs(d01 - d23) < 0.25 * std::max(d01, d23) &&
                                std::abs(d12 - d30) < 0.25 * std::max(d12, d30);
    consistent_sides += opposite_agree ? 1 : 0;
    double area2 = 0.0;
    for (int k = 0; k < 4; ++k) {
      const auto& a = c[k];
      const auto& b = c[(k + 1) % 4];
      area2 += a.x() * b.y() - b.x() * a.y();
    }
    counter_clockwise += area2 < 0.0 ? 1 : 0;
  }
  EXPECT_GT(consistent_sides, 0.95 * tags.size()) << what;
  EXPECT_EQ(counter_clockwise, static_cast<int>(tags.size())) << what;
}

TEST(RosbagReal, TagSlamTagsAreSquaresOfMappedTags) {
  REQUIRE_FILE(TagSlam("test_11", "tag_detections.bag.bz2"));
  const std::map<std::string, std::vector<std::pair<std::string, size_t>>> expected = {
      {"test_11", {{"/fla/ovc_node/left/tags", 0}, {"/fla/ovc_node/right/tags", 0}}},
      {"test_21", {{"/t265/fisheye1/tags", 0}, {"/t265/fisheye2/tags", 0}}},
      {"test_22", {{"/detector/tags/left", 0}}}};
  for (const auto& [test, topics] : expected) {
    const std::set<int> map_ids = MapTagIds(TagSlam(test, "tagslam.yaml"));
    for (size_t camera = 0; camera < topics.size(); ++camera) {
      const std::string& topic = topics[camera].first;
      const auto tags =
          ReadRosbagTags(TagSlam(test, "tag_detections.bag.bz2"), topic, static_cast<int>(camera));
      const std::string what = test + " " + topic;
      ASSERT_GT(tags.size(), 100u) << what;
      int mapped = 0;
      for (const TagObservation& tag : tags) {
        mapped += map_ids.count(tag.tag_id) > 0 ? 1 : 0;
        EXPECT_EQ(tag.camera, static_cast<int>(camera));
      }
      // test_11's map lists its 83 tags; tests 21 and 22 list only the tags that anchor the map.
      if (test == "test_11") {
        EXPECT_GT(mapped, 0.9 * tags.size()) << what;
      }
      ExpectSquareCorners(tags, what);
      fmt::print("{}: {} tags\n", what, tags.size());
    }
  }
}

TEST(RosbagReal, TagSlamReferenceOdometry) {
  REQUIRE_FILE(TagSlam("test_22", "reference.bag.bz2"));
  const LogTrajectory reference =
      ReadRosbagTrajectory(Spec(TagSlam("test_22", "reference.bag.bz2"), "/tagslam/odom/body_rig"));
  EXPECT_EQ(reference.type, "nav_msgs/Odometry");
  ASSERT_EQ(reference.states.size(), 112u);
  EXPECT_EQ(reference.parent_frame, "map");
  EXPECT_EQ(reference.child_frame, "camera_pose_frame");
  EXPECT_TRUE(reference.has_velocity);
  // The odometry equals TagSLAM's /tf map -> rig at the same stamps.
  const LogTrajectory tf =
      ReadRosbagTrajectory(Spec(TagSlam("test_22", "reference.bag.bz2"), "/tf", "map", "rig"));
  std::map<TimeNs, Pose> tf_by_stamp;
  for (const auto& s : tf.states) tf_by_stamp[s.t_ns] = s.T_W_B;
  int matched = 0;
  for (const auto& s : reference.states) {
    const auto it = tf_by_stamp.find(s.t_ns);
    if (it == tf_by_stamp.end()) continue;
    ++matched;
    EXPECT_LT((it->second.p - s.T_W_B.p).norm(), 1e-6);
    EXPECT_LT(RotationAngleBetween(it->second.q, s.T_W_B.q), 1e-6);
  }
  EXPECT_GT(matched, 100);
}

// The corner order on real data: TagSLAM's tag 3 (test_22) projected through TagSLAM's own /tf
// (map -> rig -> cam0, map -> yard -> tag_3) and cameras.yaml's equidistant model lands on the
// detected corners in mavloc's order, and not on any other order.
TEST(RosbagReal, TagSlamCornerOrderMatchesTheTagMap) {
  REQUIRE_FILE(TagSlam("test_22", "reference.bag.bz2"));
  const std::string reference = TagSlam("test_22", "reference.bag.bz2");
  auto edge = [&](const char* parent, const char* child) {
    return ReadRosbagTrajectory(Spec(reference, "/tf", parent, child));
  };
  const Pose T_rig_cam = edge("rig", "cam0").states.front().T_W_B;
  const Pose T_map_tag =
      edge("map", "yard").states.front().T_W_B * edge("yard", "tag_3").states.front().T_W_B;
  std::map<TimeNs, Pose> T_map_rig;
  for (const auto& s : edge("map", "rig").states) T_map_rig[s.t_ns] = s.T_W_B;
  const CameraModel camera(848, 800, Eigen::Vector4d(283.943, 284.986, 421.079, 400.527),
                           DistortionModel::kEquidistant, {0.00132, 0.03049, -0.02875, 0.0034});
  const auto corners_T = TagCornersInTagFrame(0.42);
  const auto tags =
      ReadRosbagTags(TagSlam("test_22", "tag_detections.bag.bz2"), "/detector/tags/left", 0);
  // Squared error per cyclic shift s (detected corner (k + s) % 4 against map corner k), and for
  // the reversed order.
  std::array<double, 8> sum_sq{};
  int used = 0;
  for (const TagObservation& tag : tags) {
    const auto it = T_map_rig.find(tag.t_ns);
    if (tag.tag_id != 3 || it == T_map_rig.end()) continue;
    const Pose T_cam_tag = (it->second * T_rig_cam).Inverse() * T_map_tag;
    std::array<Eigen::Vector2d, 4> projected;
    bool ok = true;
    for (int k = 0; k < 4; ++k) {
      const auto uv = camera.Project(T_cam_tag * corners_T[k]);
      ok = ok && uv.has_value();
      if (uv) projected[k] = *uv;
    }
    if (!ok) continue;
    ++used;
    for (int s = 0; s < 8; ++s) {
      for (int k = 0; k < 4; ++k) {
        const int j = s < 4 ? (k + s) % 4 : (s - k) % 4;
        sum_sq[s] += (tag.corners_px[j] - projected[k]).squaredNorm();
      }
    }
  }
  ASSERT_GT(used, 30);
  std::array<double, 8> rms_px;
  for (int s = 0; s < 8; ++s) rms_px[s] = std::sqrt(sum_sq[s] / (4.0 * used));
  fmt::print("corner RMS [px] per order (shifts 0-3, reversed 4-7): {:.2f}\n",
             fmt::join(rms_px, " "));
  EXPECT_LT(rms_px[0], 5.0);
  for (int s = 1; s < 8; ++s) EXPECT_GT(rms_px[s], 5.0 * rms_px[0]) << s;
}

}  // namespace
}  // namespace mavloc
