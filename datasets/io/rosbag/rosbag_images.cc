// sensor_msgs/Image and sensor_msgs/CompressedImage -> PNG files (rosbag_reader.h). Image.msg:
// `step` bytes per row, `is_bigendian` for multi-byte pixels; encodings as sensor_msgs/
// image_encodings.h names them.
#include <fmt/format.h>

#include <filesystem>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "core/atomic_file.h"
#include "core/errors.h"
#include "core/image_codec.h"
#include "datasets/io/rosbag/opened_bag.h"
#include "datasets/io/rosbag/ros_messages.h"
#include "datasets/io/rosbag/rosbag_reader.h"

namespace mavloc {

namespace {

// The raw image as an OpenCV matrix in OpenCV's channel order (BGR); empty with `error` set when
// the encoding is not supported or the buffer is too short.
cv::Mat DecodeRawImage(const ros1::ImageMsg& image, std::string* error) {
  const std::string encoding = ros1::ToStdString(image.encoding);
  struct Layout {
    int cv_type;
    int conversion;  // cv::ColorConversionCodes, or -1
  };
  Layout layout{};
  if (encoding == "mono8" || encoding == "8UC1") {
    layout = {CV_8UC1, -1};
  } else if (encoding == "mono16" || encoding == "16UC1") {
    layout = {CV_16UC1, -1};
  } else if (encoding == "bgr8" || encoding == "8UC3") {
    layout = {CV_8UC3, -1};
  } else if (encoding == "rgb8") {
    layout = {CV_8UC3, cv::COLOR_RGB2BGR};
  } else if (encoding == "bgra8") {
    layout = {CV_8UC4, -1};
  } else if (encoding == "rgba8") {
    layout = {CV_8UC4, cv::COLOR_RGBA2BGRA};
  } else {
    *error = fmt::format(
        "image encoding '{}' is not supported (mono8, mono16, bgr8, rgb8, bgra8, "
        "rgba8)",
        encoding);
    return {};
  }
  const size_t row_bytes = static_cast<size_t>(image.width) * CV_ELEM_SIZE(layout.cv_type);
  if (image.width == 0 || image.height == 0 || image.step < row_bytes ||
      image.data.size() < static_cast<size_t>(image.step) * image.height) {
    *error = fmt::format("image {}x{} with step {} does not fit its {} data bytes", image.width,
                         image.height, image.step, image.data.size());
    return {};
  }
  const cv::Mat view(static_cast<int>(image.height), static_cast<int>(image.width), layout.cv_type,
                     const_cast<uint8_t*>(image.data.data()), image.step);
  cv::Mat decoded = view.clone();
  if (CV_ELEM_SIZE1(layout.cv_type) == 2 && image.is_bigendian) {
    for (int r = 0; r < decoded.rows; ++r) {
      auto* row = decoded.ptr<uint16_t>(r);
      for (int c = 0; c < decoded.cols * decoded.channels(); ++c) {
        row[c] = static_cast<uint16_t>((row[c] >> 8) | (row[c] << 8));
      }
    }
  }
  if (layout.conversion >= 0) cv::cvtColor(decoded, decoded, layout.conversion);
  return decoded;
}

}  // namespace

std::vector<CameraFrame> ExportRosbagImages(const std::string& path, const std::string& topic,
                                            const std::string& out_dir) {
  ros1::OpenedBag bag(path);
  const std::string type = bag.TopicType(topic);
  const bool compressed = type == "sensor_msgs/CompressedImage";
  if (!compressed && type != "sensor_msgs/Image") {
    throw InputError(
        path, 0, "",
        fmt::format("topic {} is {}, not sensor_msgs/Image or CompressedImage", topic, type));
  }
  if (!std::filesystem::is_directory(out_dir)) {
    throw InputError(out_dir, 0, "", "image output folder does not exist");
  }
  const std::filesystem::path folder = std::filesystem::absolute(out_dir);
  std::vector<CameraFrame> frames;
  bag.ForEachMessage(topic, [&](const rosbag::MessageInstance& message, uint64_t index) {
    cv::Mat image;
    TimeNs t_ns = 0;
    if (compressed) {
      const auto msg = ros1::Instantiate<ros1::CompressedImageMsg>(bag, topic, index, message);
      t_ns = ros1::ToNs(msg->header.stamp);
      std::string damage;
      image = DecodeImage(std::string(msg->data.begin(), msg->data.end()),
                          ImageDecodeMode::kUnchanged, &damage);
      if (image.empty()) {
        bag.Fail(
            topic, index,
            fmt::format("cannot decode the '{}' image ({} bytes){}", ros1::ToStdString(msg->format),
                        msg->data.size(), damage.empty() ? "" : ": " + damage));
      }
    } else {
      const auto msg = ros1::Instantiate<ros1::ImageMsg>(bag, topic, index, message);
      t_ns = ros1::ToNs(msg->header.stamp);
      std::string error;
      image = DecodeRawImage(*msg, &error);
      if (image.empty()) bag.Fail(topic, index, error);
    }
    if (!frames.empty() && t_ns <= frames.back().t_ns) {
      bag.Fail(topic, index,
               fmt::format("header.stamp {} ns does not increase (previous {} ns)", t_ns,
                           frames.back().t_ns));
    }
    const std::string file = (folder / fmt::format("{}.png", t_ns)).string();
    WriteFileAtomically(file, EncodePng(image));
    frames.push_back({t_ns, file});
  });
  return frames;
}

}  // namespace mavloc
