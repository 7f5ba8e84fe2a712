// `mavloc log info|export|import` and `compare --reference LOG:TOPIC` on the real logs of
// ../shared/data: PX4's sample.ulg (pyulog's counts) and robot_localization's ROS bags (IMU round
// trip through an ASL folder: counts, stamps and values as the bag holds them). Bad input (a
// missing topic, a file that is no log, nothing to import) gives exit code 2, one line naming the
// file and topic, and no output folder.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "datasets/io/euroc_io.h"
#include "datasets/io/log_reader.h"
#include "datasets/io/tum_io.h"
#include "tests/test_support.h"

namespace fs = std::filesystem;

namespace mavloc {
namespace {

using testing::CliPath;
using testing::MakeTempDir;
using testing::RunCommand;

std::string Ulog() { return testing::SharedDataDir() + "/px4_ulog/sample.ulg"; }
std::string Bag(const char* name) { return testing::SharedDataDir() + "/ros_bags/" + name; }

TEST(CliLog, InfoListsUlogTopicsWithPyulogCounts) {
  REQUIRE_SHARED_DATA();
  const std::string dir = MakeTempDir();
  const auto r = RunCommand(CliPath() + " log info " + Ulog() + " --json " + dir + "/info.json");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("PX4 ULog"), std::string::npos) << r.output;
  std::ifstream in(dir + "/info.json");
  const auto j = nlohmann::json::parse(in);
  // pyulog's sample_info.txt: sensor_combined 17070, vehicle_attitude 6461, vehicle_local_position
  // 678 data points.
  std::map<std::string, uint64_t> counts;
  for (const auto& t : j["topics"]) counts[t["topic"].get<std::string>()] = t["messages"];
  EXPECT_EQ(counts["sensor_combined"], 17070u);
  EXPECT_EQ(counts["vehicle_attitude"], 6461u);
  EXPECT_EQ(counts["vehicle_local_position"], 678u);
  EXPECT_EQ(j["format"], "ulog");
}

TEST(CliLog, BagImuRoundTripThroughAslFolder) {
  REQUIRE_SHARED_DATA();
  for (const char* name : {"test1.bag", "test2.bag"}) {
    SCOPED_TRACE(name);
    const std::string dir = MakeTempDir();
    const auto info = RunCommand(CliPath() + " log info " + Bag(name));
    ASSERT_EQ(info.exit_code, 0) << info.output;
    EXPECT_NE(info.output.find("/imu/data"), std::string::npos) << info.output;
    EXPECT_NE(info.output.find("sensor_msgs/Imu"), std::string::npos) << info.output;
    const auto r = RunCommand(CliPath() + " log import " + Bag(name) + " --imu /imu/data --out " +
                              dir + "/ds");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const std::vector<ImuSample> direct = ReadLogImu(Bag(name), "/imu/data");
    const Dataset dataset = ReadEurocDataset(dir + "/ds");
    ASSERT_EQ(dataset.imu.samples.size(), direct.size());
    ASSERT_GT(direct.size(), 1000u);
    for (size_t i = 0; i < direct.size(); ++i) {
      ASSERT_EQ(dataset.imu.samples[i].t_ns, direct[i].t_ns) << i;
      ASSERT_LT((dataset.imu.samples[i].gyro_rad_s - direct[i].gyro_rad_s).norm(), 1e-9) << i;
      ASSERT_LT((dataset.imu.samples[i].accel_m_s2 - direct[i].accel_m_s2).norm(), 1e-9) << i;
    }
    // Units: a ground robot's accelerometer reads about g (m/s^2, not g units or mg).
    double mean_norm = 0.0;
    for (const auto& s : direct) mean_norm += s.accel_m_s2.norm() / direct.size();
    EXPECT_GT(mean_norm, 9.0);
    EXPECT_LT(mean_norm, 10.6);
    EXPECT_NE(r.output.find("median rate"), std::string::npos) << r.output;
  }
}

TEST(CliLog, UlogImportAndExport) {
  REQUIRE_SHARED_DATA();
  const std::string dir = MakeTempDir();
  const auto r = RunCommand(CliPath() + " log import " + Ulog() + " --imu sensor_combined --out " +
                            dir + "/px4");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const Dataset dataset = ReadEurocDataset(dir + "/px4");
  EXPECT_EQ(dataset.imu.samples.size(), 17070u);
  // mavloc's B is FLU: before take-off the accelerometer reads about +g on z.
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (int i = 0; i < 200; ++i) mean += dataset.imu.samples[i].accel_m_s2 / 200.0;
  EXPECT_GT(mean.z(), 9.0) << mean.transpose();
  EXPECT_LT(std::abs(mean.x()) + std::abs(mean.y()), 2.0) << mean.transpose();

  const auto e = RunCommand(CliPath() + " log export " + Ulog() + ":vehicle_attitude --out " + dir +
                            "/attitude.tum");
  ASSERT_EQ(e.exit_code, 0) << e.output;
  EXPECT_EQ(ReadTumTrajectory(dir + "/attitude.tum").size(), 6461u);
}

TEST(CliLog, CompareAgainstALogTopic) {
  REQUIRE_SHARED_DATA();
  const std::string dir = MakeTempDir();
  ASSERT_EQ(RunCommand(CliPath() + " log import " + Ulog() + " --imu sensor_combined --out " + dir +
                       "/px4")
                .exit_code,
            0);
  const auto r = RunCommand(CliPath() + " compare --dataset " + dir +
                            "/px4 --estimators gravity-ekf --reference " + Ulog() +
                            ":vehicle_attitude --report " + dir + "/report");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::ifstream in(dir + "/report/report.json");
  const auto j = nlohmann::json::parse(in);
  EXPECT_EQ(j["details"]["reference"]["kind"], "log_topic");
  const std::string text = j.dump();
  EXPECT_NE(text.find("roll"), std::string::npos);
  EXPECT_NE(text.find("pitch"), std::string::npos);
}

TEST(CliLog, EvalTakesLogTopicsDirectly) {
  REQUIRE_SHARED_DATA();
  // TagSLAM's reference.bag publishes the same rig pose twice: as nav_msgs/Odometry and as the
  // map -> rig edge of /tf. Evaluating one against the other, straight from the (whole-file bzip2)
  // bag, must give zero.
  const std::string bag = testing::SharedDataDir() + "/tagslam/test_21/reference.bag.bz2";
  const std::string dir = MakeTempDir();
  const auto r = RunCommand(CliPath() + " eval --gt " + bag + ":/tagslam/odom/body_rig --est " +
                            bag + ":/tf:map:rig --align none --json " + dir + "/eval.json");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("430 of 430 poses associated"), std::string::npos) << r.output;
  std::ifstream in(dir + "/eval.json");
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("nav_msgs/Odometry"), std::string::npos);
  // A topic without a position cannot be an eval input.
  const auto bad = RunCommand(CliPath() + " eval --gt " + Ulog() + ":vehicle_attitude --est " +
                              Ulog() + ":vehicle_attitude");
  EXPECT_EQ(bad.exit_code, 2) << bad.output;
  EXPECT_NE(bad.output.find("carries no position"), std::string::npos) << bad.output;
}

TEST(CliLog, BadInputNamesFileAndTopicAndWritesNothing) {
  REQUIRE_SHARED_DATA();
  const std::string dir = MakeTempDir();
  {
    const auto r = RunCommand(CliPath() + " log import " + Ulog() + " --imu no_such_topic --out " +
                              dir + "/a");
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find("sample.ulg"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("no_such_topic"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(dir + "/a"));
  }
  {
    const auto r = RunCommand(CliPath() + " log import " + Bag("test2.bag") +
                              " --imu /no/such/topic --out " + dir + "/b");
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find("/no/such/topic"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(dir + "/b"));
  }
  {
    std::ofstream(dir + "/not_a_log.bag") << "hello\n";
    const auto r = RunCommand(CliPath() + " log info " + dir + "/not_a_log.bag");
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find("not_a_log.bag"), std::string::npos) << r.output;
  }
  {
    const auto r = RunCommand(CliPath() + " log import " + Ulog() + " --out " + dir + "/c");
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find("nothing to import"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(dir + "/c"));
  }
  {
    // A ground-truth stream needs full poses: vehicle_attitude has no position.
    const auto r = RunCommand(CliPath() + " log import " + Ulog() +
                              " --gt vehicle_attitude --out " + dir + "/d");
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find("vehicle_attitude"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(dir + "/d"));
  }
  for (const auto& entry : fs::directory_iterator(dir))
    EXPECT_EQ(entry.path().string().find(".images-"), std::string::npos) << entry.path();
}

}  // namespace
}  // namespace mavloc
