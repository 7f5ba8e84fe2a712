// Error lines stay readable whatever the input holds: a trajectory file
// with a 2 MB field or with binary garbage gives exit code 2 and one short line on stderr naming
// the file, with control bytes escaped, never echoed raw. Messages say what the user needs, table-
// driven: a NUL byte in a ULog format does not end the line inside its quote, an undefined Allan
// slope is said in words (not "-nan"), a dataset that nothing runs on is described stream by stream
// (the IMU file and its row count).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "tests/test_support.h"

namespace mavloc {
namespace {

using testing::CliPath;
using testing::MakeTempDir;
using testing::RunCommand;

// Runs `arguments` with stderr captured alone (stdout discarded).
testing::CommandResult RunForStderr(const std::string& arguments, const std::string& dir) {
  // An inner shell keeps RunCommand's trailing "2>&1" off mavloc's own redirections.
  testing::CommandResult r =
      RunCommand("sh -c '" + CliPath() + " " + arguments + " >/dev/null 2>" + dir + "/stderr.txt'");
  std::ifstream in(dir + "/stderr.txt", std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  r.output = text.str();
  return r;
}

void ExpectOneReadableLine(const std::string& output) {
  ASSERT_FALSE(output.empty());
  EXPECT_LE(output.size(), 1200u) << output.substr(0, 300);
  EXPECT_EQ(output.find('\n'), output.size() - 1) << "more than one line";
  for (const char c : output.substr(0, output.size() - 1))
    EXPECT_FALSE(static_cast<unsigned char>(c) < 0x20 || c == 0x7f) << "raw control byte";
}

TEST(CliErrorMessage, HugeFieldIsCut) {
  const std::string dir = MakeTempDir();
  {
    std::ofstream gt(dir + "/gt.txt");
    gt << "0 0 0 0 0 0 0 1\n1 " << std::string(2'000'000, '9') << "x 0 0 0 0 0 1\n";
    std::ofstream est(dir + "/est.txt");
    est << "0 0 0 0 0 0 0 1\n1 0 0 0 0 0 0 1\n";
  }
  const auto r = RunForStderr("eval --gt " + dir + "/gt.txt --est " + dir + "/est.txt", dir);
  EXPECT_EQ(r.exit_code, 2) << r.output.substr(0, 300);
  EXPECT_NE(r.output.find("gt.txt:2"), std::string::npos) << r.output.substr(0, 300);
  EXPECT_NE(r.output.find("bytes cut"), std::string::npos) << r.output.substr(0, 300);
  ExpectOneReadableLine(r.output);
}

TEST(CliErrorMessage, BinaryGarbageIsEscaped) {
  const std::string dir = MakeTempDir();
  {
    std::ofstream gt(dir + "/gt.txt", std::ios::binary);
    gt << "0 0 0 0 0 0 0 1\n1 \x01\x02\x1b[31mred\x7f\xff\xfe 0 0 0 0 0 1\n";
    std::ofstream est(dir + "/est.txt");
    est << "0 0 0 0 0 0 0 1\n1 0 0 0 0 0 0 1\n";
  }
  const auto r = RunForStderr("eval --gt " + dir + "/gt.txt --est " + dir + "/est.txt", dir);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("gt.txt:2"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("\\x1B"), std::string::npos) << r.output;
  ExpectOneReadableLine(r.output);
}

// ---- Messages that say what the user needs

// A ULog copy whose vehicle_attitude format has a NUL byte for the space after its first type.
void WriteUlogWithNulInAFormat(const std::string& path) {
  std::string bytes =
      testing::ReadFileBytes(testing::SharedDataDir() + "/px4_ulog/sample_log_small.ulg");
  const std::string format = "Fvehicle_attitude:uint64_t timestamp";
  const size_t at = bytes.find(format);
  ASSERT_NE(at, std::string::npos);
  bytes[at + format.find(' ')] = '\0';
  testing::WriteFileBytes(path, bytes);
}

// A static IMU log whose gyro x alternates between two values: its Allan deviation is 0 at two
// samples, where the local slope has no value.
void WriteAlternatingImu(const std::string& path) {
  std::mt19937_64 generator(1);
  std::normal_distribution<double> noise(0.0, 0.01);
  std::ostringstream csv;
  csv << "#timestamp [ns],w_RS_S_x [rad s^-1],w_RS_S_y [rad s^-1],w_RS_S_z [rad s^-1],"
         "a_RS_S_x [m s^-2],a_RS_S_y [m s^-2],a_RS_S_z [m s^-2]\n";
  for (int i = 0; i < 200 * 120; ++i) {
    const double gx = 0.001 * (i % 2);
    const double gy = noise(generator), gz = noise(generator);
    const double ax = noise(generator), ay = noise(generator), az = 9.81 + noise(generator);
    csv << 1000000000LL + 5000000LL * i << "," << gx << "," << gy << "," << gz << "," << ax << ","
        << ay << "," << az << "\n";
  }
  testing::WriteFileBytes(path, csv.str());
}

// A simulated dataset whose IMU file keeps its first row only (and no camera streams).
void WriteDatasetWithOneImuRow(const std::string& dir) {
  const auto made = RunCommand("cd " + dir + " && " + CliPath() +
                               " simulate --scenario mav-figure-eight --duration 2 --out ds");
  ASSERT_EQ(made.exit_code, 0) << made.output;
  const std::string path = dir + "/ds/mav0/imu0/data.csv";
  std::istringstream lines(testing::ReadFileBytes(path));
  std::string line, kept;
  int rows = 0;
  while (std::getline(lines, line))
    if (line[0] == '#' || rows++ == 0) kept += line + "\n";
  testing::WriteFileBytes(path, kept);
  std::filesystem::remove_all(dir + "/ds/mav0/features0");
  std::filesystem::remove_all(dir + "/ds/mav0/cam0");
}

struct MessageCase {
  const char* name;
  bool needs_shared_data;
  std::function<void(const std::string& dir)> prepare;
  std::string args;  // run in `dir`
  int exit_code;
  std::vector<std::string> must_contain;  // in stdout and stderr
  std::vector<std::string> must_not_contain;
};

TEST(CliErrorMessage, MessagesSayWhatTheUserNeeds) {
  const std::vector<MessageCase> cases = {
      {"a NUL byte in a ULog format",
       true,
       [](const std::string& dir) { WriteUlogWithNulInAFormat(dir + "/nul.ulg"); },
       "log info nul.ulg",
       2,
       {"nul.ulg", "malformed format message",
        "field 'uint64_t\\x00timestamp' has no 'type name' "
        "form"},
       {}},
      {"an Allan slope where the deviation is 0",
       false,
       [](const std::string& dir) { WriteAlternatingImu(dir + "/imu.csv"); },
       "imu-noise imu.csv --out noise",
       0,
       {"gyro x N: no -1/2 slope", "undefined (the Allan deviation is 0 there)"},
       {"nan"}},
      {"one IMU row: compare",
       false,
       WriteDatasetWithOneImuRow,
       "compare --dataset ds --report r",
       2,
       {"no estimator applies to dataset ds", "mav0/imu0/data.csv 1 row"},
       {}},
      {"one IMU row: run",
       false,
       WriteDatasetWithOneImuRow,
       "run --dataset ds --estimator imu-dead-reckoning --out o.txt",
       2,
       {"imu-dead-reckoning does not apply", "mav0/imu0/data.csv 1 row"},
       {}},
  };
  for (const MessageCase& c : cases) {
    SCOPED_TRACE(c.name);
    if (c.needs_shared_data && !testing::HasSharedData()) continue;
    const std::string dir = MakeTempDir() + "/" + std::to_string(&c - cases.data());
    std::filesystem::create_directories(dir);
    c.prepare(dir);
    if (HasFatalFailure()) return;
    const auto run = RunCommand("cd " + dir + " && MAVLOC_FIGURES=0 " + CliPath() + " " + c.args);
    EXPECT_EQ(run.exit_code, c.exit_code) << run.output;
    for (const auto& text : c.must_contain)
      EXPECT_NE(run.output.find(text), std::string::npos) << "'" << text << "' in " << run.output;
    for (const auto& text : c.must_not_contain)
      EXPECT_EQ(run.output.find(text), std::string::npos) << "'" << text << "' in " << run.output;
  }
}

}  // namespace
}  // namespace mavloc
