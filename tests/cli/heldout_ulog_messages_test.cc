// Bad-input cases from the independent ("held-out") catalogue through the real CLI, table-driven
// like tests/integration/bad_input_catalogue_test.cc: mutated copies of the real logs and
// trajectories of ../shared/data, made in a temp folder.
// - PX4 ULog: a value no MAV logs (NaN or 3e38 rad/s gyro, 1e30 m position, a q that is
//   not a rotation) is refused with exit code 2, one stderr line naming the file, the field and
//   the message, and no output; what the reader drops (repeated or earlier stamps, stamps beyond
//   the range, NaN q, cut or wrong-size messages) is imported with a note saying so.
// - Report folders never name their staging folder `DIR.tmp-PID`.
// - Messages: overflowing stamps are "beyond" the range, a one-row ground truth is blamed
//   on the ground truth, an error is one stderr line (notes deferred), `--estimators ,` names the
//   option.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "datasets/io/ulog/ulog_scan.h"
#include "tests/test_support.h"

namespace mavloc {
namespace {

namespace fs = std::filesystem;
using testing::CliPath;
using testing::MakeTempDir;
using testing::RunCommand;

std::string SmallUlog() { return testing::SharedDataDir() + "/px4_ulog/sample_log_small.ulg"; }
std::string SampleUlog() { return testing::SharedDataDir() + "/px4_ulog/sample.ulg"; }
std::string EurocTruth() {
  return testing::SharedDataDir() + "/euroc_v1_01_easy/groundtruth_full_tum.txt";
}

std::vector<std::string> Lines(const std::string& text) {
  std::vector<std::string> lines;
  std::stringstream stream(text);
  std::string line;
  while (std::getline(stream, line))
    if (!line.empty()) lines.push_back(line);
  return lines;
}

// Where each data message of one topic lies in a ULog file, found by mavloc's own scanner.
class TopicMessages : public ulog::ScanHandler {
 public:
  explicit TopicMessages(std::string topic) : topic_(std::move(topic)) {}
  bool WantsTopic(const ulog::Subscription& subscription) override {
    if (subscription.name != topic_ || subscription.multi_id != 0) return false;
    layout = subscription.layout;
    return true;
  }
  void OnData(const ulog::Subscription&, const uint8_t*, uint64_t, uint64_t offset) override {
    offsets.push_back(offset);
  }
  // Byte offset in the file of a field of message `index` (header 3 bytes, msg_id 2 bytes).
  size_t FieldOffset(size_t index, const std::string& field) const {
    if (field == "timestamp") return offsets.at(index) + 5 + layout.timestamp_offset;
    const ulog::FlatField* f = layout.Find(field);
    EXPECT_NE(f, nullptr) << field;
    return offsets.at(index) + 5 + (f ? f->offset : 0);
  }

  ulog::FlatLayout layout;
  std::vector<uint64_t> offsets;

 private:
  std::string topic_;
};

TopicMessages Scan(const std::string& path, const std::string& topic) {
  TopicMessages messages(topic);
  ulog::ScanUlog(path, &messages, {});
  EXPECT_GT(messages.offsets.size(), 20u) << topic;
  return messages;
}

template <typename T>
void Put(std::string* bytes, size_t offset, T value) {
  std::memcpy(bytes->data() + offset, &value, sizeof value);
}
template <typename T>
T Get(const std::string& bytes, size_t offset) {
  T value;
  std::memcpy(&value, bytes.data() + offset, sizeof value);
  return value;
}

// Mutations of a copy of a ULog file: one field of one message set to a value, a message cut or
// resized, stamps changed.
using Mutation = std::function<void(const std::string& source, std::string* bytes)>;

Mutation SetFloat(const std::string& topic, size_t index, const std::string& field, float value) {
  return [=](const std::string& source, std::string* bytes) {
    const TopicMessages m = Scan(source, topic);
    Put(bytes, m.FieldOffset(index, field), value);
  };
}

Mutation SetFloatEverywhere(const std::string& topic, const std::string& field, float value) {
  return [=](const std::string& source, std::string* bytes) {
    const TopicMessages m = Scan(source, topic);
    for (size_t i = 0; i < m.offsets.size(); ++i) Put(bytes, m.FieldOffset(i, field), value);
  };
}

// delta_us = 0: the previous message's stamp (repeated); < 0: earlier; huge: 2^64 - 1 us.
Mutation SetStamp(const std::string& topic, size_t index, int64_t delta_us, bool huge = false) {
  return [=](const std::string& source, std::string* bytes) {
    const TopicMessages m = Scan(source, topic);
    const uint64_t previous = Get<uint64_t>(*bytes, m.FieldOffset(index - 1, "timestamp"));
    Put(bytes, m.FieldOffset(index, "timestamp"),
        huge ? std::numeric_limits<uint64_t>::max() : previous + delta_us);
  };
}

// Data message `index` keeps its msg_id and 4 payload bytes (a wrong-size message).
Mutation CutMessage(const std::string& topic, size_t index) {
  return [=](const std::string& source, std::string* bytes) {
    const TopicMessages m = Scan(source, topic);
    const size_t at = m.offsets.at(index);
    const uint16_t size = Get<uint16_t>(*bytes, at);
    Put(bytes, at, uint16_t{6});
    bytes->erase(at + 3 + 6, size - 6);
  };
}

Mutation Truncate(size_t length) {
  return [=](const std::string&, std::string* bytes) { bytes->resize(length); };
}

struct UlogCase {
  std::string name;
  std::string log;  // SmallUlog() or SampleUlog()
  Mutation mutate;
  std::string command;  // after "mavloc ", with f.ulg the mutated copy; output to "out"
  bool refused;         // exit 2, one stderr line naming f.ulg, nothing written
  std::vector<std::string> expected;  // in stderr (refused) or stdout (imported with a note)
};

void ExpectOneLineError(const testing::CliRun& o, const std::vector<std::string>& expected) {
  EXPECT_EQ(o.exit_code, 2) << o.out << o.err;
  const std::vector<std::string> lines = Lines(o.err);
  EXPECT_EQ(lines.size(), 1u) << o.err;
  for (const auto& e : expected)
    EXPECT_NE(o.err.find(e), std::string::npos) << "expected '" << e << "' in: " << o.err;
  EXPECT_EQ(o.err.find("internal error"), std::string::npos) << o.err;
  EXPECT_LT(o.err.size(), 1200u);
}

TEST(HeldoutUlog, BadSamplesAreRefusedOrDroppedWithANote) {
  REQUIRE_SHARED_DATA();
  const std::string import = "log import f.ulg --imu sensor_combined --out out";
  const std::string attitude = "log export f.ulg:vehicle_attitude --out out";
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const std::vector<UlogCase> cases = {
      {"gyro NaN",
       SmallUlog(),
       SetFloat("sensor_combined", 10, "gyro_rad[0]", nan),
       import,
       true,
       {"f.ulg", "field 'gyro_rad[0]'", "message 10", "not finite"}},
      {"gyro 3e38 rad/s",
       SmallUlog(),
       SetFloat("sensor_combined", 10, "gyro_rad[1]", 3e38f),
       import,
       true,
       {"f.ulg", "field 'gyro_rad[1]'", "message 10", "outside [-100, 100] rad/s"}},
      {"accelerometer 1e5 m/s^2",
       SmallUlog(),
       SetFloat("sensor_combined", 12, "accelerometer_m_s2[2]", 1e5f),
       import,
       true,
       {"f.ulg", "field 'accelerometer_m_s2[2]'", "message 12", "outside"}},
      {"local position x 1e30 m",
       SampleUlog(),
       SetFloatEverywhere("vehicle_local_position", "x", 1e30f),
       "log export f.ulg:vehicle_local_position --out out",
       true,
       {"f.ulg", "field 'x'", "message 0", "outside"}},
      {"attitude q not a rotation",
       SmallUlog(),
       SetFloat("vehicle_attitude", 10, "q[0]", 5.0f),
       attitude,
       true,
       {"f.ulg", "field 'q[0]'", "message 10", "not a unit quaternion"}},
      {"repeated IMU stamp",
       SmallUlog(),
       SetStamp("sensor_combined", 10, 0),
       import,
       false,
       {"sensor_combined: 1 message(s) with a repeated stamp", "(first: message 10)"}},
      {"IMU stamp 1 ms back",
       SmallUlog(),
       SetStamp("sensor_combined", 10, -1000),
       import,
       false,
       {"sensor_combined: 1 message(s) with a stamp earlier than the previous message",
        "dropped (first: message 10)"}},
      {"IMU stamp 2^64-1 us",
       SmallUlog(),
       SetStamp("sensor_combined", 10, 0, true),
       import,
       false,
       {"1 data message(s) with a timestamp beyond the range"}},
      {"wrong-size IMU message",
       SmallUlog(),
       CutMessage("sensor_combined", 10),
       import,
       false,
       {"1 data message(s) of the wrong size skipped"}},
      {"log cut at 500000 bytes",
       SmallUlog(),
       Truncate(500000),
       import,
       false,
       {"note: truncated: the last message"}},
      {"attitude q NaN",
       SmallUlog(),
       SetFloat("vehicle_attitude", 10, "q[0]", nan),
       attitude,
       false,
       {"vehicle_attitude: 1 message(s) with a NaN or infinite q (invalid) dropped"}},
      {"attitude stamp back",
       SmallUlog(),
       SetStamp("vehicle_attitude", 10, -1000),
       attitude,
       false,
       {"vehicle_attitude: 1 message(s) with a stamp earlier than the previous message"}},
  };
  for (const UlogCase& c : cases) {
    SCOPED_TRACE(c.name);
    const fs::path dir = MakeTempDir();
    std::string bytes = testing::ReadFileBytes(c.log);
    c.mutate(c.log, &bytes);
    testing::WriteFileBytes(dir / "f.ulg", bytes);
    const testing::CliRun o = testing::RunCliIn(dir, c.command);
    if (c.refused) {
      ExpectOneLineError(o, c.expected);
      EXPECT_FALSE(fs::exists(dir / "out")) << "output left";
    } else {
      EXPECT_EQ(o.exit_code, 0) << o.out << o.err;
      for (const auto& e : c.expected)
        EXPECT_NE(o.out.find(e), std::string::npos) << "expected '" << e << "' in: " << o.out;
      if (fs::is_directory(dir / "out")) {  // log import: the notes are in import.yaml as well
        const std::string yaml = testing::ReadFileBytes(dir / "out" / "import.yaml");
        EXPECT_NE(yaml.find(c.expected.front()), std::string::npos) << yaml;
      }
    }
  }
}

TEST(HeldoutUlog, RealLogsImportWithoutDroppedSamples) {
  REQUIRE_SHARED_DATA();
  for (const std::string log :
       {"sample.ulg", "sample_log_small.ulg", "sample_appended_multiple.ulg"}) {
    SCOPED_TRACE(log);
    const fs::path dir = MakeTempDir();
    const testing::CliRun o =
        testing::RunCliIn(dir, "log import " + testing::SharedDataDir() + "/px4_ulog/" + log +
                                   " --imu sensor_combined --out out");
    EXPECT_EQ(o.exit_code, 0) << o.out << o.err;
    EXPECT_EQ(o.out.find("dropped"), std::string::npos) << o.out;
    const testing::CliRun e =
        testing::RunCliIn(dir, "log export " + testing::SharedDataDir() + "/px4_ulog/" + log +
                                   ":vehicle_attitude --out att.tum");
    EXPECT_EQ(e.exit_code, 0) << e.out << e.err;
  }
}

// `compare --reference LOG:TOPIC` and `eval --gt/--est LOG:TOPIC` read through ReadLogTrajectory,
// whose LogTrajectory carries the ULog reader's notes: compare prints them on stdout ("note: "),
// eval with its other deferred notes; an eval that is refused keeps its one stderr line. The
// sample logs have no full-pose topic (vehicle_odometry), so eval on them is always refused.
TEST(HeldoutUlog, LogTopicTrajectoriesCarryTheReadersNotes) {
  REQUIRE_SHARED_DATA();
  const std::string drop =
      "f.ulg: vehicle_attitude: 1 message(s) with a stamp earlier than the previous message";
  const std::string compare =
      "compare --dataset d --estimators gravity-ekf --reference f.ulg:vehicle_attitude --report r";
  for (const bool mutated : {true, false}) {
    SCOPED_TRACE(mutated ? "stamp 1 ms back" : "real log");
    const fs::path dir = MakeTempDir();
    std::string bytes = testing::ReadFileBytes(SmallUlog());
    if (mutated) SetStamp("vehicle_attitude", 10, -1000)(SmallUlog(), &bytes);
    testing::WriteFileBytes(dir / "f.ulg", bytes);
    ASSERT_EQ(testing::RunCliIn(dir, "log import f.ulg --imu sensor_combined --out d").exit_code,
              0);
    const testing::CliRun o = testing::RunCliIn(dir, compare);
    EXPECT_EQ(o.exit_code, 0) << o.out << o.err;
    if (mutated) {
      EXPECT_NE(o.out.find("note: " + drop), std::string::npos) << o.out;
      EXPECT_NE(o.out.find("dropped (first: message 10)"), std::string::npos) << o.out;
    } else {
      EXPECT_EQ(o.out.find("note:"), std::string::npos) << o.out;
      EXPECT_EQ(o.out.find("dropped"), std::string::npos) << o.out;
    }
    // eval needs full poses: refused in one stderr line, without the reader's notes.
    const testing::CliRun e =
        testing::RunCliIn(dir, "eval --gt f.ulg:vehicle_attitude --est f.ulg:vehicle_attitude");
    ExpectOneLineError(e, {"f.ulg", "carries no position"});
    EXPECT_EQ(e.out.find("dropped"), std::string::npos) << e.out;
  }
}

// The first `rows` data rows of V1_01_easy's ground truth (TUM, with its comment line).
void WriteTruth(const fs::path& path, size_t rows) {
  const std::vector<std::string> lines = Lines(testing::ReadFileBytes(EurocTruth()));
  std::string text;
  for (size_t i = 0; i <= rows && i < lines.size(); ++i) text += lines[i] + "\n";
  testing::WriteFileBytes(path, text);
}

// Replaces the first field of every data row (TUM: the stamp) by `stamp`, or only the last row's.
void SetStamps(const fs::path& path, const std::string& stamp, bool last_only) {
  std::vector<std::string> lines = Lines(testing::ReadFileBytes(path));
  std::string text;
  for (size_t i = 0; i < lines.size(); ++i) {
    std::string line = lines[i];
    if (line[0] != '#' && (!last_only || i + 1 == lines.size()))
      line = stamp + line.substr(line.find(' '));
    text += line + "\n";
  }
  testing::WriteFileBytes(path, text);
}

TEST(HeldoutMessages, EvalErrorsAreOneLineAndNameTheRightFile) {
  REQUIRE_SHARED_DATA();
  struct Case {
    std::string name;
    std::function<void(const fs::path&)> mutate;
    std::vector<std::string> expected;
  };
  const std::vector<Case> cases = {
      {"estimate stamp 1e20 s",
       [](const fs::path& d) { SetStamps(d / "est.txt", "100000000000000000000", true); },
       {"est.txt:201: field 'timestamp", "is beyond 4611686018 s", "kMaxTimestampNs"}},
      {"estimate stamp 9999999999.5 s",
       [](const fs::path& d) { SetStamps(d / "est.txt", "9999999999.5", true); },
       {"est.txt:201:", "is beyond"}},
      {"one-row ground truth",
       [](const fs::path& d) { WriteTruth(d / "gt.txt", 1); },
       {"gt.txt", "1 pose", "at least 2"}},
      {"estimate with one stamp",
       [](const fs::path& d) { SetStamps(d / "est.txt", "1403715275.0", false); },
       {"est.txt", "only 1 pose pair", "repeated timestamp"}},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const fs::path dir = MakeTempDir();
    WriteTruth(dir / "gt.txt", 800);
    WriteTruth(dir / "est.txt", 200);
    c.mutate(dir);
    const testing::CliRun o = testing::RunCliIn(dir, "eval --gt gt.txt --est est.txt --out o");
    ExpectOneLineError(o, c.expected);
    EXPECT_FALSE(fs::exists(dir / "o"));
  }
}

TEST(HeldoutMessages, OverflowingNanosecondStampIsBeyondTheRange) {
  const fs::path dir = MakeTempDir();
  ASSERT_EQ(
      testing::RunCliIn(dir, "simulate --scenario mav-figure-eight --duration 2 --out d").exit_code,
      0);
  std::vector<std::string> lines = Lines(testing::ReadFileBytes(dir / "d/mav0/imu0/data.csv"));
  ASSERT_GT(lines.size(), 10u);
  lines[9] = "99999999999999999999" + lines[9].substr(lines[9].find(','));
  std::string text;
  for (const auto& line : lines) text += line + "\n";
  testing::WriteFileBytes(dir / "d/mav0/imu0/data.csv", text);
  const testing::CliRun o =
      testing::RunCliIn(dir, "compare --dataset d --estimators imu-dead-reckoning --report r");
  ExpectOneLineError(o, {"imu0/data.csv:10: field 'timestamp [ns]'", "is beyond", "2^62 ns"});
  EXPECT_FALSE(fs::exists(dir / "r"));
}

TEST(HeldoutMessages, EmptyEstimatorListNamesTheOption) {
  const fs::path dir = MakeTempDir();
  const testing::CliRun o = testing::RunCliIn(
      dir, "compare --scenario mav-figure-eight --duration 3 --estimators , --report r");
  ExpectOneLineError(o, {"--estimators", "the list is empty"});
  EXPECT_FALSE(fs::exists(dir / "r"));
}

TEST(HeldoutReports, FigureHintNamesTheFinalFolderNotTheStagingFolder) {
  REQUIRE_SHARED_DATA();
  const fs::path dir = MakeTempDir();
  WriteTruth(dir / "gt.txt", 800);
  WriteTruth(dir / "est.txt", 200);
  const testing::CliRun o = testing::RunCliIn(dir, "eval --gt gt.txt --est est.txt --out o");
  ASSERT_EQ(o.exit_code, 0) << o.out << o.err;
  for (const char* file : {"o/report.md", "o/report.html"}) {
    const std::string text = testing::ReadFileBytes(dir / file);
    EXPECT_EQ(text.find(".tmp-"), std::string::npos) << file;
    EXPECT_NE(text.find("mavloc figures o"), std::string::npos) << file;
  }
  const testing::CliRun c = testing::RunCliIn(
      dir,
      "compare --scenario mav-figure-eight --duration 3 --estimators imu-dead-reckoning "
      "--report r");
  ASSERT_EQ(c.exit_code, 0) << c.out << c.err;
  for (const char* file : {"r/report.md", "r/report.html"}) {
    const std::string text = testing::ReadFileBytes(dir / file);
    EXPECT_EQ(text.find(".tmp-"), std::string::npos) << file;
    EXPECT_NE(text.find("mavloc figures r"), std::string::npos) << file;
  }
}

}  // namespace
}  // namespace mavloc
