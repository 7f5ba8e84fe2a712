// PX4 ULog files (spec: https://docs.px4.io/main/en/dev_log/ulog_file_format.html), read by
// mavloc's own streaming parser: the file is read message by message and only the requested
// topic's fields are kept, so memory does not grow with the log's length.
//
// Topics are named as in the log ("sensor_combined"); a multi-instance topic's later instances
// are selected as "name.N" (N = the 'A' message's multi_id, e.g. "vehicle_imu.1"); "name" alone
// is instance 0. Timestamps are the logged uint64 microseconds since boot, as t_ns = 1000 * t_us;
// a data message whose stamp is too large for that (ulog_format.h, StampNs) is a corrupt message.
//
// Frames (PX4: docs.px4.io "Coordinate Frames"; mavloc: DESIGN.md, W z up, B = IMU):
//   PX4 body frame FRD (x forward, y right, z down) -> mavloc B = FLU:  R_FLU_FRD = diag(1, -1,
//   -1). PX4 earth frame NED (x north, y east, z down)   -> mavloc W = ENU:  R_ENU_NED = [0 1 0; 1
//   0 0; 0 0 -1]. A PX4 "FRD" earth frame (vehicle_odometry pose_frame = FRD: x along the initial
//   heading, z down) -> a z-up W by R = diag(1, -1, -1).
// PX4's accelerometer reports specific force in FRD (a level vehicle at rest reads z = -9.81); in
// FLU it reads +9.81 on z, as mavloc's IMU model a_m = R_W_B^T (a_W - g_W) expects.
//
// Truncation (decided here): a log cut inside the header or the definitions section is an
// InputError naming the byte offset; a log whose last message is cut short (a vehicle that lost
// power or crashed mid-write) keeps every complete message and gets a note in
// UlogInfo::notes / LogSummary::notes naming the offset of the partial message.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "core/imu.h"
#include "datasets/io/log_reader.h"

namespace mavloc {

// One (topic, multi_id) pair with data, as pyulog's ULog.data_list holds it.
struct UlogTopicInfo {
  std::string name;
  int multi_id = 0;
  // Bytes of one message as pyulog counts them: the flattened fields without trailing
  // "_padding" fields.
  int message_size = 0;
  uint64_t messages = 0;
  uint64_t t_first_us = 0;
  uint64_t t_last_us = 0;
};

// An 'L' or 'C' logged string.
struct UlogLoggedString {
  uint64_t t_us = 0;
  int log_level = 0;  // ASCII '0' (EMERGENCY) .. '7' (DEBUG) as PX4 writes it
  int tag = -1;       // 'C' messages only
  std::string message;
};

struct UlogInfo {
  std::string path;
  int version = 0;
  uint64_t t_start_us = 0;            // header timestamp
  uint64_t t_last_us = 0;             // largest data timestamp (pyulog's last_timestamp)
  std::vector<UlogTopicInfo> topics;  // sorted as pyulog's ulog_info prints them
  std::vector<int> dropouts_ms;       // one per 'O' message
  // 'I' messages: key -> value as text (strings as is, integers and floats in decimal, other
  // types as "<N bytes>").
  std::map<std::string, std::string> info;
  std::map<std::string, std::string> parameters;  // initial 'P' values as text
  std::vector<UlogLoggedString> logged_strings;   // 'L' and 'C' in file order
  bool data_appended = false;
  std::vector<uint64_t> appended_offsets;  // non-zero offsets of the flag bits message
  uint64_t file_bytes = 0;
  std::vector<std::string> notes;  // truncation, corrupt or skipped messages, appended data
};

// Reads everything but the topic data (which is only counted). Throws InputError on a file that
// is not ULog, a cut header/definitions section, or an unknown incompatible flag.
UlogInfo ReadUlogInfo(const std::string& path);

// The parts of pyulog's `ulog_info -v` output mavloc reproduces exactly: the "Logging start
// time" line, the "Dropouts" line, and the topic table ("Name (multi id, message size in
// bytes) ..." and one row per topic). Each line ends with '\n'.
std::string FormatUlogInfoTopicTable(const UlogInfo& info);
std::string FormatUlogInfoTimeAndDropouts(const UlogInfo& info);
// pyulog's `ulog_messages` lines ("0:02:38 ERROR: [sensors] ..."), for 'L' strings.
std::string FormatUlogLoggedStrings(const UlogInfo& info);

// mavloc's log summary (datasets/io/log_reader.h): per topic instance the counts and first/last
// stamps, with notes on dropouts (count, total duration), appended data and truncation.
LogSummary SummarizeUlog(const std::string& path);

// Called with (bytes read, file size) about every 64 MiB and at the end; may be empty.
using UlogProgress = std::function<void(uint64_t bytes_done, uint64_t bytes_total)>;

// IMU samples in mavloc's B (FLU, see above) from "sensor_combined" (gyro_rad,
// accelerometer_m_s2 at timestamp + accelerometer_timestamp_relative; the sample time is the
// gyro's `timestamp`) or "vehicle_imu[.N]" (delta_angle / delta_angle_dt and delta_velocity /
// delta_velocity_dt, mean rates over the integration interval, stamped at `timestamp_sample`).
// A message with a non-finite value, or a rate beyond limits::kMaxAngularRate_rad_s or a specific
// force beyond limits::kMaxSpecificForce_m_s2 (core/physical_limits.h), is refused (InputError
// naming the file, the field and the topic's message index), as the ROS bag reader refuses it.
// Messages PX4 marks invalid (accelerometer_timestamp_relative = INT32_MAX, a zero dt), messages
// with a corrupt stamp (ulog_format.h, StampNs) and messages whose stamp is not after the previous
// one are dropped and counted: each kind gets a note in `notes` (when not null) with its count and
// first message index, and so does whatever the scan noted (truncation, corrupt messages; as in
// UlogInfo::notes). Throws InputError for a missing topic, a topic of another type, or missing
// fields.
std::vector<ImuSample> ReadUlogImu(const std::string& path, const std::string& topic,
                                   const UlogProgress& progress = {},
                                   std::vector<std::string>* notes = nullptr);
// Its streaming form: `visit` gets each kept sample as it is read, nothing is kept here; the
// notes are added at the end.
void ForEachUlogImuSample(const std::string& path, const std::string& topic,
                          const std::function<void(const ImuSample&)>& visit,
                          const UlogProgress& progress = {},
                          std::vector<std::string>* notes = nullptr);

// A trajectory in mavloc's W (ENU or z-up FRD-world, see above) and B (FLU):
// - vehicle_attitude: q (Hamilton w,x,y,z, body FRD -> NED); position zero, no velocity.
// - vehicle_local_position: x,y,z and vx,vy,vz (NED); it has no attitude, so the rotation is
//   identity (not guessed from another topic); has_velocity when v_xy_valid and v_z_valid.
// - vehicle_odometry, vehicle_visual_odometry, vehicle_mocap_odometry: position, q, velocity
//   and their frame fields (PX4 >= 1.14: position/q/velocity, pose_frame, velocity_frame,
//   position_variance, orientation_variance; older: x,y,z, q, vx,vy,vz, local_frame,
//   velocity_frame, pose_covariance upper-right triangle). Velocity in a body frame is rotated
//   into W with the message's own q. Covariance is filled when the message carries finite,
//   non-negative, not-all-zero values.
// Stamps are timestamp_sample when the topic has it, else timestamp. Messages PX4 marks invalid
// (NaN position or q, as vehicle_odometry documents "NaN if invalid/unknown"; both xy_valid and
// z_valid false), messages with a corrupt stamp (ulog_format.h, StampNs) and messages whose stamp
// is not after the previous one are dropped and counted, each kind with a note in `notes` (when not
// null), as are the scan's notes; a local position with only z valid is kept (x, y as logged).
// A finite value no MAV logs is refused (InputError naming the file, the field and the message
// index): a position beyond limits::kMaxPosition_m, a velocity beyond limits::kMaxSpeed_m_s, a q
// whose norm is off 1 by more than 0.1.
// parent_frame is "world_enu" (from NED) or "world_flu" (from an FRD earth frame); child_frame is
// "body_flu", or "body_position_only" for vehicle_local_position.
// The instance is the topic's ".N" suffix or, without one, spec.instance.
// Throws InputError for a missing topic, a topic without the needed fields, or an unknown frame.
LogTrajectory ReadUlogTrajectory(const LogTopicSpec& spec, const UlogProgress& progress = {},
                                 std::vector<std::string>* notes = nullptr);

}  // namespace mavloc
