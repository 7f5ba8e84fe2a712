// `mavloc convert`: TUM -> KITTI (+ times file) -> TUM gives back every stamp
// exactly and every pose to 1e-9; KITTI without times gets index stamps; the real EuRoC ground
// truth CSV converts to TUM; bad input exits 2 and writes nothing.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "tests/test_support.h"

namespace fs = std::filesystem;

namespace mavloc {
namespace {

using testing::CliPath;
using testing::RunCommand;

std::string Cli(const std::string& args) { return CliPath() + " " + args; }

struct Row {
  std::string stamp;
  std::vector<double> values;
};

// Data rows of a whitespace file (stamp text kept as written).
std::vector<Row> Rows(const std::string& path) {
  std::ifstream in(path);
  std::vector<Row> rows;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream s(line);
    Row r;
    s >> r.stamp;
    double v;
    while (s >> v) r.values.push_back(v);
    rows.push_back(r);
  }
  return rows;
}

TEST(EvalConvert, TumToKittiToTumRoundTripWithTimes) {
  const std::string dir = testing::MakeTempDir();
  std::ofstream(dir + "/in.txt")
      << "# timestamp tx ty tz qx qy qz qw\n"
         "1403715274.302142976 0.878612 2.142470 0.947262 -0.828459 -0.058956 -0.553641 0.060514\n"
         "1403715274.307142912 0.878658 2.142398 0.947252 -0.828433 -0.059051 -0.553664 0.060571\n"
         "1403715274.312143104 0.878704 2.142325 0.947241 -0.828406 -0.059145 -0.553687 0.060628\n";
  auto r = RunCommand(Cli("convert --in " + dir + "/in.txt --out " + dir +
                          "/k.txt --format kitti " + "--out-times " + dir + "/times.txt"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto kitti = Rows(dir + "/k.txt");
  ASSERT_EQ(kitti.size(), 3u);
  EXPECT_EQ(kitti[0].values.size(), 11u);  // 12 numbers: the first is read as `stamp`
  r = RunCommand(Cli("convert --in " + dir + "/k.txt --in-times " + dir + "/times.txt --out " +
                     dir + "/back.txt --format tum"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto in = Rows(dir + "/in.txt");
  const auto back = Rows(dir + "/back.txt");
  ASSERT_EQ(back.size(), in.size());
  for (size_t i = 0; i < in.size(); ++i) {
    EXPECT_EQ(back[i].stamp, in[i].stamp);
    ASSERT_EQ(back[i].values.size(), 7u);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(back[i].values[k], in[i].values[k], 1e-9);
    // q and -q are the same rotation.
    const double sign = back[i].values[6] * in[i].values[6] < 0 ? -1.0 : 1.0;
    for (int k = 3; k < 7; ++k) EXPECT_NEAR(sign * back[i].values[k], in[i].values[k], 2e-6);
  }
}

TEST(EvalConvert, KittiWithoutTimesGetsIndexStamps) {
  const std::string dir = testing::MakeTempDir();
  std::ofstream(dir + "/k.txt") << "1 0 0 1 0 1 0 2 0 0 1 3\n1 0 0 4 0 1 0 5 0 0 1 6\n";
  const auto r =
      RunCommand(Cli("convert --in " + dir + "/k.txt --out " + dir + "/t.txt --format tum"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("has no stamps"), std::string::npos) << r.output;
  const auto rows = Rows(dir + "/t.txt");
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[1].stamp, "1.000000000");
  EXPECT_DOUBLE_EQ(rows[1].values[0], 4.0);
}

TEST(EvalConvert, RealEurocCsvToTum) {
  if (!testing::HasSharedData()) GTEST_SKIP() << "shared data absent: " << testing::SharedDataDir();
  const std::string dir = testing::MakeTempDir();
  const std::string csv =
      testing::SharedDataDir() + "/euroc_v1_01_easy/mav0/state_groundtruth_estimate0/data.csv";
  const auto r = RunCommand(Cli("convert --in " + csv + " --out " + dir + "/gt.txt --format tum"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto rows = Rows(dir + "/gt.txt");
  ASSERT_EQ(rows.size(), 999u);
  EXPECT_EQ(rows[0].stamp, "1403715274.302142976");
  EXPECT_NEAR(rows[0].values[0], 0.878612, 1e-12);
  // qw last in TUM; the file's 6-decimal quaternion is normalised (|q| = 1 +- 2e-7).
  EXPECT_NEAR(rows[0].values[6], 0.060514, 1e-6);
}

TEST(EvalConvert, BadInputExitsTwoAndWritesNothing) {
  const std::string dir = testing::MakeTempDir();
  std::ofstream(dir + "/bad.txt") << "1.0 0 0 0 0 0 0 1\n0.5 0 0 0 0 0 0 1\n";
  auto r =
      RunCommand(Cli("convert --in " + dir + "/bad.txt --out " + dir + "/o.txt --format kitti"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("bad.txt:2: field 'timestamp'"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir + "/o.txt"));
  r = RunCommand(
      Cli("convert --in " + dir + "/bad.txt --out " + dir + "/o.txt --format kitti --sort"));
  EXPECT_EQ(r.exit_code, 0) << r.output;
  r = RunCommand(Cli("convert --in " + dir + "/bad.txt --out " + dir + "/o2.txt --format g2o"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_FALSE(fs::exists(dir + "/o2.txt"));
}

}  // namespace
}  // namespace mavloc
