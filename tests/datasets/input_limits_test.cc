// The limits of core/input_limits.h (docs/limits.md): a few bytes that describe a structure too
// large to expand — ULog formats that nest arrays of empty formats, formats nested too deep or
// flattened too often, YAML nested too deep or repeated by aliases, a ROS array whose length
// claims more elements than the message's bytes can hold — are refused quickly with a message
// naming the file, the structure and the limit, and the real files of the shared data still read.
#include <gtest/gtest.h>
#include <rosbag/bag.h>

#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "core/errors.h"
#include "datasets/io/log_reader.h"
#include "datasets/io/rosbag/rosbag_reader.h"
#include "datasets/io/rosbag/rosbag_tag_messages.h"
#include "datasets/io/ulog/ulog_reader.h"
#include "datasets/io/yaml_util.h"
#include "tests/test_support.h"

namespace fs = std::filesystem;

namespace mavloc {
namespace {

// A ULog file of format definitions and subscriptions only (spec:
// docs.px4.io/main/en/dev_log/ulog_file_format.html).
std::string UlogBytes(const std::vector<std::string>& formats,
                      const std::vector<std::string>& subscriptions) {
  std::string bytes("ULog\x01\x12\x35\x01", 8);
  const uint64_t t_us = 1000000;
  bytes.append(reinterpret_cast<const char*>(&t_us), 8);
  const auto message = [&](char type, const std::string& payload) {
    const uint16_t size = static_cast<uint16_t>(payload.size());
    bytes.append(reinterpret_cast<const char*>(&size), 2);
    bytes.push_back(type);
    bytes += payload;
  };
  for (const std::string& format : formats) message('F', format);
  for (size_t i = 0; i < subscriptions.size(); ++i) {
    const uint16_t msg_id = static_cast<uint16_t>(i);
    message('A', std::string(1, '\0') + std::string(reinterpret_cast<const char*>(&msg_id), 2) +
                     subscriptions[i]);
  }
  return bytes;
}

// "f0:f1 n;" ... "f<depth-1>:f<depth> n;" "f<depth>:uint8_t v;": f0 nests `depth` levels.
std::vector<std::string> NestedChain(int depth) {
  std::vector<std::string> formats;
  for (int k = 0; k < depth; ++k) formats.push_back(fmt::format("f{}:f{} n;", k, k + 1));
  formats.push_back(fmt::format("f{}:uint8_t v;", depth));
  return formats;
}

struct UlogCase {
  const char* name;
  std::vector<std::string> formats;
  std::vector<std::string> subscriptions;
  std::string error;  // a fragment of the InputError; empty: the file reads
  std::string note;   // a fragment of one of the notes when it reads; empty: none asked
};

const UlogCase kUlogCases[] = {
    // An empty format in a large array: 100,000 steps of expansion for no field, and another
    // level multiplies them (minutes, then unbounded, before the limit).
    {"EmptyFormatInALargeArray",
     {"e:", "y:e[100000] a;", "z:y[100000] b;"},
     {"z"},
     "subscription to 'z': format 'y' flattens to more than 65535 fields",
     ""},
    {"ThreeLevelsOfEmptyFormats",
     {"e:", "y:e[1000] a;", "x:y[1000] b;", "w:x[1000] c;"},
     {"w"},
     "format 'x' flattens to more than 65535 fields",
     ""},
    {"PrimitivesBeyondTheFieldLimit",
     {"inner:uint8_t[300] v;", "outer:inner[300] items;"},
     {"outer"},
     "format 'outer' flattens to more than 65535 fields",
     ""},
    {"FormatLargerThanAMessage",
     {"big:uint64_t[9000] v;"},
     {"big"},
     "format 'big' is larger than a ULog message can be (more than 65535 bytes",
     ""},
    {"NestingDeeperThanTheLimit",
     NestedChain(20),
     {"f0"},
     "format 'f0' nests formats more than 16 levels deep",
     ""},
    {"ManySubscriptionsToALargeFormat",
     {"big:uint8_t[60000] v;"},
     std::vector<std::string>(40, "big"),
     "the log's formats need more than 2097152 steps to flatten",
     ""},
    // Not limits: a cycle and a missing type skip the subscription with a note, as before.
    {"CycleIsNamedInANote",
     {"a:b x;", "b:a y;"},
     {"a"},
     "",
     "format 'a' nests itself (a -> b -> a)"},
    {"MissingTypeIsANote", {"a:nothing x;"}, {"a"}, "", "no format definition for type 'nothing'"},
    // Within the limits: 16 levels, and a wide format of nested arrays.
    {"NestingAtTheLimitReads", NestedChain(16), {"f0"}, "", ""},
    {"WideNestedFormatReads",
     {"inner:float[3] v;", "outer:uint64_t timestamp;inner[1000] items;"},
     {"outer", "outer"},
     "",
     ""},
};

class UlogLimits : public ::testing::TestWithParam<UlogCase> {};

TEST_P(UlogLimits, RefusedQuicklyWithFileAndFormat) {
  const UlogCase& c = GetParam();
  const std::string path = testing::MakeTempDir() + "/crafted.ulg";
  testing::WriteFileBytes(path, UlogBytes(c.formats, c.subscriptions));
  const auto start = std::chrono::steady_clock::now();
  std::string error;
  UlogInfo info;
  try {
    info = ReadUlogInfo(path);
  } catch (const InputError& e) {
    error = e.what();
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_LT(seconds, 5.0) << "bounded work: the limits are checked before expanding";
  if (c.error.empty()) {
    EXPECT_EQ(error, "");
  } else {
    EXPECT_NE(error.find(path + ": byte offset "), std::string::npos) << error;
    EXPECT_NE(error.find(c.error), std::string::npos) << error;
    EXPECT_NE(error.find("limit input_limits::"), std::string::npos) << error;
  }
  if (!c.note.empty()) {
    std::string notes;
    for (const std::string& note : info.notes) notes += note + "\n";
    EXPECT_NE(notes.find(c.note), std::string::npos) << notes;
  }
}

INSTANTIATE_TEST_SUITE_P(Crafted, UlogLimits, ::testing::ValuesIn(kUlogCases),
                         [](const auto& row) { return std::string(row.param.name); });

// The tool itself: `mavloc log info` on the empty-format file ends at once with one line.
TEST(UlogLimitsCli, LogInfoRefusesNestedEmptyArraysWithOneLine) {
  if (!fs::exists(testing::CliPath())) GTEST_SKIP() << "mavloc is not built";
  const std::string dir = testing::MakeTempDir();
  testing::WriteFileBytes(dir + "/crafted.ulg",
                          UlogBytes({"e:", "y:e[100000] a;", "z:y[100000] b;"}, {"z"}));
  const auto start = std::chrono::steady_clock::now();
  const testing::CliRun r = testing::RunCliIn(dir, "log info crafted.ulg");
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 10.0);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_NE(r.err.find("crafted.ulg"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("format 'y'"), std::string::npos) << r.err;
}

// The real logs stay within the limits.
TEST(UlogLimitsReal, SharedLogsRead) {
  REQUIRE_SHARED_DATA();
  for (const char* name : {"sample.ulg", "sample_log_small.ulg", "sample_appended_multiple.ulg"}) {
    const std::string path = testing::SharedDataDir() + "/px4_ulog/" + name;
    const UlogInfo info = ReadUlogInfo(path);
    EXPECT_FALSE(info.topics.empty()) << path;
    for (const std::string& note : info.notes)
      EXPECT_EQ(note.find("ignored"), std::string::npos) << path << ": " << note;
  }
}

// ---- YAML

// `levels` flow lists within each other around one value.
std::string FlowNesting(int levels) {
  return std::string(levels, '[') + "1" + std::string(levels, ']') + "\n";
}

std::string BlockNesting(int levels) {
  std::string text;
  for (int i = 0; i < levels; ++i) text += std::string(2 * i, ' ') + "k:\n";
  return text + std::string(2 * levels, ' ') + "v\n";
}

// Ten aliases of the level below on each of `levels` levels: 10^levels nodes for a walker.
std::string AliasBomb(int levels) {
  std::string text = "l0: &l0 [1, 1, 1, 1, 1, 1, 1, 1, 1, 1]\n";
  for (int k = 1; k <= levels; ++k) {
    text += fmt::format("l{}: &l{} [", k, k);
    for (int i = 0; i < 10; ++i) text += fmt::format("{}*l{}", i == 0 ? "" : ", ", k - 1);
    text += "]\n";
  }
  return text;
}

struct YamlCase {
  const char* name;
  std::string text;
  std::string error;  // empty: loads
};

const YamlCase kYamlCases[] = {
    {"FlowNestedBeyondTheLimit", FlowNesting(100), "YAML nests deeper than 64 levels"},
    {"BlockNestedBeyondTheLimit", BlockNesting(100), "YAML nests deeper than 64 levels"},
    // Beyond yaml-cpp's own guard, which says only "bad file".
    {"NestedBeyondTheParserGuard", FlowNesting(5000), "YAML nests deeper than 64 levels"},
    {"AliasesOfAliases", AliasBomb(7), "YAML document has more than 1048576 nodes"},
    {"FlowNestedWithinTheLimit", FlowNesting(60), ""},
    {"FewAliasesLoad", AliasBomb(2), ""},
};

class YamlLimits : public ::testing::TestWithParam<YamlCase> {};

TEST_P(YamlLimits, RefusedWithFileAndLimit) {
  const YamlCase& c = GetParam();
  const std::string path = testing::MakeTempDir() + "/crafted.yaml";
  testing::WriteFileBytes(path, c.text);
  const auto start = std::chrono::steady_clock::now();
  std::string error;
  try {
    LoadYamlFile(path);
  } catch (const InputError& e) {
    error = e.what();
  }
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 5.0);
  if (c.error.empty()) {
    EXPECT_EQ(error, "");
  } else {
    EXPECT_EQ(error.rfind(path, 0), 0u) << error;
    EXPECT_NE(error.find(c.error), std::string::npos) << error;
  }
}

INSTANTIATE_TEST_SUITE_P(Crafted, YamlLimits, ::testing::ValuesIn(kYamlCases),
                         [](const auto& row) { return std::string(row.param.name); });

TEST(YamlLimitsReal, SharedYamlFilesLoad) {
  REQUIRE_SHARED_DATA();
  int loaded = 0;
  for (const auto& entry : fs::recursive_directory_iterator(testing::SharedDataDir())) {
    if (entry.path().extension() != ".yaml") continue;
    EXPECT_NO_THROW(LoadYamlFile(entry.path().string())) << entry.path();
    ++loaded;
  }
  EXPECT_GT(loaded, 10);
}

}  // namespace

// ---- ROS: an apriltag_msgs/ApriltagArrayStamped (same type, MD5 and definition) whose array
// length claims 1000 tags in a message of about 2 kB: within one byte per element, but a tag
// takes at least 140 bytes on the wire, so the array cannot be that long.
struct ShortTagArray {
  ros1::HeaderMsg header;
  uint32_t apriltags_length = 1000;
  boost::array<uint8_t, 2000> padding{};
};

}  // namespace mavloc

namespace ros::message_traits {
template <>
struct MD5Sum<mavloc::ShortTagArray> {
  static const char* value() { return mavloc::ros1::kApriltagArrayStampedMd5; }
  static const char* value(const mavloc::ShortTagArray&) { return value(); }
};
template <>
struct DataType<mavloc::ShortTagArray> {
  static const char* value() { return "apriltag_msgs/ApriltagArrayStamped"; }
  static const char* value(const mavloc::ShortTagArray&) { return value(); }
};
template <>
struct Definition<mavloc::ShortTagArray> {
  static const char* value() { return mavloc::ros1::ApriltagArrayStampedDefinition(); }
  static const char* value(const mavloc::ShortTagArray&) { return value(); }
};
}  // namespace ros::message_traits

namespace ros::serialization {
template <>
struct Serializer<mavloc::ShortTagArray> {
  template <typename Stream, typename T>
  inline static void allInOne(Stream& stream, T m) {
    stream.next(m.header);
    stream.next(m.apriltags_length);
    stream.next(m.padding);
  }
  ROS_DECLARE_ALLINONE_SERIALIZER
};
}  // namespace ros::serialization

namespace mavloc {
namespace {

TEST(RosbagLimits, ArrayLongerThanItsElementsCanFillIsRefusedBeforeAllocation) {
  const std::string path = testing::MakeTempDir() + "/short.bag";
  {
    rosbag::Bag bag(path, rosbag::bagmode::Write);
    bag.write("/tags", ros::Time(10, 0), ShortTagArray{});
  }
  try {
    ReadRosbagTags(path, "/tags", 0);
    FAIL() << "no error";
  } catch (const InputError& error) {
    const std::string what = error.what();
    EXPECT_NE(what.find(path + ": topic /tags, message 0: cannot deserialize"), std::string::npos)
        << what;
    EXPECT_NE(what.find("an array of 1000 elements in a message of 2020 bytes (an element takes "
                        "at least 140 bytes)"),
              std::string::npos)
        << what;
  }
}

}  // namespace
}  // namespace mavloc
