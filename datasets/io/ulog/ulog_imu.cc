// ReadUlogImu: PX4's IMU topics as mavloc IMU samples in B = FLU (ulog_frames.h). Field meanings
// from PX4's msg/SensorCombined.msg and msg/VehicleImu.msg.
#include <fmt/format.h>

#include <cmath>
#include <optional>

#include "core/errors.h"
#include "core/physical_limits.h"
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

// Hands on one IMU topic's samples: refuses values no IMU measures (ulog_reader.h), drops and
// counts what PX4 marks invalid and stamps that do not increase.
class ImuCollector {
 public:
  ImuCollector(const std::string& path, const std::string& topic,
               const std::function<void(const ImuSample&)>& visit)
      : path_(path), topic_(topic), visit_(visit) {}

  // The topic's next message (index counts them from 0).
  uint64_t NextIndex() { return index_++; }
  void Drop(const std::string& reason, uint64_t index) { dropped_.Add(reason, index); }

  // Checks each component (FRD as logged) against its limit, then hands the sample on when later
  // than the previous one. `gyro_fields` / `accel_fields` name the logged fields of the values.
  void Push(uint64_t index, TimeNs t_ns, const Eigen::Vector3d& gyro_frd_rad_s,
            const Eigen::Vector3d& accel_frd_m_s2, const char* const gyro_fields[3],
            const char* const accel_fields[3]) {
    for (int k = 0; k < 3; ++k) {
      ulog::RequireWithin(path_, topic_, index, gyro_fields[k], gyro_frd_rad_s[k],
                          limits::kMaxAngularRate_rad_s, "rad/s");
      ulog::RequireWithin(path_, topic_, index, accel_fields[k], accel_frd_m_s2[k],
                          limits::kMaxSpecificForce_m_s2, "m/s^2");
    }
    if (dropped_.DropNotIncreasing(t_ns, previous_ns_, index)) return;
    ImuSample s;
    s.t_ns = t_ns;
    s.gyro_rad_s = ulog::FrdToFlu(gyro_frd_rad_s);
    s.accel_m_s2 = ulog::FrdToFlu(accel_frd_m_s2);
    previous_ns_ = t_ns;
    visit_(s);
  }

  void Finish(std::vector<std::string>* notes) const { dropped_.AppendNotes(topic_, notes); }

 private:
  const std::string& path_;
  const std::string& topic_;
  const std::function<void(const ImuSample&)>& visit_;
  uint64_t index_ = 0;
  ulog::DroppedMessages dropped_;
  std::optional<TimeNs> previous_ns_;  // of the last sample handed on
};

void FromSensorCombined(const std::string& path, const std::string& topic,
                        const std::function<void(const ImuSample&)>& visit,
                        const UlogProgress& progress, std::vector<std::string>* notes) {
  // gyro_rad: rad/s, accelerometer_m_s2: specific force, both FRD; the gyro sample time is the
  // gyro's `timestamp`, the accelerometer's is timestamp + accelerometer_timestamp_relative.
  static const char* const kGyro[3] = {"gyro_rad[0]", "gyro_rad[1]", "gyro_rad[2]"};
  static const char* const kAccel[3] = {"accelerometer_m_s2[0]", "accelerometer_m_s2[1]",
                                        "accelerometer_m_s2[2]"};
  ImuCollector collector(path, topic, visit);
  std::vector<std::string> scan_notes;
  ulog::ForEachTopicRow(
      path, topic,
      {{kGyro[0]},
       {kGyro[1]},
       {kGyro[2]},
       {kAccel[0]},
       {kAccel[1]},
       {kAccel[2]},
       {"accelerometer_timestamp_relative", false}},
      progress,
      [&collector](uint64_t t_us, const double* v) {
        const uint64_t index = collector.NextIndex();
        if (v[6] == kRelativeTimestampInvalid) {  // NaN when the field is absent
          collector.Drop("marked invalid by PX4 (accelerometer_timestamp_relative = INT32_MAX)",
                         index);
          return;
        }
        collector.Push(index, *ulog::StampNs(t_us) /* checked by the scanner */, Vec3(v),
                       Vec3(v + 3), kGyro, kAccel);
      },
      &scan_notes);
  collector.Finish(notes);
  if (notes != nullptr) notes->insert(notes->begin(), scan_notes.begin(), scan_notes.end());
}

void FromVehicleImu(const std::string& path, const std::string& topic,
                    const std::function<void(const ImuSample&)>& visit,
                    const UlogProgress& progress, std::vector<std::string>* notes) {
  // delta_angle [rad] over delta_angle_dt [us], delta_velocity [m/s] over delta_velocity_dt [us],
  // FRD, integrated up to timestamp_sample: their means over the interval, stamped at its end.
  static const char* const kAngle[3] = {"delta_angle[0]", "delta_angle[1]", "delta_angle[2]"};
  static const char* const kVelocity[3] = {"delta_velocity[0]", "delta_velocity[1]",
                                           "delta_velocity[2]"};
  ImuCollector collector(path, topic, visit);
  std::vector<std::string> scan_notes;
  ulog::ForEachTopicRow(
      path, topic,
      {{kAngle[0]},
       {kAngle[1]},
       {kAngle[2]},
       {kVelocity[0]},
       {kVelocity[1]},
       {kVelocity[2]},
       {"delta_angle_dt"},
       {"delta_velocity_dt"},
       {"timestamp_sample", false}},
      progress,
      [&collector](uint64_t t_us, const double* v) {
        const uint64_t index = collector.NextIndex();
        const double dt_angle_s = v[6] * 1e-6;
        const double dt_velocity_s = v[7] * 1e-6;
        if (!(dt_angle_s > 0.0) || !(dt_velocity_s > 0.0)) {
          collector.Drop("with a zero integration interval (delta_angle_dt or delta_velocity_dt)",
                         index);
          return;
        }
        const std::optional<TimeNs> t_ns =
            std::isnan(v[8]) ? ulog::StampNs(t_us) : ulog::StampNsOfField(v[8]);
        if (!t_ns) {
          collector.Drop("with a corrupt timestamp_sample (negative or beyond the range)", index);
          return;
        }
        // The mean rates are checked as the values written, under the logged fields' names.
        collector.Push(index, *t_ns, Vec3(v) / dt_angle_s, Vec3(v + 3) / dt_velocity_s, kAngle,
                       kVelocity);
      },
      &scan_notes);
  collector.Finish(notes);
  if (notes != nullptr) notes->insert(notes->begin(), scan_notes.begin(), scan_notes.end());
}

}  // namespace

std::vector<ImuSample> ReadUlogImu(const std::string& path, const std::string& topic,
                                   const UlogProgress& progress, std::vector<std::string>* notes) {
  std::vector<ImuSample> samples;
  ForEachUlogImuSample(
      path, topic, [&samples](const ImuSample& s) { samples.push_back(s); }, progress, notes);
  return samples;
}

void ForEachUlogImuSample(const std::string& path, const std::string& topic,
                          const std::function<void(const ImuSample&)>& visit,
                          const UlogProgress& progress, std::vector<std::string>* notes) {
  const ulog::TopicSelector selector = ulog::ParseTopicSelector(path, topic);
  if (selector.name == "sensor_combined")
    return FromSensorCombined(path, topic, visit, progress, notes);
  if (selector.name == "vehicle_imu") return FromVehicleImu(path, topic, visit, progress, notes);
  throw InputError(path, 0, topic,
                   "not a ULog IMU topic: use sensor_combined or vehicle_imu (vehicle_imu.N for "
                   "another instance)");
}

}  // namespace mavloc
