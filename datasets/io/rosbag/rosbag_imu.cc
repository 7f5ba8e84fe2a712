// sensor_msgs/Imu -> ImuSample (rosbag_reader.h; the streaming form is declared in log_reader.h).
#include <fmt/format.h>

#include <cmath>
#include <optional>

#include "core/errors.h"
#include "core/physical_limits.h"
#include "datasets/io/rosbag/opened_bag.h"
#include "datasets/io/rosbag/ros_messages.h"
#include "datasets/io/rosbag/rosbag_reader.h"

namespace mavloc {

void ForEachRosbagImuSample(const std::string& path, const std::string& topic,
                            const std::function<void(const ImuSample&)>& visit) {
  ros1::OpenedBag bag(path);
  const std::string type = bag.TopicType(topic);
  if (type != "sensor_msgs/Imu") {
    throw InputError(path, 0, "", fmt::format("topic {} is {}, not sensor_msgs/Imu", topic, type));
  }
  std::optional<TimeNs> previous_ns;
  bag.ForEachMessage(topic, [&](const rosbag::MessageInstance& message, uint64_t index) {
    const auto imu = ros1::Instantiate<ros1::ImuMsg>(bag, topic, index, message);
    ImuSample sample;
    sample.t_ns = ros1::ToNs(imu->header.stamp);
    sample.gyro_rad_s = {imu->angular_velocity.x, imu->angular_velocity.y, imu->angular_velocity.z};
    sample.accel_m_s2 = {imu->linear_acceleration.x, imu->linear_acceleration.y,
                         imu->linear_acceleration.z};
    if (!sample.gyro_rad_s.allFinite() || !sample.accel_m_s2.allFinite()) {
      bag.Fail(topic, index, "angular_velocity or linear_acceleration is not finite");
    }
    // The sanity ranges of core/physical_limits.h, as the EuRoC reader applies to imu0/data.csv.
    if (!(sample.gyro_rad_s.cwiseAbs().maxCoeff() <= limits::kMaxAngularRate_rad_s)) {
      bag.Fail(topic, index,
               fmt::format("angular_velocity {:g} rad/s is outside {}",
                           sample.gyro_rad_s.cwiseAbs().maxCoeff(),
                           limits::RangeText(-limits::kMaxAngularRate_rad_s,
                                             limits::kMaxAngularRate_rad_s, "rad/s")));
    }
    if (!(sample.accel_m_s2.cwiseAbs().maxCoeff() <= limits::kMaxSpecificForce_m_s2)) {
      bag.Fail(topic, index,
               fmt::format("linear_acceleration {:g} m/s^2 is outside {}",
                           sample.accel_m_s2.cwiseAbs().maxCoeff(),
                           limits::RangeText(-limits::kMaxSpecificForce_m_s2,
                                             limits::kMaxSpecificForce_m_s2, "m/s^2")));
    }
    if (previous_ns && sample.t_ns <= *previous_ns) {
      bag.Fail(topic, index,
               fmt::format("header.stamp {} ns does not increase (previous {} ns)", sample.t_ns,
                           *previous_ns));
    }
    previous_ns = sample.t_ns;
    visit(sample);
  });
}

std::vector<ImuSample> ReadRosbagImu(const std::string& path, const std::string& topic) {
  std::vector<ImuSample> samples;
  ForEachRosbagImuSample(path, topic, [&samples](const ImuSample& s) { samples.push_back(s); });
  return samples;
}

}  // namespace mavloc
