// ReadUlogImu: PX4's IMU topics as mavloc IMU samples in B = FLU (ulog_frames.h). Field meanings
// from PX4's msg/SensorCombined.msg and msg/VehicleImu.msg.
#include <fmt/format.h>

#include <cmath>
#include <optional>

#include "core/errors.h"
#include "datasets/io/ulog/ulog_format.h"
#include "datasets/io/ulog/ulog_frames.h"
#include "datasets/io/ulog/ulog_reader.h"
#include "datasets/io/ulog/ulog_topic_fields.h"

namespace mavloc {
namespace {

// sensor_combined.accelerometer_timestamp_relative when the accelerometer sample is invalid
// (SensorCombined.msg: RELATIVE_TIMESTAMP_INVALID).
constexpr double kRelativeTimestampInvalid = 2147483647.0;

Eigen::Vector3d Vec3(const double* values) { return {values[0], values[1], values[2]}; }

// Appends when finite and later than the previous sample.
void Push(std::vector<ImuSample>* samples, const ImuSample& s) {
  if (!s.gyro_rad_s.allFinite() || !s.accel_m_s2.allFinite()) return;
  if (!samples->empty() && s.t_ns <= samples->back().t_ns) return;
  samples->push_back(s);
}

std::vector<ImuSample> FromSensorCombined(const std::string& path, const std::string& topic,
                                          const UlogProgress& progress) {
  // gyro_rad: rad/s, accelerometer_m_s2: specific force, both FRD; the gyro sample time is the
  // message timestamp, the accelerometer's is timestamp + accelerometer_timestamp_relative.
  std::vector<ImuSample> samples;
  ulog::ForEachTopicRow(path, topic,
                        {{"gyro_rad[0]"},
                         {"gyro_rad[1]"},
                         {"gyro_rad[2]"},
                         {"accelerometer_m_s2[0]"},
                         {"accelerometer_m_s2[1]"},
                         {"accelerometer_m_s2[2]"},
                         {"accelerometer_timestamp_relative", false}},
                        progress, [&samples](uint64_t t_us, const double* v) {
                          if (v[6] == kRelativeTimestampInvalid)
                            return;  // NaN when the field is absent
                          ImuSample s;
                          s.t_ns = *ulog::StampNs(t_us);  // checked by the scanner
                          s.gyro_rad_s = ulog::FrdToFlu(Vec3(v));
                          s.accel_m_s2 = ulog::FrdToFlu(Vec3(v + 3));
                          Push(&samples, s);
                        });
  return samples;
}

std::vector<ImuSample> FromVehicleImu(const std::string& path, const std::string& topic,
                                      const UlogProgress& progress) {
  // delta_angle [rad] over delta_angle_dt [us], delta_velocity [m/s] over delta_velocity_dt [us],
  // FRD, integrated up to timestamp_sample: their means over the interval, stamped at its end.
  std::vector<ImuSample> samples;
  ulog::ForEachTopicRow(path, topic,
                        {{"delta_angle[0]"},
                         {"delta_angle[1]"},
                         {"delta_angle[2]"},
                         {"delta_velocity[0]"},
                         {"delta_velocity[1]"},
                         {"delta_velocity[2]"},
                         {"delta_angle_dt"},
                         {"delta_velocity_dt"},
                         {"timestamp_sample", false}},
                        progress, [&samples](uint64_t t_us, const double* v) {
                          const double dt_angle_s = v[6] * 1e-6;
                          const double dt_velocity_s = v[7] * 1e-6;
                          if (!(dt_angle_s > 0.0) || !(dt_velocity_s > 0.0)) return;
                          ImuSample s;
                          const std::optional<TimeNs> t_ns =
                              std::isnan(v[8]) ? ulog::StampNs(t_us) : ulog::StampNsOfField(v[8]);
                          if (!t_ns) return;  // a corrupt timestamp_sample
                          s.t_ns = *t_ns;
                          s.gyro_rad_s = ulog::FrdToFlu(Vec3(v) / dt_angle_s);
                          s.accel_m_s2 = ulog::FrdToFlu(Vec3(v + 3) / dt_velocity_s);
                          Push(&samples, s);
                        });
  return samples;
}

}  // namespace

std::vector<ImuSample> ReadUlogImu(const std::string& path, const std::string& topic,
                                   const UlogProgress& progress) {
  const ulog::TopicSelector selector = ulog::ParseTopicSelector(path, topic);
  if (selector.name == "sensor_combined") return FromSensorCombined(path, topic, progress);
  if (selector.name == "vehicle_imu") return FromVehicleImu(path, topic, progress);
  throw InputError(path, 0, topic,
                   "not a ULog IMU topic: use sensor_combined or vehicle_imu (vehicle_imu.N for "
                   "another instance)");
}

}  // namespace mavloc
