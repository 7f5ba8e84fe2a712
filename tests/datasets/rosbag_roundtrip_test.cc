// Synthetic ROS1 bags written here with Debian's rosbag::Bag (uncompressed, bz2 and lz4 chunks, and
// a whole-file bzip2 copy) and read back through rosbag_reader.h: every supported message type,
// the summary, and the errors (missing topic, wrong type, foreign MD5, truncated bag).
#include <bzlib.h>
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <rosbag/bag.h>

#include <unistd.h>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>

#include "core/errors.h"
#include "core/image_codec.h"
#include "datasets/io/rosbag/bag_records.h"
#include "datasets/io/rosbag/ros_messages.h"
#include "datasets/io/rosbag/rosbag_reader.h"
#include "datasets/io/rosbag/rosbag_tag_messages.h"
#include "tests/test_support.h"

namespace fs = std::filesystem;

namespace mavloc {
namespace {

using namespace ros1;

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

constexpr int kMessages = 40;
constexpr uint32_t kStartSec = 1'600'000'000;

ros::Time Stamp(int i) {
  return ros::Time(kStartSec + static_cast<uint32_t>(i / 10), 100'000'000u * (i % 10) + 7);
}
TimeNs StampNs(int i) { return ToNs(Stamp(i)); }

template <class S>
S Text(const std::string& text) {
  return S(text.begin(), text.end());
}

Eigen::Quaterniond TestRotation(int i) {
  return Eigen::Quaterniond(Eigen::AngleAxisd(0.1 * i, Eigen::Vector3d(1, 2, 3).normalized()));
}

template <class PoseMsg>
void SetPose(int i, PoseMsg* pose) {
  const Eigen::Quaterniond q = TestRotation(i);
  pose->position.x = 0.5 * i;
  pose->position.y = -0.25 * i;
  pose->position.z = 1.0 + 0.01 * i;
  pose->orientation.w = q.w();
  pose->orientation.x = q.x();
  pose->orientation.y = q.y();
  pose->orientation.z = q.z();
}

// Writes every supported type, kMessages of each (images: 3), with the given chunk compression.
void WriteTestBag(const std::string& path, rosbag::compression::CompressionType compression) {
  rosbag::Bag bag(path, rosbag::bagmode::Write);
  bag.setCompression(compression);
  bag.setChunkThreshold(4096);  // many chunks
  for (int i = 0; i < kMessages; ++i) {
    const ros::Time t = Stamp(i);
    ImuMsg imu;
    imu.header.stamp = t;
    imu.angular_velocity.x = 0.01 * i;
    imu.angular_velocity.y = -0.02;
    imu.angular_velocity.z = 0.3;
    imu.linear_acceleration.x = 0.1;
    imu.linear_acceleration.y = 0.2 * i;
    imu.linear_acceleration.z = 9.81;
    bag.write("/imu", t, imu);

    PoseStampedMsg pose;
    pose.header.stamp = t;
    pose.header.frame_id = Text<decltype(pose.header.frame_id)>("/world");
    SetPose(i, &pose.pose);
    bag.write("/pose", t, pose);

    PoseWithCovarianceStampedMsg pose_cov;
    pose_cov.header = pose.header;
    SetPose(i, &pose_cov.pose.pose);
    for (int k = 0; k < 36; ++k) pose_cov.pose.covariance[k] = k % 7 == 0 ? 0.01 * (k + 1) : 0.0;
    bag.write("/pose_cov", t, pose_cov);

    OdometryMsg odom;
    odom.header.stamp = t;
    odom.header.frame_id = Text<decltype(odom.header.frame_id)>("odom");
    odom.child_frame_id = Text<decltype(odom.child_frame_id)>("base_link");
    SetPose(i, &odom.pose.pose);  // covariance left all zero: "not filled in"
    odom.twist.twist.linear.x = 1.0;
    odom.twist.twist.linear.y = 0.5;
    odom.twist.twist.linear.z = -0.25 * i;
    bag.write("/odom", t, odom);

    TfMessageMsg tf;
    for (const char* child : {"camera", "body"}) {
      geometry_msgs::TransformStamped_<Alloc> transform;
      transform.header.stamp = t;
      transform.header.frame_id = Text<decltype(transform.header.frame_id)>("map");
      transform.child_frame_id = Text<decltype(transform.child_frame_id)>(child);
      transform.transform.translation.x = 0.5 * i + (child[0] == 'c' ? 100.0 : 0.0);
      transform.transform.translation.y = -0.25 * i;
      transform.transform.translation.z = 1.0 + 0.01 * i;
      const Eigen::Quaterniond q = TestRotation(i);
      transform.transform.rotation.w = q.w();
      transform.transform.rotation.x = q.x();
      transform.transform.rotation.y = q.y();
      transform.transform.rotation.z = q.z();
      tf.transforms.push_back(transform);
    }
    bag.write("/tf", t, tf);

    ApriltagArrayStampedMsg tags;
    tags.header.stamp = t;
    for (int id : {3, 8}) {
      ApriltagMsg tag;
      tag.id = id;
      tag.family = "36h11";
      for (int c = 0; c < 4; ++c) {
        tag.corners[c].x = 100.0 * id + 10.0 * c + i;
        tag.corners[c].y = 50.0 + c;
      }
      tags.apriltags.push_back(tag);
    }
    bag.write("/tags", t, tags);

    AprilTagDetectionArrayMsg detections;
    detections.header.stamp = t;
    AprilTagDetectionMsg detection;
    detection.id.push_back(5);
    detection.size.push_back(0.2);
    detection.pose.pose.pose.position.x = 0.1;
    detection.pose.pose.pose.position.y = -0.05;
    detection.pose.pose.pose.position.z = 1.0 + 0.01 * i;
    detection.pose.pose.pose.orientation.w = 1.0;
    detections.detections.push_back(detection);
    AprilTagDetectionMsg bundle = detection;  // a bundle: skipped
    bundle.id.push_back(6);
    bundle.size.push_back(0.2);
    detections.detections.push_back(bundle);
    bag.write("/tag_detections", t, detections);

    if (i < 3) {
      CameraInfoMsg info;
      info.header.stamp = t;
      info.width = 752;
      info.height = 480;
      info.distortion_model = Text<decltype(info.distortion_model)>("plumb_bob");
      info.D = {-0.28, 0.07, 0.0002, 1.7e-05, 0.0};
      info.K = {458.654, 0, 367.215, 0, 457.296, 248.375, 0, 0, 1};
      bag.write("/camera_info", t, info);

      CameraInfoMsg fisheye = info;
      fisheye.distortion_model = Text<decltype(info.distortion_model)>("equidistant");
      fisheye.D = {0.0013, 0.0305, -0.0288, 0.0034};
      bag.write("/fisheye_info", t, fisheye);

      ImageMsg mono;
      mono.header.stamp = t;
      mono.width = 5;
      mono.height = 3;
      mono.encoding = Text<decltype(mono.encoding)>("mono8");
      mono.step = 8;  // padded rows
      mono.data.resize(24);
      for (size_t k = 0; k < mono.data.size(); ++k) mono.data[k] = static_cast<uint8_t>(10 * k + i);
      bag.write("/mono", t, mono);

      ImageMsg rgb = mono;
      rgb.encoding = Text<decltype(rgb.encoding)>("rgb8");
      rgb.step = 15;
      rgb.data.resize(45);
      for (size_t k = 0; k < rgb.data.size(); ++k)
        rgb.data[k] = static_cast<uint8_t>(k % 3 == 0 ? 200 : k % 3 == 1 ? 100 : 50);
      bag.write("/rgb", t, rgb);

      ImageMsg mono16 = mono;
      mono16.encoding = Text<decltype(mono16.encoding)>("mono16");
      mono16.is_bigendian = 1;
      mono16.step = 10;
      mono16.data.assign(30, 0);
      mono16.data[0] = 0x12;  // big-endian 0x1234 at pixel (0, 0)
      mono16.data[1] = 0x34;
      bag.write("/mono16", t, mono16);

      cv::Mat source(4, 6, CV_8UC1, cv::Scalar(77 + i));
      const std::string png = EncodePng(source);
      CompressedImageMsg compressed;
      compressed.header.stamp = t;
      compressed.format = Text<decltype(compressed.format)>("png");
      compressed.data.assign(png.begin(), png.end());
      bag.write("/compressed", t, compressed);
    }
  }
  bag.close();
}

// Whole-file bzip2 of `path` written with libbz2.
void Bzip2File(const std::string& path, const std::string& out) {
  std::ifstream in(path, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), {});
  std::vector<char> compressed(bytes.size() + bytes.size() / 100 + 600);
  unsigned int size = static_cast<unsigned int>(compressed.size());
  ASSERT_EQ(BZ2_bzBuffToBuffCompress(compressed.data(), &size, const_cast<char*>(bytes.data()),
                                     static_cast<unsigned int>(bytes.size()), 9, 0, 0),
            BZ_OK);
  std::ofstream(out, std::ios::binary).write(compressed.data(), size);
}

class RosbagRoundTrip : public ::testing::TestWithParam<std::string> {
 protected:
  // One bag per compression kind, written once per process (the tests only read it; ctest runs
  // each test in its own process).
  void SetUp() override {
    dir_ = testing::MakeTempDir();
    static std::map<std::string, std::string> written;
    const std::string kind = GetParam();
    if (written.count(kind) == 0) {
      std::string path = dir_ + "/test.bag";
      WriteTestBag(path, kind == "bz2"   ? rosbag::compression::BZ2
                         : kind == "lz4" ? rosbag::compression::LZ4
                                         : rosbag::compression::Uncompressed);
      if (kind == "whole-file-bz2") {
        Bzip2File(path, path + ".bz2");
        fs::remove(path);
        path += ".bz2";
      }
      written[kind] = path;
    }
    path_ = written[kind];
  }
  std::string dir_, path_;
};

TEST_P(RosbagRoundTrip, Summary) {
  EXPECT_TRUE(IsRosbagFile(path_));
  const LogSummary summary = SummarizeRosbag(path_);
  EXPECT_EQ(summary.format, LogFormat::kRosbag);
  ASSERT_EQ(summary.topics.size(), 13u);
  std::map<std::string, LogTopicSummary> by_topic;
  for (const auto& topic : summary.topics) by_topic[topic.topic] = topic;
  EXPECT_EQ(summary.topics.front().topic, "/camera_info");  // sorted by name
  EXPECT_EQ(by_topic["/imu"].type, "sensor_msgs/Imu");
  EXPECT_EQ(by_topic["/imu"].messages, static_cast<uint64_t>(kMessages));
  EXPECT_EQ(by_topic["/imu"].t_first_ns, StampNs(0));
  EXPECT_EQ(by_topic["/imu"].t_last_ns, StampNs(kMessages - 1));
  EXPECT_EQ(by_topic["/mono"].messages, 3u);
  EXPECT_EQ(by_topic["/tags"].type, "apriltag_msgs/ApriltagArrayStamped");
  EXPECT_EQ(summary.t_start_ns, StampNs(0));
  EXPECT_EQ(summary.t_end_ns, StampNs(kMessages - 1));
  const std::string kind = GetParam();
  const std::string chunk_kind = kind == "bz2" ? "bz2" : kind == "lz4" ? "lz4" : "none";
  bool chunk_note = false, whole_file_note = false;
  for (const std::string& note : summary.notes) {
    if (note.rfind("chunks: ", 0) == 0) {
      chunk_note = true;
      EXPECT_NE(note.find(" " + chunk_kind), std::string::npos) << note;
      EXPECT_EQ(note.find(","), std::string::npos) << note;  // one compression kind
    }
    whole_file_note = whole_file_note || note.find("whole-file bzip2") != std::string::npos;
  }
  EXPECT_TRUE(chunk_note);
  EXPECT_EQ(whole_file_note, kind == "whole-file-bz2");
}

TEST_P(RosbagRoundTrip, Imu) {
  const auto samples = ReadRosbagImu(path_, "/imu");
  ASSERT_EQ(samples.size(), static_cast<size_t>(kMessages));
  for (int i = 0; i < kMessages; ++i) {
    EXPECT_EQ(samples[i].t_ns, StampNs(i));
    EXPECT_EQ(samples[i].gyro_rad_s, Eigen::Vector3d(0.01 * i, -0.02, 0.3));
    EXPECT_EQ(samples[i].accel_m_s2, Eigen::Vector3d(0.1, 0.2 * i, 9.81));
  }
}

TEST_P(RosbagRoundTrip, Trajectories) {
  for (const char* topic : {"/pose", "/pose_cov", "/odom"}) {
    const LogTrajectory trajectory = ReadRosbagTrajectory(Spec(path_, topic));
    ASSERT_EQ(trajectory.states.size(), static_cast<size_t>(kMessages)) << topic;
    EXPECT_EQ(trajectory.source, path_ + ":" + topic);
    for (int i = 0; i < kMessages; ++i) {
      const GroundTruthState& s = trajectory.states[i];
      EXPECT_EQ(s.t_ns, StampNs(i));
      EXPECT_TRUE(s.T_W_B.p.isApprox(Eigen::Vector3d(0.5 * i, -0.25 * i, 1.0 + 0.01 * i)));
      EXPECT_LT(RotationAngleBetween(s.T_W_B.q, TestRotation(i)), 1e-12);
    }
  }
  const LogTrajectory pose = ReadRosbagTrajectory(Spec(path_, "/pose"));
  EXPECT_EQ(pose.parent_frame, "world");  // leading '/' dropped
  EXPECT_FALSE(pose.has_velocity);
  EXPECT_TRUE(pose.covariance.empty());

  const LogTrajectory pose_cov = ReadRosbagTrajectory(Spec(path_, "/pose_cov"));
  ASSERT_EQ(pose_cov.covariance.size(), static_cast<size_t>(kMessages));
  EXPECT_DOUBLE_EQ(pose_cov.covariance[3](0, 0), 0.01);
  EXPECT_DOUBLE_EQ(pose_cov.covariance[3](1, 1), 0.08);  // row-major index 7
  EXPECT_DOUBLE_EQ(pose_cov.covariance[3](5, 5), 0.36);  // index 35
  EXPECT_DOUBLE_EQ(pose_cov.covariance[3](0, 1), 0.0);

  const LogTrajectory odom = ReadRosbagTrajectory(Spec(path_, "/odom"));
  EXPECT_EQ(odom.type, "nav_msgs/Odometry");
  EXPECT_EQ(odom.parent_frame, "odom");
  EXPECT_EQ(odom.child_frame, "base_link");
  EXPECT_TRUE(odom.has_velocity);
  EXPECT_TRUE(odom.covariance.empty());  // all zero: not filled in
  for (int i = 0; i < kMessages; ++i) {
    const Eigen::Vector3d v_B(1.0, 0.5, -0.25 * i);
    EXPECT_TRUE(odom.states[i].v_W.isApprox(TestRotation(i) * v_B, 1e-12));
  }

  const LogTrajectory tf = ReadRosbagTrajectory(Spec(path_, "/tf", "/map", "body"));
  ASSERT_EQ(tf.states.size(), static_cast<size_t>(kMessages));
  EXPECT_EQ(tf.parent_frame, "map");
  EXPECT_EQ(tf.child_frame, "body");
  EXPECT_TRUE(tf.states[7].T_W_B.p.isApprox(Eigen::Vector3d(3.5, -1.75, 1.07)));
  const LogTrajectory camera = ReadRosbagTrajectory(Spec(path_, "/tf", "map", "camera"));
  EXPECT_DOUBLE_EQ(camera.states[0].T_W_B.p.x(), 100.0);
  EXPECT_THROW(ReadRosbagTrajectory(Spec(path_, "/tf", "map", "nowhere")), InputError);
  EXPECT_THROW(ReadRosbagTrajectory(Spec(path_, "/tf")), InputError);
}

TEST_P(RosbagRoundTrip, TagsBothLayouts) {
  const auto tags = ReadRosbagTags(path_, "/tags", 1);
  ASSERT_EQ(tags.size(), 2u * kMessages);
  EXPECT_EQ(tags[2].t_ns, StampNs(1));
  EXPECT_EQ(tags[2].tag_id, 3);
  EXPECT_EQ(tags[3].tag_id, 8);
  EXPECT_EQ(tags[3].camera, 1);
  for (int k = 0; k < 4; ++k) {  // mavloc corner k = message corner k
    EXPECT_EQ(tags[3].corners_px[k], Eigen::Vector2d(800.0 + 10.0 * k + 1, 50.0 + k));
  }

  EXPECT_THROW(ReadRosbagTags(path_, "/tag_detections", 0), InputError);  // no camera model
  const CameraModel camera(752, 480, Eigen::Vector4d(400, 410, 376, 240),
                           DistortionModel::kRadialTangential, {-0.3, 0.1, 0, 0});
  const auto projected = ReadRosbagTags(path_, "/tag_detections", 0, camera);
  ASSERT_EQ(projected.size(), static_cast<size_t>(kMessages));  // bundles skipped
  const auto& first = projected.front();
  EXPECT_EQ(first.tag_id, 5);
  // Tag at (0.1, -0.05, 1.0), identity rotation, 0.2 m: corner 0 at (0, -0.15, 1) -> pinhole K.
  EXPECT_TRUE(first.corners_px[0].isApprox(Eigen::Vector2d(376.0, 240.0 - 0.15 * 410), 1e-12));
  EXPECT_TRUE(
      first.corners_px[2].isApprox(Eigen::Vector2d(376.0 + 0.2 * 400, 240.0 + 0.05 * 410), 1e-12));
}

TEST_P(RosbagRoundTrip, CameraInfo) {
  const CameraModel radtan = ReadRosbagCameraInfo(path_, "/camera_info");
  EXPECT_EQ(radtan.width(), 752);
  EXPECT_EQ(radtan.height(), 480);
  EXPECT_EQ(radtan.intrinsics(), Eigen::Vector4d(458.654, 457.296, 367.215, 248.375));
  EXPECT_EQ(radtan.distortion_model(), DistortionModel::kRadialTangential);
  EXPECT_EQ(radtan.distortion(), (std::array<double, 4>{-0.28, 0.07, 0.0002, 1.7e-05}));
  const CameraModel equi = ReadRosbagCameraInfo(path_, "/fisheye_info");
  EXPECT_EQ(equi.distortion_model(), DistortionModel::kEquidistant);
  EXPECT_EQ(equi.distortion(), (std::array<double, 4>{0.0013, 0.0305, -0.0288, 0.0034}));
}

TEST_P(RosbagRoundTrip, Images) {
  for (const char* topic : {"/mono", "/rgb", "/mono16", "/compressed"}) {
    const std::string out = dir_ + "/images" + topic;
    fs::create_directories(out);
    const auto frames = ExportRosbagImages(path_, topic, out);
    ASSERT_EQ(frames.size(), 3u) << topic;
    for (int i = 0; i < 3; ++i) {
      EXPECT_EQ(frames[i].t_ns, StampNs(i));
      EXPECT_EQ(frames[i].image_path,
                fs::absolute(out).string() + fmt::format("/{}.png", StampNs(i)));
    }
    std::string why;
    const cv::Mat image = DecodeImage(testing::ReadFileBytes(frames[1].image_path),
                                      ImageDecodeMode::kUnchanged, &why);
    ASSERT_FALSE(image.empty()) << topic;
    const std::string name = topic;
    if (name == "/mono") {
      ASSERT_EQ(image.type(), CV_8UC1);
      EXPECT_EQ(image.cols, 5);
      EXPECT_EQ(image.at<uint8_t>(1, 2), 10 * (8 + 2) + 1);  // row 1 starts at byte step = 8
    } else if (name == "/rgb") {
      ASSERT_EQ(image.type(), CV_8UC3);
      EXPECT_EQ(image.at<cv::Vec3b>(2, 4), cv::Vec3b(50, 100, 200));  // BGR
    } else if (name == "/mono16") {
      ASSERT_EQ(image.type(), CV_16UC1);
      EXPECT_EQ(image.at<uint16_t>(0, 0), 0x1234);
    } else {
      ASSERT_EQ(image.type(), CV_8UC1);
      EXPECT_EQ(image.rows, 4);
      EXPECT_EQ(image.at<uint8_t>(3, 5), 78);
    }
  }
}

TEST_P(RosbagRoundTrip, Errors) {
  try {
    ReadRosbagImu(path_, "/missing");
    FAIL() << "no error";
  } catch (const InputError& error) {
    const std::string what = error.what();
    EXPECT_NE(what.find(path_), std::string::npos) << what;
    EXPECT_NE(what.find("/missing is not in the bag"), std::string::npos) << what;
    EXPECT_NE(what.find("/imu"), std::string::npos) << what;  // the topics it has
  }
  try {
    ReadRosbagImu(path_, "/odom");
    FAIL() << "no error";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("nav_msgs/Odometry, not sensor_msgs/Imu"),
              std::string::npos)
        << error.what();
  }
  EXPECT_THROW(ReadRosbagTrajectory(Spec(path_, "/imu")), InputError);
  EXPECT_THROW(ReadRosbagTags(path_, "/imu", 0), InputError);
  EXPECT_THROW(ReadRosbagCameraInfo(path_, "/imu"), InputError);
  EXPECT_THROW(ExportRosbagImages(path_, "/imu", dir_), InputError);
}

INSTANTIATE_TEST_SUITE_P(Compression, RosbagRoundTrip,
                         ::testing::Values("none", "bz2", "lz4", "whole-file-bz2"),
                         [](const auto& param_info) {
                           std::string name = param_info.param;
                           std::replace(name.begin(), name.end(), '-', '_');
                           return name;
                         });

// A field the bag defines differently from mavloc's apriltag_msgs/ApriltagArrayStamped.
struct ForeignTagArray {
  HeaderMsg header;
  RosVector<int32_t> ids;
};

// An apriltag_msgs/ApriltagArrayStamped (same type, MD5 and definition) whose array length says
// 4e9 tags but that carries none: found by fuzz_rosbag, where ros::serialization resized the vector
// to the corrupt length (hundreds of gigabytes) before checking the message's size.
struct LyingTagArray {
  HeaderMsg header;
  uint32_t apriltags_length = 4'000'000'000u;
};

}  // namespace
}  // namespace mavloc

namespace ros::message_traits {
template <>
struct MD5Sum<mavloc::ForeignTagArray> {
  static const char* value() { return "0123456789abcdef0123456789abcdef"; }
  static const char* value(const mavloc::ForeignTagArray&) { return value(); }
};
template <>
struct DataType<mavloc::ForeignTagArray> {
  static const char* value() { return "apriltag_msgs/ApriltagArrayStamped"; }
  static const char* value(const mavloc::ForeignTagArray&) { return value(); }
};
template <>
struct Definition<mavloc::ForeignTagArray> {
  static const char* value() { return "std_msgs/Header header\nint32[] ids # not Apriltag[]\n"; }
  static const char* value(const mavloc::ForeignTagArray&) { return value(); }
};

template <>
struct MD5Sum<mavloc::LyingTagArray> {
  static const char* value() { return mavloc::ros1::kApriltagArrayStampedMd5; }
  static const char* value(const mavloc::LyingTagArray&) { return value(); }
};
template <>
struct DataType<mavloc::LyingTagArray> {
  static const char* value() { return "apriltag_msgs/ApriltagArrayStamped"; }
  static const char* value(const mavloc::LyingTagArray&) { return value(); }
};
template <>
struct Definition<mavloc::LyingTagArray> {
  static const char* value() { return mavloc::ros1::ApriltagArrayStampedDefinition(); }
  static const char* value(const mavloc::LyingTagArray&) { return value(); }
};
}  // namespace ros::message_traits

namespace ros::serialization {
template <>
struct Serializer<mavloc::LyingTagArray> {
  template <typename Stream, typename T>
  inline static void allInOne(Stream& stream, T m) {
    stream.next(m.header);
    stream.next(m.apriltags_length);
  }
  ROS_DECLARE_ALLINONE_SERIALIZER
};
template <>
struct Serializer<mavloc::ForeignTagArray> {
  template <typename Stream, typename T>
  inline static void allInOne(Stream& stream, T m) {
    stream.next(m.header);
    stream.next(m.ids);
  }
  ROS_DECLARE_ALLINONE_SERIALIZER
};
}  // namespace ros::serialization

namespace mavloc {
namespace {

TEST(RosbagErrors, ForeignTagDefinitionIsNamed) {
  const std::string path = testing::MakeTempDir() + "/foreign.bag";
  {
    rosbag::Bag bag(path, rosbag::bagmode::Write);
    ForeignTagArray message;
    message.ids.push_back(4);
    bag.write("/tags", ros::Time(10, 0), message);
  }
  try {
    ReadRosbagTags(path, "/tags", 0);
    FAIL() << "no error";
  } catch (const InputError& error) {
    const std::string what = error.what();
    EXPECT_NE(what.find("md5 0123456789abcdef0123456789abcdef"), std::string::npos) << what;
    EXPECT_NE(what.find("line 2: bag has 'int32[] ids', mavloc expects 'Apriltag[] apriltags'"),
              std::string::npos)
        << what;
  }
}

TEST(RosbagErrors, CorruptArrayLengthIsRefusedBeforeAllocation) {
  const std::string path = testing::MakeTempDir() + "/lying.bag";
  {
    rosbag::Bag bag(path, rosbag::bagmode::Write);
    bag.write("/tags", ros::Time(10, 0), LyingTagArray{});
  }
  try {
    ReadRosbagTags(path, "/tags", 0);
    FAIL() << "no error";
  } catch (const InputError& error) {
    const std::string what = error.what();
    EXPECT_NE(what.find(path + ": topic /tags, message 0: cannot deserialize"), std::string::npos)
        << what;
    EXPECT_NE(what.find("an array of 4000000000 elements in a message of"), std::string::npos)
        << what;
  }
}

// Bytes of a file, and the file rewritten with 4 bytes (little-endian) replaced at `offset`.
std::string FileBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}
void PatchUint32(const std::string& path, uint64_t offset, uint32_t value) {
  std::string bytes = FileBytes(path);
  for (int i = 0; i < 4; ++i) bytes[offset + i] = static_cast<char>((value >> (8 * i)) & 0xff);
  std::ofstream(path, std::ios::binary) << bytes;
}

// Reading /imu of the bag at `path` fails with an InputError naming the bag and `expected`.
void ExpectImuReadRefused(const std::string& path, const std::string& expected) {
  try {
    ReadRosbagImu(path, "/imu");
    FAIL() << "no error for " << expected;
  } catch (const InputError& error) {
    const std::string what = error.what();
    EXPECT_NE(what.find(path), std::string::npos) << what;
    EXPECT_NE(what.find(expected), std::string::npos) << what;
  }
}

// Found by fuzz_rosbag: rosbag::Bag::open read a header length of 4 GB at the index position and
// allocated it before the read failed. The record walk runs before rosbag opens the bag.
TEST(RosbagErrors, CorruptLengthsAndPositionsAreRefusedBeforeRosbagReadsThem) {
  const std::string dir = testing::MakeTempDir();
  const std::string good = dir + "/good.bag";
  WriteTestBag(good, rosbag::compression::Uncompressed);
  const BagRecordScan scan = ScanBagRecords(good);
  ASSERT_TRUE(scan.problem.empty()) << scan.problem;
  ASSERT_GT(scan.index_pos, 13u);
  // The header length of the first index record.
  const std::string huge_header = dir + "/huge_header.bag";
  fs::copy_file(good, huge_header);
  PatchUint32(huge_header, scan.index_pos, 0xFFFFFFFFu);
  ExpectImuReadRefused(huge_header,
                       fmt::format("the record at byte {} has an implausible header length "
                                   "4294967295",
                                   scan.index_pos));
  // The bag header's index position, moved into the middle of a record.
  const std::string bytes = FileBytes(good);
  const auto field = bytes.find("index_pos=");
  ASSERT_NE(field, std::string::npos);
  const std::string moved = dir + "/moved_index.bag";
  fs::copy_file(good, moved);
  PatchUint32(moved, field + 10, static_cast<uint32_t>(scan.index_pos + 1));
  ExpectImuReadRefused(
      moved, fmt::format("the index position {} is not the start of a record", scan.index_pos + 1));
  // A chunk's uncompressed size (the field after "size=" in the first chunk header).
  const auto size_field = bytes.find("size=");
  ASSERT_NE(size_field, std::string::npos);
  const std::string big_chunk = dir + "/big_chunk.bag";
  fs::copy_file(good, big_chunk);
  PatchUint32(big_chunk, size_field + 5, 0xF0000000u);
  ExpectImuReadRefused(big_chunk, "states an implausible uncompressed size");
  // A field of the bag header record (at byte 13, its first field at 17) longer than the header:
  // ros::Header::parse would read past its buffer.
  const std::string long_field = dir + "/long_field.bag";
  fs::copy_file(good, long_field);
  PatchUint32(long_field, 17, 0x7FFFu);
  ExpectImuReadRefused(long_field, "the record header at byte 13 is corrupt (a field runs past");
}

// Found by fuzz_rosbag: rosbag read the message record at an index entry's offset without checking
// it against the chunk's size (SEGV in rosbag::Bag::readHeaderFromBuffer). The record walk checks
// every index entry against its chunk (and, in an uncompressed chunk, the message record there).
TEST(RosbagErrors, IndexEntriesOutsideTheirChunkAreRefused) {
  const std::string dir = testing::MakeTempDir();
  const std::string good = dir + "/good.bag";
  WriteTestBag(good, rosbag::compression::Uncompressed);
  ASSERT_TRUE(ScanBagRecords(good).problem.empty());
  // The first index-data record (op 0x04): walk the records <uint32 hl><header><uint32 dl><data>.
  const std::string bytes = FileBytes(good);
  const auto u32 = [&](uint64_t at) {
    uint32_t v = 0;
    for (int i = 0; i < 4; ++i)
      v |= static_cast<uint32_t>(static_cast<uint8_t>(bytes[at + i])) << (8 * i);
    return v;
  };
  uint64_t at = 13, entries = 0;
  while (at + 8 < bytes.size() && entries == 0) {
    const uint32_t header_len = u32(at);
    const std::string header = bytes.substr(at + 4, header_len);
    const uint32_t data_len = u32(at + 4 + header_len);
    if (header.find(std::string("op=\x04", 4)) != std::string::npos) entries = at + 8 + header_len;
    at += 8 + uint64_t{header_len} + data_len;
  }
  ASSERT_GT(entries, 0u) << "no index-data record";
  // The first entry's offset (after its uint32 sec, uint32 nsec) far beyond the chunk.
  const std::string beyond = dir + "/beyond.bag";
  fs::copy_file(good, beyond);
  PatchUint32(beyond, entries + 8, 0x7FFFFFF0u);
  ExpectImuReadRefused(beyond, "points at a message beyond the end of its chunk");
  // Inside the chunk but not at a message record: the "header length" read there runs past it.
  const std::string inside = dir + "/inside.bag";
  fs::copy_file(good, inside);
  PatchUint32(inside, entries + 8, u32(entries + 8) + 1);
  const BagRecordScan scan = ScanBagRecords(inside);
  EXPECT_NE(scan.problem.find("the index record at byte"), std::string::npos) << scan.problem;
}

TEST(RosbagErrors, TruncatedBagNamesTheByteOffset) {
  const std::string dir = testing::MakeTempDir();
  const std::string path = dir + "/full.bag";
  WriteTestBag(path, rosbag::compression::Uncompressed);
  const auto size = fs::file_size(path);
  const std::string cut = dir + "/cut.bag";
  fs::copy_file(path, cut);
  fs::resize_file(cut, size / 2);
  try {
    SummarizeRosbag(cut);
    FAIL() << "no error";
  } catch (const InputError& error) {
    const std::string what = error.what();
    EXPECT_NE(what.find(cut), std::string::npos) << what;
    EXPECT_NE(what.find("is cut off (truncated file)"), std::string::npos) << what;
    EXPECT_NE(what.find(fmt::format("of {} bytes", size / 2)), std::string::npos) << what;
  }
  // A truncated whole-file bzip2 fails in the decompression, and leaves no temporary bag.
  Bzip2File(path, path + ".bz2");
  const auto bz2_size = fs::file_size(path + ".bz2");
  fs::resize_file(path + ".bz2", bz2_size / 2);
  try {
    ReadRosbagImu(path + ".bz2", "/imu");
    FAIL() << "no error";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("bzip2 stream is truncated"), std::string::npos)
        << error.what();
  }
  EXPECT_FALSE(IsRosbagFile(dir));
  const std::string prefix = fmt::format("mavloc-bag-{}-", static_cast<long>(getpid()));
  for (const auto& entry : fs::directory_iterator(fs::temp_directory_path())) {
    EXPECT_NE(entry.path().filename().string().rfind(prefix, 0), 0u) << entry.path();
  }
}

}  // namespace
}  // namespace mavloc
