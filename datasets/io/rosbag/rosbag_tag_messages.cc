#include "datasets/io/rosbag/rosbag_tag_messages.h"

#include <sstream>

namespace mavloc::ros1 {

namespace {
constexpr char kSeparator[] =
    "================================================================================\n";

std::string HeaderSection() {
  return std::string(kSeparator) +
         "MSG: std_msgs/Header\nuint32 seq\ntime stamp\nstring frame_id\n";
}
std::string PointSection() {
  return std::string(kSeparator) + "MSG: geometry_msgs/Point\nfloat64 x\nfloat64 y\nfloat64 z\n";
}
}  // namespace

const char* ApriltagArrayStampedDefinition() {
  static const std::string text = "std_msgs/Header header\nApriltag[] apriltags\n\n" +
                                  HeaderSection() + kSeparator +
                                  "MSG: apriltag_msgs/Apriltag\nint32 id\nstring family\n"
                                  "int32 hamming\nint32 border\nint32 bits\n"
                                  "geometry_msgs/Point center\ngeometry_msgs/Point[4] corners\n" +
                                  PointSection();
  return text.c_str();
}

const char* AprilTagDetectionArrayDefinition() {
  static const std::string text =
      "std_msgs/Header header\nAprilTagDetection[] detections\n\n" + HeaderSection() + kSeparator +
      "MSG: apriltag_ros/AprilTagDetection\nint32[] id\nfloat64[] size\n"
      "geometry_msgs/PoseWithCovarianceStamped pose\n" +
      kSeparator +
      "MSG: geometry_msgs/PoseWithCovarianceStamped\nstd_msgs/Header header\n"
      "geometry_msgs/PoseWithCovariance pose\n" +
      kSeparator +
      "MSG: geometry_msgs/PoseWithCovariance\ngeometry_msgs/Pose pose\nfloat64[36] covariance\n" +
      kSeparator +
      "MSG: geometry_msgs/Pose\ngeometry_msgs/Point position\n"
      "geometry_msgs/Quaternion orientation\n" +
      PointSection() + kSeparator +
      "MSG: geometry_msgs/Quaternion\nfloat64 x\nfloat64 y\nfloat64 z\nfloat64 w\n";
  return text.c_str();
}

std::vector<std::string> CanonicalDefinitionLines(const std::string& definition) {
  std::vector<std::string> lines;
  std::istringstream in(definition);
  std::string line;
  while (std::getline(in, line)) {
    if (const auto hash = line.find('#'); hash != std::string::npos) line.erase(hash);
    std::istringstream words(line);
    std::string word, canonical;
    while (words >> word) {
      if (canonical.empty() && word == "Header") word = "std_msgs/Header";
      canonical += canonical.empty() ? word : " " + word;
    }
    if (!canonical.empty()) lines.push_back(canonical);
  }
  return lines;
}

}  // namespace mavloc::ros1
