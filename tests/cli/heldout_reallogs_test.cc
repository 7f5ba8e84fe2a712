// Bad input on real logs from the independent ("held-out") catalogue, table-driven: each case makes
// a mutated copy of real data from ../shared/data in a temp folder (EuRoC's imu_april log with
// yac's config.yaml, the same calibration as Kalibr's camchain.yaml/imu.yaml, EuRoC's cam0
// sensor.yaml, TagSLAM's test_2, the ROS bag test2.bag) and runs the real CLI on it. A refused case
// must exit with code 2, print one line on stderr naming the file (and the line where it has lines)
// and the field, and leave no output. A second table holds real-world variants that must keep
// loading (a UTF-8 BOM before a corner file's header; `log info` escapes control bytes in topic
// names).
#include <gtest/gtest.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include "datasets/io/rosbag/ros_messages.h"
#include "tests/test_support.h"

namespace mavloc {
namespace {

namespace fs = std::filesystem;
using testing::CliPath;
using testing::MakeTempDir;
using testing::RunCommand;
using testing::SharedDataDir;

// The first corner file of cam0 in EuRoC's imu_april log (the copies keep the first 20 per camera).
constexpr const char* kFirstCorners = "1404733405732800000.csv";

// Replaces the first occurrence of `from` in `file` by `to` (the case fails when it is absent).
void Substitute(const fs::path& file, const std::string& from, const std::string& to) {
  fs::permissions(file, fs::perms::owner_write, fs::perm_options::add);
  std::string text = testing::ReadFileBytes(file);
  const auto at = text.find(from);
  ASSERT_NE(at, std::string::npos) << "case substitutes missing text '" << from << "' in " << file;
  text.replace(at, from.size(), to);
  testing::WriteFileBytes(file, text);
}

// Kalibr's camchain.yaml and imu.yaml holding EuRoC's calibration (the values of
// euroc_v1_01_easy/mav0/cam*/sensor.yaml and imu0/sensor.yaml, as Kalibr writes them).
constexpr const char* kCamchain = R"(cam0:
  camera_model: pinhole
  intrinsics: [458.654, 457.296, 367.215, 248.375]
  distortion_model: radtan
  distortion_coeffs: [-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05]
  resolution: [752, 480]
cam1:
  camera_model: pinhole
  intrinsics: [457.587, 456.134, 379.999, 255.238]
  distortion_model: radtan
  distortion_coeffs: [-0.28368365, 0.07451284, -0.00010473, -3.555e-05]
  resolution: [752, 480]
)";
constexpr const char* kImuYaml = R"(rostopic: /imu0
update_rate: 200.0
accelerometer_noise_density: 2.0e-3
accelerometer_random_walk: 3.0e-3
gyroscope_noise_density: 1.6968e-04
gyroscope_random_walk: 1.9393e-05
)";

// `dir`/a: 5 s of imu_april's IMU, its first 20 corner files per camera, config.yaml, the
// target.yaml of euroc_cam_april, camchain.yaml and imu.yaml; `dir`/e: EuRoC's cam0 sensor.yaml.
void MakeAprilCopy(const fs::path& dir) {
  const fs::path log = SharedDataDir() + "/euroc_imu_april";
  const fs::path a = dir / "a";
  for (const char* camera : {"cam0", "cam1"}) {
    std::vector<fs::path> files;
    for (const auto& entry : fs::directory_iterator(log / camera)) files.push_back(entry.path());
    std::sort(files.begin(), files.end());
    fs::create_directories(a / camera);
    for (size_t i = 0; i < 20 && i < files.size(); ++i)
      fs::copy_file(files[i], a / camera / files[i].filename());
  }
  std::ifstream imu(log / "imu0.csv");
  std::ofstream imu_copy(a / "imu0.csv");
  std::string line;
  for (int i = 0; i < 1001 && std::getline(imu, line); ++i) imu_copy << line << "\n";
  fs::copy_file(log / "config.yaml", a / "config.yaml");
  fs::copy_file(SharedDataDir() + "/euroc_cam_april/target.yaml", a / "target.yaml");
  testing::WriteFileBytes(a / "camchain.yaml", kCamchain);
  testing::WriteFileBytes(a / "imu.yaml", kImuYaml);
  fs::create_directories(dir / "e/mav0/cam0");
  fs::copy_file(SharedDataDir() + "/euroc_v1_01_easy/mav0/cam0/sensor.yaml",
                dir / "e/mav0/cam0/sensor.yaml");
  for (const auto& entry : fs::recursive_directory_iterator(dir))
    fs::permissions(entry.path(), fs::perms::owner_write, fs::perm_options::add);
}

void MakeTagslamCopy(const fs::path& dir) {
  fs::copy(SharedDataDir() + "/tagslam/test_2", dir / "t", fs::copy_options::recursive);
  fs::permissions(dir / "t", fs::perms::owner_write, fs::perm_options::add);
  for (const auto& entry : fs::recursive_directory_iterator(dir / "t"))
    fs::permissions(entry.path(), fs::perms::owner_write, fs::perm_options::add);
}

// test2.bag rewritten with uncompressed chunks by rosbag::Bag; `edit` may change the topic of a
// message (returning the new name) or, for /imu/data, the message itself.
void WriteBagCopy(
    const fs::path& out,
    const std::function<void(uint64_t index, std::string* topic, ros1::ImuMsg* imu)>& edit) {
  rosbag::Bag in(SharedDataDir() + "/ros_bags/test2.bag", rosbag::bagmode::Read);
  rosbag::Bag bag(out.string(), rosbag::bagmode::Write);
  uint64_t imu_index = 0;
  for (const rosbag::MessageInstance& message : rosbag::View(in)) {
    std::string topic = message.getTopic();
    if (topic == "/imu/data") {
      const auto original = message.instantiate<ros1::ImuMsg>();
      ros1::ImuMsg imu = *original;
      edit(imu_index++, &topic, &imu);
      bag.write(topic, message.getTime(), imu);
    } else {
      bag.write(topic, message.getTime(), message);
    }
  }
  bag.close();
}

// Breaks the headers of the message records inside the chunks from the 800th on (both topics):
// their "op=" field loses its '=', which ros::Header::parse (libcpp_common) reports on stderr
// itself before rosbag throws. The records outside the chunks (which mavloc walks first) are
// intact.
void BreakMessageRecordHeaders(const fs::path& bag) {
  std::string bytes = testing::ReadFileBytes(bag);
  const std::string op_field("\x04\x00\x00\x00op=\x02", 8);
  size_t at = 0;
  for (int n = 0; (at = bytes.find(op_field, at + 1)) != std::string::npos; ++n) {
    if (n >= 800) bytes[at + 6] = 'X';
  }
  testing::WriteFileBytes(bag, bytes);
}

struct Case {
  std::string name;
  std::function<void(const fs::path& dir)> mutate;  // applied to the copy in `dir`
  std::string command;                              // run in `dir`, mavloc prepended
  std::vector<std::string> expected;                // substrings of the one stderr line
};

const std::string kImport =
    "import-aprilgrid --imu a/imu0.csv --config a/config.yaml --corners cam0=a/cam0 --corners "
    "cam1=a/cam1 --out out";
const std::string kTagslam = "import-tagslam t --out out --camera cam0 --no-trajectories";
const std::string kBagImport = "log import f.bag --imu /imu/data --out out";

bool HasControlBytes(const std::string& text) {
  return std::any_of(text.begin(), text.end(), [](char c) {
    const auto u = static_cast<unsigned char>(c);
    return (u < 0x20 && c != '\n') || u == 0x7f;
  });
}

std::vector<Case> RefusedCases() {
  auto config = [](const std::string& from, const std::string& to) {
    return [from, to](const fs::path& dir) { Substitute(dir / "a/config.yaml", from, to); };
  };
  return {
      // Calibration readers.
      {"yac_focal_length",
       config("proj_params: [458.654", "proj_params: [1e308"),
       kImport,
       {"a/config.yaml:53: field 'cam0.proj_params'", "fu = 1e+308"}},
      {"yac_principal_point",
       config("367.215", "1e308"),
       kImport,
       {"a/config.yaml:53: field 'cam0.proj_params'", "cu = 1e+308"}},
      {"yac_distortion",
       config("dist_params: [-0.28340811", "dist_params: [1e308"),
       kImport,
       {"a/config.yaml:54: field 'cam0.dist_params'", "1e+308"}},
      {"yac_noise_density",
       config("sigma_g_c: 1.6968e-04", "sigma_g_c: 1e308"),
       kImport,
       {"a/config.yaml:44: field 'sigma_g_c'", "1e+308"}},
      {"yac_imu_rate",
       config("  rate: 200.0", "  rate: 1e308"),
       kImport,
       {"a/config.yaml:42: field 'rate'", "1e+308"}},
      {"kalibr_imu_noise_density",
       [](const fs::path& dir) {
         Substitute(dir / "a/imu.yaml", "accelerometer_noise_density: 2.0e-3",
                    "accelerometer_noise_density: 1e308");
       },
       kImport + " --imu-noise a/imu.yaml",
       {"a/imu.yaml:3: field 'accelerometer_noise_density'", "1e+308"}},
      {"kalibr_camchain_focal_length",
       [](const fs::path& dir) { Substitute(dir / "a/camchain.yaml", "458.654", "1e308"); },
       kImport + " --intrinsics a/camchain.yaml",
       {"a/camchain.yaml:3: field 'cam0.intrinsics'", "fu = 1e+308"}},
      {"kalibr_camchain_distortion",
       [](const fs::path& dir) { Substitute(dir / "a/camchain.yaml", "-0.28340811", "1e308"); },
       kImport + " --intrinsics a/camchain.yaml",
       {"a/camchain.yaml:5: field 'cam0.distortion_coeffs'", "1e+308"}},
      {"euroc_camera_rate_negative",
       [](const fs::path& dir) {
         Substitute(dir / "e/mav0/cam0/sensor.yaml", "rate_hz: 20", "rate_hz: -20");
       },
       kImport + " --intrinsics cam0=e/mav0/cam0/sensor.yaml",
       {"e/mav0/cam0/sensor.yaml:16: field 'rate_hz'", "-20"}},
      {"tagslam_camera_focal_length",
       [](const fs::path& dir) { Substitute(dir / "t/cameras.yaml", "470.338", "1e308"); },
       kTagslam,
       {"t/cameras.yaml:3: field 'intrinsics'", "fu = 1e+308"}},
      {"tagslam_camera_distortion",
       [](const fs::path& dir) { Substitute(dir / "t/cameras.yaml", "-0.0177484", "1e308"); },
       kTagslam,
       {"t/cameras.yaml:5: field 'distortion_coeffs'", "1e+308"}},
      {"tagslam_default_tag_size",
       [](const fs::path& dir) {
         Substitute(dir / "t/tagslam.yaml", "default_tag_size: 0.160", "default_tag_size: 1e308");
       },
       kTagslam,
       {"t/tagslam.yaml:16: field 'default_tag_size'", "1e+308"}},
      // The target's tag size, blamed on the YAML line that holds it.
      {"yac_target_tag_size",
       config("tag_size: 0.088 ", "tag_size: 1e308 "),
       kImport,
       {"a/config.yaml:37: field 'tag_size'", "1e+308"}},
      {"kalibr_target_tag_size",
       [](const fs::path& dir) {
         Substitute(dir / "a/target.yaml", "tag_size: 0.088", "tag_size: 1e308");
       },
       kImport + " --target a/target.yaml",
       {"a/target.yaml:4: field 'tag_size'", "1e+308"}},
      // A corner file named for a time beyond 2^62 ns.
      {"corner_file_beyond_2e62",
       [](const fs::path& dir) {
         const fs::path from = dir / "a/cam0" / kFirstCorners;
         const fs::path to = dir / "a/cam0/9000000000000000000.csv";
         std::string text = testing::ReadFileBytes(from);
         for (size_t at; (at = text.find("1404733405732800000")) != std::string::npos;)
           text.replace(at, 19, "9000000000000000000");
         testing::WriteFileBytes(to, text);
         fs::remove(from);
       },
       kImport,
       {"a/cam0/9000000000000000000.csv: field 'ts'", "beyond"}},
      // ROS bags.
      {"bag_gyro_1e300",
       [](const fs::path& dir) {
         WriteBagCopy(dir / "f.bag", [](uint64_t index, std::string*, ros1::ImuMsg* imu) {
           if (index == 10) imu->angular_velocity.y = 1e300;
         });
       },
       kBagImport,
       {"f.bag: topic /imu/data, message 10", "angular_velocity", "1e+300"}},
      {"bag_corrupt_record_in_chunk",
       [](const fs::path& dir) {
         WriteBagCopy(dir / "f.bag", [](uint64_t, std::string*, ros1::ImuMsg*) {});
         BreakMessageRecordHeaders(dir / "f.bag");
       },
       kBagImport,
       {"f.bag: topic /imu/data, message", "corrupt bag"}},
  };
}

class HeldoutRealLogs : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!testing::HasSharedData()) GTEST_SKIP() << "../shared/data is absent";
  }

  // A fresh copy of the inputs for one case.
  static fs::path CaseDir(const std::string& name) {
    const fs::path dir = fs::path(MakeTempDir()) / name;
    fs::create_directories(dir);
    MakeAprilCopy(dir);
    MakeTagslamCopy(dir);
    return dir;
  }
};

TEST_F(HeldoutRealLogs, UnmutatedCopiesLoad) {
  const fs::path dir = CaseDir("baseline");
  for (const std::string& command :
       {kImport,
        kImport + " --imu-noise a/imu.yaml --intrinsics a/camchain.yaml --target "
                  "a/target.yaml",
        kImport + " --intrinsics cam0=e/mav0/cam0/sensor.yaml", kTagslam}) {
    const testing::CliRun r = testing::RunCliIn(dir, command);
    EXPECT_EQ(r.exit_code, 0) << command << "\n" << r.out << r.err;
    fs::remove_all(dir / "out");
  }
  WriteBagCopy(dir / "f.bag", [](uint64_t, std::string*, ros1::ImuMsg*) {});
  const testing::CliRun r = testing::RunCliIn(dir, kBagImport);
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
}

TEST_F(HeldoutRealLogs, AbsurdValuesAreRefusedWithFileLineAndField) {
  for (const Case& c : RefusedCases()) {
    SCOPED_TRACE(c.name);
    const fs::path dir = CaseDir(c.name);
    c.mutate(dir);
    if (::testing::Test::HasFatalFailure()) continue;
    const testing::CliRun r = testing::RunCliIn(dir, c.command);
    EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_FALSE(HasControlBytes(r.err)) << r.err;
    EXPECT_EQ(r.err.find("internal error"), std::string::npos) << r.err;
    for (const std::string& expected : c.expected)
      EXPECT_NE(r.err.find(expected), std::string::npos) << "expected '" << expected << "' in\n"
                                                         << r.err;
    EXPECT_FALSE(fs::exists(dir / "out")) << "output left behind";
    for (const auto& entry : fs::directory_iterator(dir)) {
      const std::string name = entry.path().filename().string();
      EXPECT_EQ(name.find(".tmp-"), std::string::npos) << name;
      EXPECT_EQ(name.find(".old-"), std::string::npos) << name;
    }
  }
}

// A UTF-8 byte order mark before a corner file's header (as Windows editors write) is accepted,
// as in every other CSV reader.
TEST_F(HeldoutRealLogs, CornerFileWithByteOrderMarkLoads) {
  const fs::path dir = CaseDir("corner_bom");
  const fs::path file = dir / "a/cam0" / kFirstCorners;
  testing::WriteFileBytes(file, "\xEF\xBB\xBF" + testing::ReadFileBytes(file));
  const testing::CliRun r = testing::RunCliIn(dir, kImport);
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("cam0: 20 frames"), std::string::npos) << r.out;
  EXPECT_TRUE(fs::exists(dir / "out/mav0/tags0/data.csv"));
}

// `log info` prints topic names from the bag: control bytes (an ESC sequence) are escaped.
TEST_F(HeldoutRealLogs, LogInfoEscapesControlBytesInTopicNames) {
  const fs::path dir = fs::path(MakeTempDir()) / "topic_ctrl";
  fs::create_directories(dir);
  WriteBagCopy(dir / "f.bag",
               [](uint64_t, std::string* topic, ros1::ImuMsg*) { *topic = "/imu/da\x1b[31mta"; });
  const testing::CliRun r = testing::RunCliIn(dir, "log info f.bag");
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_FALSE(HasControlBytes(r.out)) << r.out;
  EXPECT_NE(r.out.find("/imu/da\\x1B[31mta"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("sensor_msgs/Imu"), std::string::npos) << r.out;
}

}  // namespace
}  // namespace mavloc
