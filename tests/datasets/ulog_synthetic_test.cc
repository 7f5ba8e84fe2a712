// Hand-assembled ULog files (bytes written by the test, following
// docs.px4.io/main/en/dev_log/ulog_file_format.html): nested formats, arrays, padding,
// multi-instance topics, logged strings, dropouts, appended data, corrupt messages, and a file
// cut at every byte offset.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "core/errors.h"
#include "datasets/io/ulog/ulog_format.h"
#include "datasets/io/ulog/ulog_reader.h"
#include "datasets/io/ulog/ulog_topic_fields.h"
#include "tests/test_support.h"

namespace mavloc {
namespace {

LogTopicSpec Spec(const std::string& path, const std::string& topic) {
  LogTopicSpec spec;
  spec.path = path;
  spec.topic = topic;
  return spec;
}

// Little-endian byte writer for ULog messages.
class UlogBytes {
 public:
  explicit UlogBytes(int version = 1, uint64_t t_us = 1000000) {
    const uint8_t magic[7] = {'U', 'L', 'o', 'g', 0x01, 0x12, 0x35};
    bytes_.insert(bytes_.end(), magic, magic + 7);
    bytes_.push_back(static_cast<uint8_t>(version));
    Put(t_us);
  }

  template <typename T>
  static void PutTo(std::vector<uint8_t>* out, T value) {
    uint8_t raw[sizeof(T)];
    std::memcpy(raw, &value, sizeof(T));
    out->insert(out->end(), raw, raw + sizeof(T));
  }
  template <typename T>
  void Put(T value) {
    PutTo(&bytes_, value);
  }

  void Message(char type, const std::vector<uint8_t>& payload) {
    Put(static_cast<uint16_t>(payload.size()));
    bytes_.push_back(static_cast<uint8_t>(type));
    bytes_.insert(bytes_.end(), payload.begin(), payload.end());
  }
  static std::vector<uint8_t> Text(const std::string& s) { return {s.begin(), s.end()}; }

  void FlagBits(uint8_t incompat0, std::vector<uint64_t> offsets = {}) {
    std::vector<uint8_t> p(16, 0);
    p[8] = incompat0;
    offsets.resize(3, 0);
    for (const uint64_t o : offsets) PutTo(&p, o);
    Message('B', p);
  }
  void Format(const std::string& text) { Message('F', Text(text)); }
  void Info(const std::string& type_key, const std::vector<uint8_t>& value) {
    std::vector<uint8_t> p = {static_cast<uint8_t>(type_key.size())};
    p.insert(p.end(), type_key.begin(), type_key.end());
    p.insert(p.end(), value.begin(), value.end());
    Message('I', p);
  }
  void Add(uint8_t multi_id, uint16_t msg_id, const std::string& name) {
    std::vector<uint8_t> p = {multi_id};
    PutTo(&p, msg_id);
    p.insert(p.end(), name.begin(), name.end());
    Message('A', p);
  }
  void Data(uint16_t msg_id, const std::vector<uint8_t>& data) {
    std::vector<uint8_t> p;
    PutTo(&p, msg_id);
    p.insert(p.end(), data.begin(), data.end());
    Message('D', p);
  }
  void Logged(char level, uint64_t t_us, const std::string& text) {
    std::vector<uint8_t> p = {static_cast<uint8_t>(level)};
    PutTo(&p, t_us);
    p.insert(p.end(), text.begin(), text.end());
    Message('L', p);
  }
  void Dropout(uint16_t ms) {
    std::vector<uint8_t> p;
    PutTo(&p, ms);
    Message('O', p);
  }
  void Sync() { Message('S', {0x2F, 0x73, 0x13, 0x20, 0x25, 0x0C, 0xBB, 0x12}); }

  size_t size() const { return bytes_.size(); }
  std::vector<uint8_t>& bytes() { return bytes_; }

  std::string Write(const std::string& path, size_t length = SIZE_MAX) const {
    std::ofstream out(path, std::ios::binary);
    out.write(reinterpret_cast<const char*>(bytes_.data()),
              static_cast<std::streamsize>(std::min(length, bytes_.size())));
    return path;
  }

 private:
  std::vector<uint8_t> bytes_;
};

// One payload of "test_topic" (format in WriteNestedLog): 46 logged bytes, or 52 with the
// trailing padding.
std::vector<uint8_t> NestedPayload(uint64_t t_us, int k, bool with_trailing_padding) {
  std::vector<uint8_t> p;
  UlogBytes::PutTo(&p, t_us);
  for (int item = 0; item < 2; ++item) {
    UlogBytes::PutTo(&p, static_cast<uint32_t>(100 * k + item));  // items[i].id
    UlogBytes::PutTo(&p, static_cast<float>(k + 0.25f * item));   // items[i].w[0]
    UlogBytes::PutTo(&p, static_cast<float>(-k - 0.5f * item));   // items[i].w[1]
  }
  p.push_back(static_cast<uint8_t>(k % 2));                    // flag
  p.insert(p.end(), 3, 0xAA);                                  // _padding0
  UlogBytes::PutTo(&p, 1e9 + k);                               // d
  p.push_back(static_cast<uint8_t>(static_cast<int8_t>(-k)));  // s[0]
  p.push_back(static_cast<uint8_t>(static_cast<int8_t>(k)));   // s[1]
  if (with_trailing_padding) p.insert(p.end(), 6, 0);          // _padding1
  return p;
}

std::vector<uint8_t> SensorCombinedPayload(uint64_t t_us, const Eigen::Vector3f& gyro_frd,
                                           const Eigen::Vector3f& accel_frd) {
  std::vector<uint8_t> p;
  UlogBytes::PutTo(&p, t_us);
  for (int i = 0; i < 3; ++i) UlogBytes::PutTo(&p, gyro_frd[i]);
  UlogBytes::PutTo(&p, static_cast<int32_t>(0));  // accelerometer_timestamp_relative
  for (int i = 0; i < 3; ++i) UlogBytes::PutTo(&p, accel_frd[i]);
  return p;
}

constexpr const char* kInner = "inner:uint32_t id;float[2] w;";
constexpr const char* kTestTopic =
    "test_topic:uint64_t timestamp;inner[2] items;uint8_t flag;uint8_t[3] _padding0;double d;"
    "int8_t[2] s;uint8_t[6] _padding1;";
constexpr const char* kSensorCombined =
    "sensor_combined:uint64_t timestamp;float[3] gyro_rad;int32_t "
    "accelerometer_timestamp_relative;float[3] accelerometer_m_s2;";

// A small log: nested formats with arrays and padding, a two-instance sensor_combined, strings,
// a dropout and a sync message.
UlogBytes NestedLog() {
  UlogBytes log;
  log.FlagBits(0);
  log.Format(kInner);
  log.Format(kTestTopic);
  log.Format(kSensorCombined);
  log.Info("char[3] sys_name", UlogBytes::Text("PX4"));
  std::vector<uint8_t> v;
  UlogBytes::PutTo(&v, static_cast<int32_t>(-7));
  log.Info("int32_t answer", v);
  log.Add(0, 3, "test_topic");
  log.Add(0, 1, "sensor_combined");
  log.Add(1, 2, "sensor_combined");
  log.Logged('6', 1500000, "[commander] hello");
  for (int k = 0; k < 4; ++k) {
    const uint64_t t = 2000000 + 10000 * k;
    log.Data(3, NestedPayload(t, k, k == 3));
    log.Data(1, SensorCombinedPayload(t, {0.1f * k, 0.2f, -0.3f}, {0.5f, -0.25f, -9.81f}));
    log.Data(2, SensorCombinedPayload(t + 5, {1.0f, 2.0f, 3.0f}, {4.0f, 5.0f, 6.0f}));
    if (k == 1) log.Dropout(25);
    if (k == 2) log.Sync();
  }
  log.Logged('3', 3723000000, "[sensors] bye");
  return log;
}

class UlogSynthetic : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = testing::MakeTempDir(); }
  std::string Path(const std::string& name) const { return dir_ + "/" + name; }
  std::string dir_;
};

TEST(UlogFormat, FlattensNestedArraysAndPadding) {
  std::map<std::string, ulog::MessageFormat> formats;
  for (const char* text : {kInner, kTestTopic}) {
    ulog::MessageFormat f;
    std::string error;
    ASSERT_TRUE(ulog::ParseMessageFormat(text, &f, &error)) << error;
    formats[f.name] = f;
  }
  ulog::FlatLayout layout;
  std::string error;
  ASSERT_TRUE(ulog::FlattenFormat(formats, "test_topic", &layout, &error)) << error;
  EXPECT_EQ(layout.full_size, 52);
  EXPECT_EQ(layout.logged_size, 46);
  EXPECT_EQ(layout.timestamp_offset, 0);
  ASSERT_NE(layout.Find("items[1].w[1]"), nullptr);
  EXPECT_EQ(layout.Find("items[1].w[1]")->offset, 28);
  EXPECT_EQ(layout.Find("flag")->offset, 32);
  EXPECT_EQ(layout.Find("_padding0[2]")->offset, 35);  // inner padding kept for offsets
  EXPECT_EQ(layout.Find("d")->offset, 36);
  EXPECT_EQ(layout.Find("s[1]")->offset, 45);
  EXPECT_EQ(layout.Find("_padding1[0]"), nullptr);  // trailing padding dropped
  // Unknown nested type and self-nesting are errors, not crashes.
  formats["loop"] = {"loop", {{"loop", 0, "again"}}};
  EXPECT_FALSE(ulog::FlattenFormat(formats, "loop", &layout, &error));
  EXPECT_FALSE(ulog::FlattenFormat(formats, "missing", &layout, &error));
  ulog::MessageFormat bad;
  EXPECT_FALSE(ulog::ParseMessageFormat("x:float[] a;", &bad, &error));
  EXPECT_FALSE(ulog::ParseMessageFormat("no_colon", &bad, &error));
}

TEST_F(UlogSynthetic, ReadsNestedFieldsAndInstances) {
  const std::string path = NestedLog().Write(Path("nested.ulg"));
  const UlogInfo info = ReadUlogInfo(path);
  EXPECT_EQ(info.version, 1);
  EXPECT_EQ(info.t_start_us, 1000000u);
  EXPECT_EQ(info.t_last_us, 2030005u);
  EXPECT_EQ(info.info.at("sys_name"), "PX4");
  EXPECT_EQ(info.info.at("answer"), "-7");
  EXPECT_EQ(info.dropouts_ms, std::vector<int>{25});
  EXPECT_TRUE(info.notes.empty());
  ASSERT_EQ(info.topics.size(), 3u);
  EXPECT_EQ(info.topics[0].name, "sensor_combined");
  EXPECT_EQ(info.topics[1].name, "sensor_combined");
  EXPECT_EQ(info.topics[1].multi_id, 1);
  EXPECT_EQ(info.topics[2].name, "test_topic");
  EXPECT_EQ(info.topics[2].message_size, 46);
  EXPECT_EQ(info.topics[2].messages, 4u);
  EXPECT_EQ(FormatUlogInfoTopicTable(info),
            "Name (multi id, message size in bytes)    number of data points, total bytes\n"
            " sensor_combined (0, 36)                        4        144\n"
            " sensor_combined (1, 36)                        4        144\n"
            " test_topic (0, 46)                             4        184\n");
  EXPECT_EQ(FormatUlogInfoTimeAndDropouts(info),
            "Logging start time: 0:00:01, duration: 0:00:01\n"
            "Dropouts: count: 1, total duration: 0.0 s, max: 25 ms, mean: 25 ms\n");
  EXPECT_EQ(FormatUlogLoggedStrings(info),
            "0:00:01 INFO: [commander] hello\n1:02:03 ERROR: [sensors] bye\n");

  const ulog::TopicTable table = ulog::ReadTopicFields(
      path, "test_topic",
      {{"items[1].id"}, {"items[1].w[1]"}, {"flag"}, {"d"}, {"s[0]"}, {"nope", false}}, {});
  ASSERT_EQ(table.rows(), 4u);
  for (int k = 0; k < 4; ++k) {
    EXPECT_EQ(table.t_us[k], 2000000u + 10000u * k);
    EXPECT_EQ(table.at(k, 0), 100 * k + 1);
    EXPECT_FLOAT_EQ(table.at(k, 1), -k - 0.5f);
    EXPECT_EQ(table.at(k, 2), k % 2);
    EXPECT_EQ(table.at(k, 3), 1e9 + k);
    EXPECT_EQ(table.at(k, 4), -k);
    EXPECT_TRUE(std::isnan(table.at(k, 5)));
  }
  EXPECT_FALSE(table.has(5));
}

TEST_F(UlogSynthetic, ImuInstancesAreConvertedFromFrdToFlu) {
  const std::string path = NestedLog().Write(Path("imu.ulg"));
  const std::vector<ImuSample> imu0 = ReadUlogImu(path, "sensor_combined");
  ASSERT_EQ(imu0.size(), 4u);
  EXPECT_EQ(imu0[2].t_ns, 2020000000);
  EXPECT_TRUE(imu0[2].gyro_rad_s.isApprox(Eigen::Vector3d(0.2, -0.2, 0.3), 1e-6));
  EXPECT_NEAR(imu0[0].accel_m_s2.x(), 0.5, 1e-6);
  EXPECT_NEAR(imu0[0].accel_m_s2.y(), 0.25, 1e-6);
  EXPECT_NEAR(imu0[0].accel_m_s2.z(), 9.81, 1e-5);
  const std::vector<ImuSample> imu1 = ReadUlogImu(path, "sensor_combined.1");
  ASSERT_EQ(imu1.size(), 4u);
  EXPECT_EQ(imu1[0].t_ns, 2000005000);
  EXPECT_TRUE(imu1[0].gyro_rad_s.isApprox(Eigen::Vector3d(1, -2, -3)));
  EXPECT_TRUE(imu1[0].accel_m_s2.isApprox(Eigen::Vector3d(4, -5, -6)));
  EXPECT_THROW(ReadUlogImu(path, "sensor_combined.2"), InputError);
}

TEST_F(UlogSynthetic, WrongSizeAndUnknownIdsAreSkippedWithNotes) {
  UlogBytes log = NestedLog();
  std::vector<uint8_t> short_payload = NestedPayload(5000000, 9, false);
  short_payload.pop_back();  // 45 bytes: less than the 46 logged bytes
  log.Data(3, short_payload);
  log.Data(77, {1, 2, 3});         // no subscription
  log.Message('Z', {1, 2, 3, 4});  // unknown type: skipped (future message types)
  log.Data(3, NestedPayload(6000000, 5, false));
  const UlogInfo info = ReadUlogInfo(log.Write(Path("corrupt.ulg")));
  ASSERT_EQ(info.topics.size(), 3u);
  EXPECT_EQ(info.topics[2].messages, 5u);
  EXPECT_EQ(info.notes.size(), 3u);
}

TEST_F(UlogSynthetic, ImpossibleHeaderResynchronisesAtTheNextSync) {
  UlogBytes log = NestedLog();
  log.Message('\0', {});  // type 0, size 0: an impossible header
  log.bytes().insert(log.bytes().end(), {0x13, 0x37, 0x00, 0xFF});
  log.Sync();
  log.Data(3, NestedPayload(7000000, 6, false));
  const UlogInfo info = ReadUlogInfo(log.Write(Path("resync.ulg")));
  EXPECT_EQ(info.topics[2].messages, 5u);
  ASSERT_EQ(info.notes.size(), 1u);
  EXPECT_NE(info.notes[0].find("sync"), std::string::npos);
}

TEST_F(UlogSynthetic, AppendedDataSegmentsAreRead) {
  // The main log is cut mid-message at the appended offset (the logger stopped there); the
  // appended segment starts exactly at the offset, as PX4 writes crash dumps after the log.
  UlogBytes log;
  log.FlagBits(1, {0});  // offset patched below
  log.Format(kInner);
  log.Format(kTestTopic);
  log.Add(0, 3, "test_topic");
  log.Data(3, NestedPayload(2000000, 0, false));
  log.Data(3, NestedPayload(2010000, 1, false));
  const size_t cut = log.size() - 10;  // inside the second data message
  log.bytes().resize(cut);
  const size_t appended = log.size();
  log.Data(3, NestedPayload(2020000, 2, false));
  std::memcpy(log.bytes().data() + 16 + 3 + 16, &appended, 8);
  const UlogInfo info = ReadUlogInfo(log.Write(Path("appended.ulg")));
  EXPECT_TRUE(info.data_appended);
  EXPECT_EQ(info.appended_offsets, std::vector<uint64_t>{appended});
  ASSERT_EQ(info.topics.size(), 1u);
  EXPECT_EQ(info.topics[0].messages, 2u);  // the cut message is not read
  EXPECT_EQ(info.t_last_us, 2020000u);
}

TEST_F(UlogSynthetic, UnknownIncompatibleFlagIsAnError) {
  UlogBytes log;
  log.FlagBits(0x2);
  try {
    ReadUlogInfo(log.Write(Path("flags.ulg")));
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("byte offset 16"), std::string::npos) << e.what();
  }
}

TEST_F(UlogSynthetic, AttitudeAndLocalPositionFrames) {
  UlogBytes log;
  log.FlagBits(0);
  log.Format("vehicle_attitude:uint64_t timestamp;float[4] q;");
  log.Format(
      "vehicle_local_position:uint64_t timestamp;float x;float y;float z;float vx;float "
      "vy;float vz;bool xy_valid;bool z_valid;bool v_xy_valid;bool v_z_valid;");
  log.Add(0, 0, "vehicle_attitude");
  log.Add(0, 1, "vehicle_local_position");
  // Level, nose east: in NED a yaw of +90 deg about down. In ENU facing east is yaw 0, so the
  // converted q_W_B is the identity (FLU body x = east = ENU x).
  const double h = std::sqrt(0.5);
  std::vector<uint8_t> att;
  UlogBytes::PutTo(&att, uint64_t{1000});
  for (const double c : {h, 0.0, 0.0, h}) UlogBytes::PutTo(&att, static_cast<float>(c));
  log.Data(0, att);
  // Nose north, rolled right wing down by 30 deg (FRD roll +30 deg about x north).
  const Eigen::Quaterniond q_roll(Eigen::AngleAxisd(M_PI / 6, Eigen::Vector3d::UnitX()));
  att.clear();
  UlogBytes::PutTo(&att, uint64_t{2000});
  for (const double c : {q_roll.w(), q_roll.x(), q_roll.y(), q_roll.z()}) {
    UlogBytes::PutTo(&att, static_cast<float>(c));
  }
  log.Data(0, att);
  std::vector<uint8_t> pos;
  UlogBytes::PutTo(&pos, uint64_t{1500});
  for (const float c : {1.0f, 2.0f, -3.0f, 0.1f, 0.2f, -0.3f}) UlogBytes::PutTo(&pos, c);
  pos.insert(pos.end(), {1, 1, 1, 1});
  log.Data(1, pos);
  const std::string path = log.Write(Path("frames.ulg"));

  const LogTrajectory attitude = ReadUlogTrajectory(Spec(path, "vehicle_attitude"));
  ASSERT_EQ(attitude.states.size(), 2u);
  EXPECT_LT(RotationAngleBetween(attitude.states[0].T_W_B.q, Eigen::Quaterniond::Identity()), 1e-6);
  // Nose north = ENU +y; right wing down means the FLU left wing (+y body) points up-ish.
  const Eigen::Matrix3d R = attitude.states[1].T_W_B.R();
  EXPECT_TRUE(R.col(0).isApprox(Eigen::Vector3d(0, 1, 0), 1e-6));
  EXPECT_NEAR(R.col(1).z(), std::sin(M_PI / 6), 1e-6);
  EXPECT_EQ(attitude.source, path + ":vehicle_attitude");

  const LogTrajectory local = ReadUlogTrajectory(Spec(path, "vehicle_local_position"));
  ASSERT_EQ(local.states.size(), 1u);
  EXPECT_TRUE(local.states[0].T_W_B.p.isApprox(Eigen::Vector3d(2, 1, 3)));
  EXPECT_TRUE(local.has_velocity);
  EXPECT_TRUE(local.states[0].v_W.isApprox(Eigen::Vector3d(0.2, 0.1, 0.3), 1e-6));
  EXPECT_TRUE(local.covariance.empty());
}

TEST_F(UlogSynthetic, OdometryWithVariancesAndBodyVelocity) {
  UlogBytes log;
  log.FlagBits(0);
  log.Format(
      "vehicle_visual_odometry:uint64_t timestamp;uint64_t timestamp_sample;uint8_t "
      "pose_frame;float[3] position;float[4] q;uint8_t velocity_frame;float[3] "
      "velocity;float[3] angular_velocity;float[3] position_variance;float[3] "
      "orientation_variance;float[3] velocity_variance;uint8_t reset_counter;int8_t "
      "quality;");
  log.Add(0, 0, "vehicle_visual_odometry");
  const double h = std::sqrt(0.5);
  std::vector<uint8_t> p;
  UlogBytes::PutTo(&p, uint64_t{5000});
  UlogBytes::PutTo(&p, uint64_t{4000});
  p.push_back(1);  // NED
  for (const float c : {1.0f, 2.0f, -3.0f}) UlogBytes::PutTo(&p, c);
  for (const double c : {h, 0.0, 0.0, h}) UlogBytes::PutTo(&p, static_cast<float>(c));  // east
  p.push_back(3);  // body FRD velocity
  for (const float c : {1.0f, 0.0f, 0.0f, 0.f, 0.f, 0.f}) UlogBytes::PutTo(&p, c);
  for (const float c : {0.1f, 0.2f, 0.3f, 0.01f, 0.02f, 0.03f, 0.f, 0.f, 0.f}) {
    UlogBytes::PutTo(&p, c);
  }
  p.push_back(0);
  p.push_back(0);
  log.Data(0, p);
  const std::string path = log.Write(Path("odom.ulg"));
  const LogTrajectory odom = ReadUlogTrajectory(Spec(path, "vehicle_visual_odometry"));
  ASSERT_EQ(odom.states.size(), 1u);
  EXPECT_EQ(odom.parent_frame, "world_enu");
  EXPECT_EQ(odom.states[0].t_ns, 4000000);  // timestamp_sample
  EXPECT_TRUE(odom.states[0].T_W_B.p.isApprox(Eigen::Vector3d(2, 1, 3)));
  ASSERT_TRUE(odom.has_velocity);
  // Forward at 1 m/s while facing east.
  EXPECT_TRUE(odom.states[0].v_W.isApprox(Eigen::Vector3d(1, 0, 0), 1e-6));
  ASSERT_EQ(odom.covariance.size(), 1u);
  EXPECT_NEAR(odom.covariance[0](0, 0), 0.2, 1e-7);  // east variance = NED y variance
  EXPECT_NEAR(odom.covariance[0](1, 1), 0.1, 1e-7);
  EXPECT_NEAR(odom.covariance[0](2, 2), 0.3, 1e-7);
  EXPECT_NEAR(odom.covariance[0](3, 3), 0.01, 1e-8);
}

// Cutting the log at every byte offset never crashes: a cut in the header or definitions is an
// InputError naming a byte offset; a cut in the data section keeps the complete messages and,
// when it falls inside a message, adds a "truncated" note.
TEST_F(UlogSynthetic, TruncationAtEveryByteOffset) {
  const UlogBytes log = NestedLog();
  const std::string full_path = log.Write(Path("full.ulg"));
  const UlogInfo full = ReadUlogInfo(full_path);
  uint64_t full_messages = 0;
  for (const UlogTopicInfo& t : full.topics) full_messages += t.messages;
  const std::string path = Path("cut.ulg");
  int errors = 0, notes = 0, clean = 0;
  for (size_t length = 0; length < log.size(); ++length) {
    log.Write(path, length);
    try {
      const UlogInfo info = ReadUlogInfo(path);
      uint64_t messages = 0;
      for (const UlogTopicInfo& t : info.topics) messages += t.messages;
      EXPECT_LE(messages, full_messages);
      bool truncated = false;
      for (const std::string& n : info.notes) {
        if (n.find("truncated") != std::string::npos) {
          truncated = true;
          EXPECT_NE(n.find("byte offset"), std::string::npos);
        }
      }
      truncated ? ++notes : ++clean;
      // The IMU reader sees the same prefix: a sample list or a clear error (topic absent yet).
      try {
        const std::vector<ImuSample> imu = ReadUlogImu(path, "sensor_combined");
        EXPECT_LE(imu.size(), 4u);
      } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("sensor_combined"), std::string::npos);
      }
    } catch (const InputError& e) {
      ++errors;
      const std::string what = e.what();
      EXPECT_NE(what.find(path), std::string::npos) << what;
      EXPECT_NE(what.find("byte offset"), std::string::npos) << what;
    }
  }
  EXPECT_GT(errors, 0);
  EXPECT_GT(notes, 0);
  EXPECT_GT(clean, 0);
}

// Regression (fuzz_ulog, UBSan signed-integer-overflow in SummarizeUlog): a data message stamped
// beyond what 1000 * t_us can hold in int64 ns is a corrupt message, skipped with a note; the
// summary and the IMU reader see only the valid ones.
TEST_F(UlogSynthetic, StampTooLargeForNanosecondsIsACorruptMessage) {
  UlogBytes log = NestedLog();
  log.Data(1, SensorCombinedPayload(9151594818294213574ull, {1, 2, 3}, {4, 5, 6}));
  log.Data(1, SensorCombinedPayload(ulog::kMaxStampUs, {1, 2, 3}, {4, 5, 6}));
  const std::string path = log.Write(Path("huge_stamp.ulg"));
  const UlogInfo info = ReadUlogInfo(path);
  bool corrupt_note = false;
  for (const std::string& n : info.notes)
    corrupt_note = corrupt_note || n.find("2 data message(s) with a timestamp beyond the range") !=
                                       std::string::npos;
  EXPECT_TRUE(corrupt_note);
  const LogSummary summary = SummarizeUlog(path);
  EXPECT_EQ(summary.t_end_ns, 2030005000);  // the last valid stamp (instance 1)
  EXPECT_EQ(ReadUlogImu(path, "sensor_combined").size(), 4u);
  // The last stamp kept is within limits::kMaxTimestampNs (2^62 ns), as every other reader's.
  EXPECT_EQ(ulog::StampNs(ulog::kMaxStampUs - 1), int64_t{4'611'686'018'427'387'000});
  EXPECT_LE(*ulog::StampNs(ulog::kMaxStampUs - 1), limits::kMaxTimestampNs);
  EXPECT_FALSE(ulog::StampNsOfField(std::nan("")));
  EXPECT_FALSE(ulog::StampNsOfField(-1.0));
  EXPECT_FALSE(ulog::StampNsOfField(1e300));
}

TEST_F(UlogSynthetic, HeaderStampTooLargeIsAnError) {
  UlogBytes log(1, ~uint64_t{0});
  log.FlagBits(0);
  const std::string path = log.Write(Path("huge_header_stamp.ulg"));
  try {
    ReadUlogInfo(path);
    ADD_FAILURE() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("byte offset 8"), std::string::npos) << e.what();
  }
}

// Regression (UBSan float-cast-overflow in ulog_trajectory.cc): frame codes and timestamp_sample
// held in float fields of a corrupt log (NaN, 1e30, beyond int64 ns) are compared or checked as
// doubles, never cast: a corrupt stamp skips the message, an unknown velocity frame drops the
// velocities, an unknown pose frame is an InputError.
TEST_F(UlogSynthetic, FloatFrameCodesAndHugeSampleStampsAreNotCast) {
  const auto odometry_log = [](float pose_frame, float velocity_frame) {
    UlogBytes log;
    log.FlagBits(0);
    log.Format(
        "vehicle_odometry:uint64_t timestamp;double timestamp_sample;float pose_frame;float[3] "
        "position;float[4] q;float velocity_frame;float[3] velocity;");
    log.Add(0, 0, "vehicle_odometry");
    for (const double t_sample_us : {1e30, 4000.0}) {
      std::vector<uint8_t> p;
      UlogBytes::PutTo(&p, uint64_t{5000});
      UlogBytes::PutTo(&p, t_sample_us);
      UlogBytes::PutTo(&p, pose_frame);
      for (const float c : {1.0f, 2.0f, -3.0f, 1.0f, 0.0f, 0.0f, 0.0f}) UlogBytes::PutTo(&p, c);
      UlogBytes::PutTo(&p, velocity_frame);
      for (const float c : {1.0f, 0.0f, 0.0f}) UlogBytes::PutTo(&p, c);
      log.Data(0, p);
    }
    return log;
  };
  const std::string path = odometry_log(1.0f, std::nanf("")).Write(Path("nan_frame.ulg"));
  const LogTrajectory odom = ReadUlogTrajectory(Spec(path, "vehicle_odometry"));
  ASSERT_EQ(odom.states.size(), 1u);  // the 1e30 us stamp is skipped
  EXPECT_EQ(odom.states[0].t_ns, 4000000);
  EXPECT_FALSE(odom.has_velocity);
  const std::string bad_pose = odometry_log(1e30f, 1.0f).Write(Path("huge_frame.ulg"));
  EXPECT_THROW(ReadUlogTrajectory(Spec(bad_pose, "vehicle_odometry")), InputError);
  const std::string half = odometry_log(1.5f, 1.0f).Write(Path("half_frame.ulg"));
  EXPECT_THROW(ReadUlogTrajectory(Spec(half, "vehicle_odometry")), InputError);
}

}  // namespace
}  // namespace mavloc
