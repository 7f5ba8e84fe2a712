// TagSLAM's tagslam.yaml -> mavloc's known tag map: the real files of tests 1, 11, 21 and 22
// (counts, known tag poses from the rotation-vector convention, a static body's pose, ignored
// ids, id remaps, odometry topics) and small files written here for every bad-input error.
#include "datasets/io/tagslam/tagslam_map_io.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "core/errors.h"
#include "core/rotation.h"
#include "tests/test_support.h"

namespace mavloc {
namespace {

std::string TestFile(const std::string& test) {
  return testing::SharedDataDir() + "/tagslam/" + test + "/tagslam.yaml";
}

TEST(TagslamMap, Test11BuildingMap) {
  REQUIRE_SHARED_DATA();
  const TagslamMap m = ReadTagslamMap(TestFile("test_11"));
  EXPECT_EQ(m.map.frame, MapFrame::kWorld);
  EXPECT_EQ(m.listed_tags.size(), 82u);
  EXPECT_EQ(m.map.tags.size(), 82u);  // every listed tag has a pose; none is ignored
  EXPECT_EQ(m.ignored_tags.size(), 10u);
  EXPECT_TRUE(m.ignored_tags.count(166));
  EXPECT_TRUE(m.tags_without_pose.empty());
  EXPECT_EQ(m.default_body, "top_floor");
  EXPECT_EQ(m.static_bodies, std::vector<std::string>{"top_floor"});
  EXPECT_EQ(m.dynamic_bodies, std::vector<std::string>{"rig"});
  // Tag 0: position (0.589, 19.26, 2.289), rotation vector (2.22144147, 2.22144147, 0) = pi about
  // (1, 1, 0)/sqrt(2): R = 2 n n^T - I = [[0 1 0] [1 0 0] [0 0 -1]], a ceiling tag facing down.
  const TagInfo& tag0 = m.map.tags.at(0);
  EXPECT_DOUBLE_EQ(tag0.size_m, 0.150);
  EXPECT_NEAR((tag0.T_W_T.p - Eigen::Vector3d(0.589, 19.26, 2.289)).norm(), 0.0, 1e-12);
  Eigen::Matrix3d expected;
  expected << 0, 1, 0, 1, 0, 0, 0, 0, -1;
  EXPECT_LT((tag0.T_W_T.R() - expected).cwiseAbs().maxCoeff(), 1e-8);
  // tag_id_remap: detections of 20 within the two windows are 420 and 520, both in the map.
  ASSERT_EQ(m.id_remaps.size(), 2u);
  EXPECT_EQ(m.id_remaps[0].remap_id, 420);
  EXPECT_EQ(m.id_remaps[0].t_begin_ns, 1541686885999522770LL);
  EXPECT_EQ(m.id_remaps[1].t_end_ns, 1541687229942551085LL);
  EXPECT_EQ(RemapTagId(m.id_remaps, 20, 1541686900000000000LL), 420);
  EXPECT_EQ(RemapTagId(m.id_remaps, 20, 1541687200000000000LL), 520);
  EXPECT_EQ(RemapTagId(m.id_remaps, 20, 1541687000000000000LL), 20);
  EXPECT_EQ(RemapTagId(m.id_remaps, 21, 1541686900000000000LL), 21);
  EXPECT_TRUE(m.map.tags.count(420) && m.map.tags.count(520));
  ASSERT_EQ(m.odometry.size(), 1u);
  EXPECT_EQ(m.odometry[0].topic, "/fla/vio/odom");
  EXPECT_TRUE(m.odometry[0].has_T_body_odom);
  EXPECT_NEAR(m.odometry[0].T_body_odom.p.x(), 0.02535438, 1e-12);
}

TEST(TagslamMap, Test21OneKnownTagNineUnknown) {
  REQUIRE_SHARED_DATA();
  const TagslamMap m = ReadTagslamMap(TestFile("test_21"));
  EXPECT_EQ(m.listed_tags.size(), 10u);
  ASSERT_EQ(m.map.tags.size(), 1u);
  EXPECT_EQ(m.tags_without_pose, (std::vector<int>{100, 101, 102, 103, 104, 105, 106, 107, 108}));
  const TagInfo& tag2 = m.map.tags.at(2);
  EXPECT_DOUBLE_EQ(tag2.size_m, 0.16);
  EXPECT_NEAR((tag2.T_W_T.p - Eigen::Vector3d(0.93840377, -0.51000614, 0.13412727)).norm(), 0.0,
              1e-12);
  // The rotation vector round-trips through mavloc's Log.
  EXPECT_NEAR(
      (LogSO3(tag2.T_W_T.R()) - Eigen::Vector3d(1.06798425, -1.09447860, -1.25097143)).norm(), 0.0,
      1e-9);
  ASSERT_EQ(m.odometry.size(), 1u);
  EXPECT_EQ(m.odometry[0].topic, "/vio_node/odom");
  EXPECT_EQ(m.odometry[0].frame_id, "basalt_pose_frame");
}

TEST(TagslamMap, Test22TagOnAWall) {
  REQUIRE_SHARED_DATA();
  const TagslamMap m = ReadTagslamMap(TestFile("test_22"));
  ASSERT_EQ(m.map.tags.size(), 1u);
  const TagInfo& tag3 = m.map.tags.at(3);
  EXPECT_DOUBLE_EQ(tag3.size_m, 0.42);
  // Rotation vector (0, -1.5708, 0): the tag's z axis (its normal) is -x of the yard.
  EXPECT_LT((tag3.T_W_T.R().col(2) - Eigen::Vector3d(-1, 0, 0)).norm(), 1e-4);
  EXPECT_NEAR(tag3.T_W_T.p.z(), 1.5, 1e-12);
  ASSERT_EQ(m.odometry.size(), 1u);
  EXPECT_EQ(m.odometry[0].topic, "/camera/odom/sample");
}

TEST(TagslamMap, Test1StaticBodyPoseComposes) {
  REQUIRE_SHARED_DATA();
  // The body 'perch' has pose rotation (0, 1.507963, 0); its tag 0 sits at the body's origin with
  // identity rotation, so T_W_T is the body's pose.
  const TagslamMap m = ReadTagslamMap(TestFile("test_1"));
  ASSERT_EQ(m.map.tags.size(), 1u);
  const TagInfo& tag0 = m.map.tags.at(0);
  EXPECT_DOUBLE_EQ(tag0.size_m, 0.225);
  EXPECT_LT((tag0.T_W_T.R() - ExpSO3(Eigen::Vector3d(0, 1.507963, 0))).norm(), 1e-12);
  EXPECT_TRUE(m.odometry.empty());
}

std::string WriteYaml(const std::string& text) {
  const std::string path = testing::MakeTempDir() + "/tagslam.yaml";
  std::ofstream(path) << text;
  return path;
}

std::string ErrorOf(const std::string& text) {
  try {
    ReadTagslamMap(WriteYaml(text));
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

const char* kBody =
    "bodies:\n"
    " - room:\n"
    "     is_static: true\n"
    "     default_tag_size: 0.2\n"
    "     pose:\n"
    "       position: {x: 1, y: 0, z: 0}\n"
    "       rotation: {x: 0, y: 0, z: 1.5707963267948966}\n"
    "     tags:\n";

TEST(TagslamMap, SmallFileComposesBodyAndDefaults) {
  const TagslamMap m = ReadTagslamMap(
      WriteYaml(std::string(kBody) +
                "       - id: 7\n"
                "         pose:\n"
                "           position: {x: 1, y: 0, z: 0}\n"
                "           rotation: {x: 0, y: 0, z: 0}\n"
                "       - id: 8\n"
                "         size: 0.1\n"
                " - rig:\n"
                "     is_static: false\n"
                "     tags:\n"
                "       - id: 9\n"
                "         size: 0.05\n"
                "         pose: {position: {x: 0, y: 0, z: 0}, rotation: {x: 0, y: 0, z: 0}}\n"));
  ASSERT_EQ(m.map.tags.size(), 1u);
  // T_W_T = T_W_room * T_room_tag: the room is turned 90 deg about z and shifted by x = 1, so the
  // tag at x = 1 in the room is at (1, 1, 0) in W; its size is the room's default.
  EXPECT_NEAR((m.map.tags.at(7).T_W_T.p - Eigen::Vector3d(1, 1, 0)).norm(), 0.0, 1e-12);
  EXPECT_DOUBLE_EQ(m.map.tags.at(7).size_m, 0.2);
  EXPECT_EQ(m.tags_without_pose, std::vector<int>{8});
  EXPECT_EQ(m.tags_on_dynamic_bodies, std::vector<int>{9});
}

TEST(TagslamMapBadInput, ErrorsNameFileLineAndField) {
  // A missing position component.
  std::string error = ErrorOf(std::string(kBody) +
                              "       - id: 7\n"
                              "         pose:\n"
                              "           position: {x: 1, y: 0}\n"
                              "           rotation: {x: 0, y: 0, z: 0}\n");
  EXPECT_NE(error.find("tagslam.yaml"), std::string::npos) << error;
  EXPECT_NE(error.find("'z'"), std::string::npos) << error;
  EXPECT_NE(error.find("missing"), std::string::npos) << error;
  // A rotation that is not a number, with its line.
  error = ErrorOf(std::string(kBody) +
                  "       - id: 7\n"
                  "         pose:\n"
                  "           position: {x: 1, y: 0, z: 0}\n"
                  "           rotation: {x: 0, y: abc, z: 0}\n");
  EXPECT_NE(error.find("tagslam.yaml:12"), std::string::npos) << error;
  EXPECT_NE(error.find("'y'"), std::string::npos) << error;
  // A duplicate id.
  error = ErrorOf(std::string(kBody) + "       - id: 7\n       - id: 7\n");
  EXPECT_NE(error.find("tagslam.yaml:10"), std::string::npos) << error;
  EXPECT_NE(error.find("tag 7 listed twice"), std::string::npos) << error;
  // A tag without id.
  error = ErrorOf(std::string(kBody) + "       - size: 0.1\n");
  EXPECT_NE(error.find("'id'"), std::string::npos) << error;
  // A non-positive size.
  error = ErrorOf(std::string(kBody) + "       - id: 1\n         size: -0.1\n");
  EXPECT_NE(error.find("must be > 0"), std::string::npos) << error;
  // No bodies.
  EXPECT_NE(ErrorOf("default_body: x\n").find("'bodies'"), std::string::npos);
  // A remap ending before it starts, and a malformed ROS time.
  const std::string remap_head = std::string(kBody) + "       - id: 1\n" +
                                 "tag_id_remap:\n"
                                 "  - id: 1\n"
                                 "    remaps:\n"
                                 "      - remap_id: 2\n";
  error = ErrorOf(remap_head + "        start_time: 10.000000000\n        end_time: 9.5\n");
  EXPECT_NE(error.find("end_time"), std::string::npos) << error;
  EXPECT_NE(error.find("before start_time"), std::string::npos) << error;
  error = ErrorOf(remap_head + "        start_time: 1e9\n        end_time: 9.5\n");
  EXPECT_NE(error.find("start_time"), std::string::npos) << error;
  EXPECT_NE(error.find("not a ROS time"), std::string::npos) << error;
}

TEST(TagslamMap, RosTimeText) {
  EXPECT_EQ(ParseRosTimeText("1541686885.999522770"), 1541686885999522770LL);
  EXPECT_EQ(ParseRosTimeText("12.5"), 12500000000LL);
  EXPECT_EQ(ParseRosTimeText("12"), 12000000000LL);
  EXPECT_FALSE(ParseRosTimeText("-1.0"));
  EXPECT_FALSE(ParseRosTimeText("1.0000000001"));
  EXPECT_FALSE(ParseRosTimeText("1e9"));
  EXPECT_FALSE(ParseRosTimeText(""));
}

}  // namespace
}  // namespace mavloc
