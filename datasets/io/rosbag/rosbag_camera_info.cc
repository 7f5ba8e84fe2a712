// sensor_msgs/CameraInfo -> CameraModel (rosbag_reader.h). CameraInfo.msg: K row-major
// [fx 0 cx; 0 fy cy; 0 0 1]; D per distortion_model: "plumb_bob" k1 k2 p1 p2 k3,
// "rational_polynomial" k1 k2 p1 p2 k3 k4 k5 k6, "equidistant" k1 k2 k3 k4 (image_geometry).
#include <fmt/format.h>

#include <algorithm>

#include "core/errors.h"
#include "datasets/io/rosbag/opened_bag.h"
#include "datasets/io/rosbag/ros_messages.h"
#include "datasets/io/rosbag/rosbag_reader.h"

namespace mavloc {

namespace {

CameraModel ToCameraModel(const ros1::CameraInfoMsg& info, ros1::OpenedBag& bag,
                          const std::string& topic) {
  const std::string model = ros1::ToStdString(info.distortion_model);
  const std::vector<double> d(info.D.begin(), info.D.end());
  const Eigen::Vector4d intrinsics(info.K[0], info.K[4], info.K[2], info.K[5]);
  if (!intrinsics.allFinite() || intrinsics[0] <= 0.0 || intrinsics[1] <= 0.0) {
    bag.Fail(topic, 0, "K has no positive focal lengths");
  }
  const int width = static_cast<int>(info.width);
  const int height = static_cast<int>(info.height);
  const bool all_zero = std::all_of(d.begin(), d.end(), [](double k) { return k == 0.0; });
  if (model.empty() || all_zero) return CameraModel(width, height, intrinsics);
  auto coefficient = [&](size_t i) { return i < d.size() ? d[i] : 0.0; };
  if (model == "plumb_bob" || model == "rational_polynomial") {
    for (size_t i = 4; i < d.size(); ++i) {
      if (d[i] != 0.0) {
        bag.Fail(topic, 0,
                 fmt::format("{} coefficient D[{}] = {} is not zero: mavloc's radial-tangential "
                             "model has k1 k2 p1 p2 only",
                             model, i, d[i]));
      }
    }
    return CameraModel(width, height, intrinsics, DistortionModel::kRadialTangential,
                       {coefficient(0), coefficient(1), coefficient(2), coefficient(3)});
  }
  if (model == "equidistant") {
    if (d.size() > 4) bag.Fail(topic, 0, "equidistant model with more than 4 coefficients");
    return CameraModel(width, height, intrinsics, DistortionModel::kEquidistant,
                       {coefficient(0), coefficient(1), coefficient(2), coefficient(3)});
  }
  bag.Fail(topic, 0,
           fmt::format("distortion_model '{}' is not supported (plumb_bob, rational_polynomial, "
                       "equidistant)",
                       model));
}

}  // namespace

CameraModel ReadRosbagCameraInfo(const std::string& path, const std::string& topic) {
  ros1::OpenedBag bag(path);
  const std::string type = bag.TopicType(topic);
  if (type != "sensor_msgs/CameraInfo") {
    throw InputError(path, 0, "",
                     fmt::format("topic {} is {}, not sensor_msgs/CameraInfo", topic, type));
  }
  std::optional<CameraModel> model;
  // The first message defines the model (a calibrated camera publishes the same one throughout).
  bag.ForEachMessage(topic, [&](const rosbag::MessageInstance& message, uint64_t index) {
    if (model) return;
    model = ToCameraModel(*ros1::Instantiate<ros1::CameraInfoMsg>(bag, topic, index, message), bag,
                          topic);
  });
  return *model;
}

}  // namespace mavloc
