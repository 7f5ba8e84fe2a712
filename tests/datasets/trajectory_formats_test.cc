// Trajectory readers and writers (datasets/io/trajectory_formats): every accepted
// variant of the files evo, ov_eval, Kimera-VIO, VINS-Fusion and the KITTI devkit read or write,
// every refused case with its file:line and field, and the real EuRoC V1_01 ground truth in both
// of its formats.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "core/errors.h"
#include "datasets/io/trajectory_formats/kitti_poses.h"
#include "datasets/io/trajectory_formats/trajectory_format.h"
#include "datasets/io/tum_io.h"
#include "tests/test_support.h"

namespace mavloc {
namespace {

struct Accepted {
  const char* name;
  const char* file_name;
  std::string body;
  TrajectoryFormat forced = TrajectoryFormat::kAuto;
  bool sort = false;
  TrajectoryFormat expected_format;
  size_t expected_poses;
  // First pose after reading (stamp, position, quaternion w x y z).
  TimeNs t0_ns;
  Eigen::Vector3d p0;
  Eigen::Vector4d q0_wxyz;
  size_t expected_duplicates = 0;
  long expected_first_duplicate_line = 0;
  bool expected_velocity = false;
};

const Eigen::Vector4d kIdentity(1, 0, 0, 0);

std::vector<Accepted> AcceptedCases() {
  const std::string tum = "1.0 1 2 3 0 0 0 1\n2.0 4 5 6 0 0 0 1\n3.5 7 8 9 0 0 0 1\n";
  std::vector<Accepted> cases = {
      {"TumPlain",
       "t.txt",
       tum,
       TrajectoryFormat::kAuto,
       false,
       TrajectoryFormat::kTum,
       3,
       1'000'000'000,
       {1, 2, 3},
       kIdentity},
      {"TumRgbdHeaderComments",
       "t.txt",
       "# ground truth trajectory\n# file: 'rgbd_dataset_freiburg2_desk.bag'\n# timestamp tx ty tz "
       "qx qy qz qw\n" +
           tum,
       TrajectoryFormat::kAuto,
       false,
       TrajectoryFormat::kTum,
       3,
       1'000'000'000,
       {1, 2, 3},
       kIdentity},
      {"TumCrlf",
       "t.txt",
       "1.0 1 2 3 0 0 0 1\r\n2.0 4 5 6 0 0 0 1\r\n",
       TrajectoryFormat::kAuto,
       false,
       TrajectoryFormat::kTum,
       2,
       1'000'000'000,
       {1, 2, 3},
       kIdentity},
      {"TumUtf8Bom",
       "t.txt",
       "\xEF\xBB\xBF# timestamp tx ty tz qx qy qz qw\n" + tum,
       TrajectoryFormat::kAuto,
       false,
       TrajectoryFormat::kTum,
       3,
       1'000'000'000,
       {1, 2, 3},
       kIdentity},
      {"TumTabsBlankLinesTrailingSpaces",
       "t.txt",
       "\n1.0\t1\t2\t3\t0\t0\t0\t1  \n\n2.0  4 5   6 0 0 0 1\n\n",
       TrajectoryFormat::kAuto,
       false,
       TrajectoryFormat::kTum,
       2,
       1'000'000'000,
       {1, 2, 3},
       kIdentity},
      {"TumCommas",
       "t.txt",
       "1.0,1,2,3,0,0,0,1\n2.0,4,5,6,0,0,0,1\n",
       TrajectoryFormat::kTum,
       false,
       TrajectoryFormat::kTum,
       2,
       1'000'000'000,
       {1, 2, 3},
       kIdentity},
      {"TumRepeatedStampKeepsFirst",
       "t.txt",
       "1.0 1 2 3 0 0 0 1\n2.0 4 5 6 0 0 0 1\n2.0 9 9 9 0 0 0 1\n2.000 8 8 8 0 0 0 1\n3.0 7 8 9 0 "
       "0 "
       "0 1\n",
       TrajectoryFormat::kAuto,
       false,
       TrajectoryFormat::kTum,
       3,
       1'000'000'000,
       {1, 2, 3},
       kIdentity,
       2,
       3},
      {"TumScientificStamps",
       "t.txt",
       "1.403636580013555527e+09 1 2 3 0 0 0 1\n1.403636580018555527e+09 1 2 3 0 0 0 1\n",
       TrajectoryFormat::kAuto,
       false,
       TrajectoryFormat::kTum,
       2,
       1'403'636'580'013'555'456,
       {1, 2, 3},
       kIdentity},
      {"OvEval20Columns",
       "t.txt",
       "# timestamp(s) tx ty tz qx qy qz qw Pr11 Pr12 Pr13 Pr22 Pr23 Pr33 Pt11 Pt12 Pt13 Pt22 Pt23 "
       "Pt33\n1.0 1 2 3 0 0 0 1 1 0 0 1 0 1 1 0 0 1 0 1\n2.0 1 2 3 0 0 0 1 1 0 0 1 0 1 1 0 0 1 0 "
       "1\n",
       TrajectoryFormat::kAuto,
       false,
       TrajectoryFormat::kTum,
       2,
       1'000'000'000,
       {1, 2, 3},
       kIdentity},
      {"OvEval20ColumnsNoHeader",
       "t.txt",
       "1.0 1 2 3 0 0 0 1 1 0 0 1 0 1 1 0 0 1 0 1\n2.0 1 2 3 0 0 0 1 1 0 0 1 0 1 1 0 0 1 0 1\n",
       TrajectoryFormat::kAuto,
       false,
       TrajectoryFormat::kTum,
       2,
       1'000'000'000,
       {1, 2, 3},
       kIdentity},
      {"TumFewDecimalsNormalised",
       "t.txt",
       "1.0 0 0 0 0.707 0 0 0.709\n",
       TrajectoryFormat::kAuto,
       false,
       TrajectoryFormat::kTum,
       1,
       1'000'000'000,
       {0, 0, 0},
       Eigen::Vector4d(0.709, 0.707, 0, 0).normalized()},
      {"EurocGroundTruth17",
       "data.csv",
       "#timestamp, p_RS_R_x [m], p_RS_R_y [m], p_RS_R_z [m], q_RS_w [], q_RS_x [], q_RS_y [], "
       "q_RS_z [], v_RS_R_x [m s^-1], v_RS_R_y [m s^-1], v_RS_R_z [m s^-1], b_w_RS_S_x [rad s^-1], "
       "b_w_RS_S_y [rad s^-1], b_w_RS_S_z [rad s^-1], b_a_RS_S_x [m s^-2], b_a_RS_S_y [m s^-2], "
       "b_a_RS_S_z [m s^-2]\n"
       "1403715274302142976,1,2,3,1,0,0,0,0.1,0.2,0.3,0,0,0,0,0,0\n"
       "1403715274307142912,1,2,3,1,0,0,0,0.1,0.2,0.3,0,0,0,0,0,0\n",
       TrajectoryFormat::kAuto,
       false,
       TrajectoryFormat::kEuroc,
       2,
       1403715274302142976,
       {1, 2, 3},
       kIdentity,
       0,
       0,
       true},
      {"EurocPoseOnlyNoHeader",
       "data.csv",
       "100,1,2,3,1,0,0,0\n200,1,2,3,1,0,0,0\n",
       TrajectoryFormat::kAuto,
       false,
       TrajectoryFormat::kEuroc,
       2,
       100,
       {1, 2, 3},
       kIdentity},
      {"VinsFusionTrailingComma",
       "vio.csv",
       "1403715282262142976,1.00000,2.00000,3.00000,0.70711,0.70711,0.00000,0.00000,0.1,0.2,0.3,\n"
       "1403715282312143104,1.00000,2.00000,3.00000,0.70711,0.70711,0.00000,0.00000,0.1,0.2,0.3,\n",
       TrajectoryFormat::kAuto,
       false,
       TrajectoryFormat::kEuroc,
       2,
       1403715282262142976,
       {1, 2, 3},
       Eigen::Vector4d(1, 1, 0, 0).normalized(),
       0,
       0,
       true},
      {"KimeraHeader",
       "traj_vio.csv",
       "#timestamp,x,y,z,qw,qx,qy,qz,vx,vy,vz,bgx,bgy,bgz,bax,bay,baz\n"
       "1403715274302142976,1,2,3,1,0,0,0,0.1,0.2,0.3,0,0,0,0,0,0\n"
       "1403715274352142976,1,2,3,1,0,0,0,0.1,0.2,0.3,0,0,0,0,0,0\n",
       TrajectoryFormat::kAuto,
       false,
       TrajectoryFormat::kAsl,
       2,
       1403715274302142976,
       {1, 2, 3},
       kIdentity,
       0,
       0,
       true},
      {"AslColumnsInAnotherOrder",
       "est.csv",
       "#timestamp [ns],qx,qy,qz,qw,x,y,z\n5000,0,0,1,0,1,2,3\n6000,0,0,1,0,1,2,3\n",
       TrajectoryFormat::kAuto,
       false,
       TrajectoryFormat::kAsl,
       2,
       5000,
       {1, 2, 3},
       Eigen::Vector4d(0, 0, 0, 1)},
      {"AslHeaderWithoutHashSeconds",
       "est.csv",
       "timestamp,x,y,z,qw,qx,qy,qz\n1.5,1,2,3,1,0,0,0\n2.5,1,2,3,1,0,0,0\n",
       TrajectoryFormat::kAuto,
       false,
       TrajectoryFormat::kAsl,
       2,
       1'500'000'000,
       {1, 2, 3},
       kIdentity},
      {"CommasWithSpaces",
       "est.csv",
       "100, 1, 2, 3, 1, 0, 0, 0\n200, 1, 2, 3, 1, 0, 0, 0\n",
       TrajectoryFormat::kAuto,
       false,
       TrajectoryFormat::kEuroc,
       2,
       100,
       {1, 2, 3},
       kIdentity},
      {"OpenVinsStateFile",
       "state_estimate.txt",
       "# timestamp(s) q p v bg ba cam_imu_dt num_cam cam0_k cam0_d cam0_rot cam0_trans .... etc\n"
       "1.0 0 0 0 1 2 3 4 0.1 0.2 0.3 0 0 0 0 0 0 0.001 1\n"
       "2.0 0 0 0 1 5 6 7 0.1 0.2 0.3 0 0 0 0 0 0 0.001 1\n",
       TrajectoryFormat::kAuto,
       false,
       TrajectoryFormat::kAsl,
       2,
       1'000'000'000,
       {2, 3, 4},
       kIdentity,
       0,
       0,
       true},
      {"RostopicEchoCsv",
       "pose.csv",
       "%time,field.header.seq,field.header.stamp,field.header.frame_id,field.pose.position.x,"
       "field.pose.position.y,field.pose.position.z,field.pose.orientation.x,field.pose."
       "orientation.y,field.pose.orientation.z,field.pose.orientation.w\n"
       "1403715274400000000,1,1403715274302142976,world,1,2,3,0,0,0,1\n"
       "1403715274500000000,2,1403715274402142976,world,1,2,3,0,0,0,1\n",
       TrajectoryFormat::kAuto,
       false,
       TrajectoryFormat::kAsl,
       2,
       1403715274302142976,
       {1, 2, 3},
       kIdentity},
      {"KittiWithoutTimes",
       "poses.txt",
       "1 0 0 1 0 1 0 2 0 0 1 3\n1 0 0 4 0 1 0 5 0 0 1 6\n1.000001 0 0 7 0 1 0 8 0 0 1 9\n",
       TrajectoryFormat::kAuto,
       false,
       TrajectoryFormat::kKitti,
       3,
       0,
       {1, 2, 3},
       kIdentity},
      {"SortOptIn",
       "t.txt",
       "2.0 4 5 6 0 0 0 1\n1.0 1 2 3 0 0 0 1\n3.0 7 8 9 0 0 0 1\n",
       TrajectoryFormat::kAuto,
       true,
       TrajectoryFormat::kTum,
       3,
       1'000'000'000,
       {1, 2, 3},
       kIdentity},
  };
  return cases;
}

class TrajectoryReaderAccepts : public ::testing::TestWithParam<Accepted> {};

TEST_P(TrajectoryReaderAccepts, Variant) {
  const Accepted& c = GetParam();
  const std::string dir = testing::MakeTempDir();
  const std::string path = dir + "/" + c.file_name;
  std::ofstream(path, std::ios::binary) << c.body;
  TrajectoryReadOptions options;
  options.format = c.forced;
  options.sort = c.sort;
  const LoadedTrajectory t = ReadTrajectory(path, options);
  EXPECT_EQ(t.report.format, c.expected_format) << t.report.layout;
  ASSERT_EQ(t.poses.size(), c.expected_poses) << t.report.layout;
  EXPECT_EQ(t.poses[0].t_ns, c.t0_ns);
  EXPECT_TRUE(t.poses[0].T_W_B.p.isApprox(c.p0, 1e-12)) << t.poses[0].T_W_B.p.transpose();
  const Eigen::Quaterniond& q = t.poses[0].T_W_B.q;
  EXPECT_NEAR(
      std::abs(q.coeffs().dot(
          Eigen::Quaterniond(c.q0_wxyz[0], c.q0_wxyz[1], c.q0_wxyz[2], c.q0_wxyz[3]).coeffs())),
      1.0, 1e-9);
  EXPECT_NEAR(q.norm(), 1.0, 1e-12);
  EXPECT_EQ(t.report.duplicates_dropped, c.expected_duplicates);
  EXPECT_EQ(t.report.first_duplicate_line, c.expected_first_duplicate_line);
  EXPECT_EQ(t.report.has_velocity, c.expected_velocity);
  for (size_t i = 1; i < t.poses.size(); ++i) EXPECT_LT(t.poses[i - 1].t_ns, t.poses[i].t_ns);
  EXPECT_FALSE(t.report.layout.empty());
}

INSTANTIATE_TEST_SUITE_P(Variants, TrajectoryReaderAccepts, ::testing::ValuesIn(AcceptedCases()),
                         [](const auto& test_info) { return std::string(test_info.param.name); });

TEST(TrajectoryReader, ReportsWhatWasFixed) {
  const std::string dir = testing::MakeTempDir();
  std::ofstream(dir + "/t.txt") << "\xEF\xBB\xBF"
                                   "1.0 1 2 3 0 0 0 1\r\n2.0 1 2 3 0 0 0 1\r\n2.0 1 2 3 0 0 0 1\r\n"
                                   "1.5 0 0 0 0.707 0 0 0.707\r\n";
  TrajectoryReadOptions options;
  options.sort = true;
  const LoadedTrajectory t = ReadTrajectory(dir + "/t.txt", options);
  ASSERT_EQ(t.poses.size(), 3u);
  EXPECT_EQ(t.poses[1].t_ns, 1'500'000'000);
  EXPECT_TRUE(t.report.had_bom);
  EXPECT_TRUE(t.report.had_crlf);
  EXPECT_TRUE(t.report.sorted);
  EXPECT_EQ(t.report.rows_out_of_order, 1u);
  EXPECT_EQ(t.report.first_out_of_order_line, 4);
  EXPECT_EQ(t.report.duplicates_dropped, 1u);
  EXPECT_EQ(t.report.first_duplicate_line, 3);
  EXPECT_EQ(t.report.quaternions_normalised, 1u);
  EXPECT_NEAR(t.report.max_quaternion_norm_error, 1.0 - std::sqrt(2 * 0.707 * 0.707), 1e-12);
  const std::string fixes = DescribeRowFixes(t.report);
  EXPECT_NE(fixes.find("1 row with a repeated timestamp dropped"), std::string::npos) << fixes;
  EXPECT_NE(fixes.find("t.txt:3"), std::string::npos) << fixes;
  EXPECT_NE(fixes.find("sorted"), std::string::npos) << fixes;
}

TEST(TrajectoryReader, KittiTimesFileGivesStamps) {
  const std::string dir = testing::MakeTempDir();
  std::ofstream(dir + "/poses.txt") << "1 0 0 1 0 1 0 2 0 0 1 3\n0 -1 0 4 1 0 0 5 0 0 1 6\n";
  std::ofstream(dir + "/times.txt") << "0.000000e+00\n1.036060e-01\n";
  TrajectoryReadOptions options;
  options.times_path = dir + "/times.txt";
  const LoadedTrajectory t = ReadTrajectory(dir + "/poses.txt", options);
  EXPECT_TRUE(t.report.has_stamps);
  ASSERT_EQ(t.poses.size(), 2u);
  EXPECT_EQ(t.poses[1].t_ns, 103'606'000);
  // Row 2: a rotation of +90 deg about z.
  EXPECT_NEAR(t.poses[1].T_W_B.q.angularDistance(
                  Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()))),
              0.0, 1e-12);
  const LoadedTrajectory index = ReadTrajectory(dir + "/poses.txt");
  EXPECT_FALSE(index.report.has_stamps);
  EXPECT_EQ(index.poses[1].t_ns, kNsPerSecond);
}

struct Refused {
  const char* name;
  const char* file_name;
  std::string body;
  TrajectoryFormat forced = TrajectoryFormat::kAuto;
  std::vector<std::string> must_contain;  // file:line, field, message
  bool refuse_duplicates = false;
};

std::vector<Refused> RefusedCases() {
  return {
      {"TumSevenFields",
       "t.txt",
       "1.0 0 0 0 0 0 0 1\n2.0 0 0 0 0 0 0\n",
       TrajectoryFormat::kAuto,
       {"t.txt:2", "field 'qw'", "expected 8 fields"}},
      {"TumNotANumber",
       "t.txt",
       "1.0 0 0 0 0 0 0 1\n2.0 1 0 zero 0 0 0 1\n",
       TrajectoryFormat::kAuto,
       {"t.txt:2: field 'tz': 'zero' is not a number"}},
      {"TumNan",
       "t.txt",
       "1.0 nan 0 0 0 0 0 1\n",
       TrajectoryFormat::kAuto,
       {"t.txt:1: field 'tx'", "not finite"}},
      {"TumInf",
       "t.txt",
       "1.0 0 0 0 0 0 0 1\n2.0 0 inf 0 0 0 0 1\n",
       TrajectoryFormat::kAuto,
       {"t.txt:2: field 'ty'", "not finite"}},
      {"TumOutOfOrder",
       "t.txt",
       "2.0 0 0 0 0 0 0 1\n1.0 1 0 0 0 0 0 1\n",
       TrajectoryFormat::kAuto,
       {"t.txt:2: field 'timestamp'", "earlier than the previous row", "--sort"}},
      {"TumNotARotation",
       "t.txt",
       "1.0 0 0 0 0 0 0 0.5\n",
       TrajectoryFormat::kAuto,
       {"t.txt:1: field 'qw'", "not unit length"}},
      {"TumZeroQuaternion",
       "t.txt",
       "1.0 0 0 0 0 0 0 0\n",
       TrajectoryFormat::kAuto,
       {"t.txt:1", "not unit length"}},
      {"TumBadStamp",
       "t.txt",
       "-1.0 0 0 0 0 0 0 1\n",
       TrajectoryFormat::kAuto,
       {"t.txt:1: field 'timestamp'", "not a non-negative time"}},
      {"EmptyFile",
       "t.txt",
       "# only a comment\n\n",
       TrajectoryFormat::kAuto,
       {"t.txt", "no data rows"}},
      {"NineWhitespaceFields",
       "t.txt",
       "1 2 3 4 5 6 7 8 9\n",
       TrajectoryFormat::kAuto,
       {"t.txt:1", "cannot tell the format from 9 whitespace-separated fields",
        "--gt-format/--est-format (eval) or --in-format (convert)"}},
      {"FiveCommaFields",
       "t.csv",
       "1,2,3,4,5\n",
       TrajectoryFormat::kAuto,
       {"t.csv:1", "cannot tell the format from 5 comma-separated fields"}},
      {"KittiNotARotation",
       "k.txt",
       "2 0 0 1 0 1 0 2 0 0 1 3\n",
       TrajectoryFormat::kAuto,
       {"k.txt:1: field 'r11'", "not a rotation"}},
      {"KittiShortRow",
       "k.txt",
       "1 0 0 1 0 1 0 2 0 0 1 3\n1 0 0 1 0 1 0 2 0 0 1\n",
       TrajectoryFormat::kAuto,
       {"k.txt:2: field 'tz'", "expected 12 fields"}},
      {"KittiBadNumber",
       "k.txt",
       "1 0 0 1 0 1 0 x 0 0 1 3\n",
       TrajectoryFormat::kKitti,
       {"k.txt:1: field 'ty'", "'x' is not a finite number"}},
      {"EurocShortRow",
       "d.csv",
       "100,1,2,3,1,0,0,0\n200,1,2,3,1,0,0\n",
       TrajectoryFormat::kAuto,
       {"d.csv:2: field 'q_z'", "expected 8 fields, found 7"}},
      {"EurocFractionalNanoseconds",
       "d.csv",
       "1e2x,1,2,3,1,0,0,0\n",
       TrajectoryFormat::kEuroc,
       {"d.csv:1: field 'timestamp [ns]'", "not a non-negative time in nanoseconds"}},
      {"AslForcedWithoutHeader",
       "d.csv",
       "100,1,2,3,1,0,0,0\n",
       TrajectoryFormat::kAsl,
       {"d.csv", "no header line names the columns"}},
      {"AslHeaderWithoutQuaternion",
       "d.csv",
       "#timestamp,x,y,z,a,b,c,d\n100,1,2,3,1,0,0,0\n",
       TrajectoryFormat::kAsl,
       {"d.csv", "does not name", "quaternion"}},
      {"KimeraShortRow",
       "traj_vio.csv",
       "#timestamp,x,y,z,qw,qx,qy,qz,vx,vy,vz\n100,1,2,3,1,0,0,0,0,0,0\n200,1,2,3,1,0,0,0,0\n",
       TrajectoryFormat::kAuto,
       {"traj_vio.csv:3: field 'vy'", "expected 11 fields, found 9"}},
      {"KimeraEmptyField",
       "traj_vio.csv",
       "#timestamp,x,y,z,qw,qx,qy,qz\n100,1,,3,1,0,0,0\n",
       TrajectoryFormat::kAuto,
       {"traj_vio.csv:2: field 'y'", "empty value"}},
      {"DuplicatesRefusedWhenAsked",
       "t.txt",
       "1.0 0 0 0 0 0 0 1\n1.0 1 0 0 0 0 0 1\n",
       TrajectoryFormat::kTum,
       {"t.txt:2: field 'timestamp'", "duplicate timestamp"},
       true},
  };
}

class TrajectoryReaderRefuses : public ::testing::TestWithParam<Refused> {};

TEST_P(TrajectoryReaderRefuses, Case) {
  const Refused& c = GetParam();
  const std::string dir = testing::MakeTempDir();
  const std::string path = dir + "/" + c.file_name;
  std::ofstream(path, std::ios::binary) << c.body;
  TrajectoryReadOptions options;
  options.format = c.forced;
  options.refuse_duplicates = c.refuse_duplicates;
  try {
    ReadTrajectory(path, options);
    FAIL() << "accepted " << c.name;
  } catch (const InputError& e) {
    const std::string message = e.what();
    for (const auto& part : c.must_contain)
      EXPECT_NE(message.find(part), std::string::npos) << "'" << part << "' not in: " << message;
  }
}

INSTANTIATE_TEST_SUITE_P(Cases, TrajectoryReaderRefuses, ::testing::ValuesIn(RefusedCases()),
                         [](const auto& test_info) { return std::string(test_info.param.name); });

TEST(TrajectoryReader, MissingFileAndBadTimesFile) {
  const std::string dir = testing::MakeTempDir();
  EXPECT_THROW(ReadTrajectory(dir + "/none.txt"), InputError);
  std::ofstream(dir + "/poses.txt") << "1 0 0 1 0 1 0 2 0 0 1 3\n1 0 0 1 0 1 0 2 0 0 1 4\n";
  std::ofstream(dir + "/times.txt") << "0.0\n";
  TrajectoryReadOptions options;
  options.times_path = dir + "/times.txt";
  try {
    ReadTrajectory(dir + "/poses.txt", options);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("times.txt: has 1 stamps but"), std::string::npos)
        << e.what();
  }
  std::ofstream(dir + "/times.txt") << "0.0\n0.0\n";
  try {
    ReadTrajectory(dir + "/poses.txt", options);  // repeated stamps keep the first pose
  } catch (const InputError& e) {
    FAIL() << e.what();
  }
  std::ofstream(dir + "/t.txt") << "1.0 0 0 0 0 0 0 1\n";
  try {
    ReadTrajectory(dir + "/t.txt", options);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("only used with KITTI"), std::string::npos) << e.what();
  }
}

TEST(TrajectoryWriters, TumKittiTumRoundTripWithTimes) {
  const std::string dir = testing::MakeTempDir();
  std::vector<StampedPose> poses;
  for (int i = 0; i < 5; ++i) {
    const Eigen::Quaterniond q =
        Eigen::Quaterniond(Eigen::AngleAxisd(0.3 * i - 0.5, Eigen::Vector3d(1, 2, 3).normalized()));
    poses.push_back(
        {1403715274302142976 + i * 5'000'123, Pose(q, Eigen::Vector3d(i, -2.5 * i, 0.1))});
  }
  std::ofstream(dir + "/k.txt") << KittiPosesText(poses);
  std::ofstream(dir + "/times.txt") << KittiTimesText(poses);
  TrajectoryReadOptions options;
  options.times_path = dir + "/times.txt";
  const LoadedTrajectory kitti = ReadTrajectory(dir + "/k.txt", options);
  ASSERT_EQ(kitti.report.format, TrajectoryFormat::kKitti);
  WriteTumTrajectory(kitti.Poses(), dir + "/back.txt");
  const auto back = ReadTumTrajectory(dir + "/back.txt");
  ASSERT_EQ(back.size(), poses.size());
  for (size_t i = 0; i < poses.size(); ++i) {
    EXPECT_EQ(back[i].t_ns, poses[i].t_ns);
    EXPECT_LT((back[i].T_W_B.p - poses[i].T_W_B.p).norm(), 1e-11);
    EXPECT_LT(back[i].T_W_B.q.angularDistance(poses[i].T_W_B.q), 1e-11);
  }
}

// ---- the real EuRoC V1_01 ground truth, as TUM and as the ASL CSV ----

TEST(TrajectoryReaderRealFiles, EurocGroundTruthInBothFormatsAgrees) {
  if (!testing::HasSharedData()) GTEST_SKIP() << "shared data absent: " << testing::SharedDataDir();
  const std::string root = testing::SharedDataDir() + "/euroc_v1_01_easy";
  const LoadedTrajectory tum = ReadTrajectory(root + "/groundtruth_full_tum.txt");
  const LoadedTrajectory csv = ReadTrajectory(root + "/mav0/state_groundtruth_estimate0/data.csv");
  EXPECT_EQ(tum.report.format, TrajectoryFormat::kTum) << tum.report.layout;
  EXPECT_EQ(csv.report.format, TrajectoryFormat::kEuroc) << csv.report.layout;
  EXPECT_TRUE(csv.report.has_velocity);
  EXPECT_TRUE(csv.report.has_biases);
  EXPECT_EQ(tum.poses.size(), 28712u);
  EXPECT_EQ(csv.poses.size(), 999u);
  // The CSV covers the first 5 s; TUM's stamps have 10 us resolution.
  for (size_t i = 0; i < csv.poses.size(); i += 97) {
    EXPECT_NEAR(NsToSeconds(tum.poses[i].t_ns - csv.poses[i].t_ns), 0.0, 1e-5) << i;
    EXPECT_LT((tum.poses[i].T_W_B.p - csv.poses[i].T_W_B.p).norm(), 1e-9) << i;
    EXPECT_LT(tum.poses[i].T_W_B.q.angularDistance(csv.poses[i].T_W_B.q), 1e-9) << i;
  }
  // Forced formats read the same files the same way.
  TrajectoryReadOptions forced;
  forced.format = TrajectoryFormat::kTum;
  EXPECT_EQ(ReadTrajectory(root + "/groundtruth_full_tum.txt", forced).poses.size(), 28712u);
  forced.format = TrajectoryFormat::kAsl;
  EXPECT_EQ(
      ReadTrajectory(root + "/mav0/state_groundtruth_estimate0/data.csv", forced).poses.size(),
      999u);
  // ... and a KITTI round trip of the real file keeps every pose.
  const std::string dir = testing::MakeTempDir();
  const auto poses = tum.Poses();
  std::ofstream(dir + "/k.txt") << KittiPosesText(poses);
  std::ofstream(dir + "/times.txt") << KittiTimesText(poses);
  TrajectoryReadOptions kitti_options;
  kitti_options.times_path = dir + "/times.txt";
  const LoadedTrajectory kitti = ReadTrajectory(dir + "/k.txt", kitti_options);
  ASSERT_EQ(kitti.poses.size(), poses.size());
  EXPECT_EQ(kitti.poses.back().t_ns, poses.back().t_ns);
  EXPECT_LT((kitti.poses.back().T_W_B.p - poses.back().T_W_B.p).norm(), 1e-12);
}

}  // namespace
}  // namespace mavloc
