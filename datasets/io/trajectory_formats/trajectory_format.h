// Trajectory files as the tools of this field write them, read into mavloc's poses T_W_B with
// int64 nanosecond stamps. Formats (the name is what --gt-format/--est-format take):
//   tum   - "timestamp tx ty tz qx qy qz qw", seconds (TUM RGB-D benchmark, evo, mavloc); also
//           OpenVINS ov_eval's 20-column variant (the pose, then 12 covariance values, ignored).
//   euroc - EuRoC/ASL ground truth without relying on its header: "t_ns, p_x, p_y, p_z, q_w, q_x,
//           q_y, q_z" then optionally v (3), b_w (3), b_a (3) (17 columns) or anything further
//           (ignored). VINS-Fusion's headerless "t_ns,x,y,z,qw,qx,qy,qz,vx,vy,vz," is this layout.
//   asl   - a CSV (or whitespace table) whose header names the columns, read by name: Kimera-VIO's
//           "#timestamp,x,y,z,qw,qx,qy,qz,vx,...", EuRoC's "#timestamp [ns],p_RS_R_x [m],...",
//           OpenVINS' state file "# timestamp(s) q p v bg ba ..." (q = JPL q_GtoI stored x,y,z,w,
//           whose components are the Hamilton q_W_B: R_JPL(q) = R_Hamilton(q)^T).
//   kitti - KITTI odometry poses: 12 numbers per line, the first 3 rows of T_W_B row-major; no
//           stamps (an optional times file gives one stamp in seconds per line, as KITTI's
//           times.txt). Without it the i-th pose gets stamp i seconds and `has_stamps` is false:
//           evo associates such files by index.
//           The attitude may be named roll, pitch, yaw instead of a quaternion (R = Rz(yaw)
//           Ry(pitch) Rx(roll); radians unless the header says [deg]): mavloc's quantity CSVs.
// Detection (auto) from the content: a header whose names give a timestamp, a position and an
// attitude -> asl (euroc when they are EuRoC's own names); a header naming a timestamp and a
// position without an attitude is refused (its rows are never read by position); otherwise
// whitespace rows of 8 or 20 fields -> tum, of 12 -> kitti; comma rows whose stamp has a decimal
// point -> tum (seconds; 8 or 20 fields, else refused); other comma rows of 8 or more -> euroc.
// Seconds are never read as nanoseconds: stamps taken for nanoseconds without a header stating
// the unit are refused when they look like seconds (trajectory_stamps.h: a rate beyond any pose
// source, or a date before 1971 that is a date as seconds), and stamps that must be seconds but
// look like nanoseconds, microseconds or milliseconds since 1970 are refused with the divisor.
//
// Rows (all formats): exactly repeated stamps keep the first row and count the others (evo's
// nearest-stamp association takes the first of equal stamps too); a stamp earlier than the one
// before it is an error naming file and line unless sorting was asked for (stable: equal stamps
// keep file order). Quaternions are normalised when | |q| - 1 | <= kQuaternionNormTolerance
// (files printed with 3-5 decimals are off by up to a few 1e-3); farther off is an error.
// KITTI rotation blocks are projected onto SO(3) when max |R^T R - I| <= the same tolerance.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "core/dataset.h"
#include "core/physical_limits.h"
#include "core/pose.h"

namespace mavloc {

// kLog: a topic of a ROS1 bag or PX4 ULog file, "LOG:TOPIC" (datasets/io/log_reader.h); chosen
// whenever the path names one, never forced.
enum class TrajectoryFormat { kAuto, kTum, kEuroc, kAsl, kKitti, kLog };

std::optional<TrajectoryFormat> ParseTrajectoryFormat(const std::string& name);
std::string TrajectoryFormatName(TrajectoryFormat format);  // "auto", "tum", ...

// Largest accepted | |q| - 1 | (and max |R^T R - I| for KITTI) before normalising: the one
// tolerance of every reader (core/physical_limits.h).
constexpr double kQuaternionNormTolerance = limits::kUnitNormTolerance;

struct TrajectoryReadOptions {
  TrajectoryFormat format = TrajectoryFormat::kAuto;
  bool sort = false;               // sort rows by stamp instead of refusing rows out of order
  bool refuse_duplicates = false;  // mavloc's own files: a repeated stamp is an error
  std::string times_path;          // KITTI: one stamp [s] per pose
};

// How a file was read: everything the report's protocol says about it.
struct TrajectoryReadReport {
  std::string path;
  TrajectoryFormat format = TrajectoryFormat::kAuto;  // the format used (never kAuto)
  bool format_forced = false;                         // given by the user
  std::string layout;      // e.g. "tum (8 columns)", "asl by header: #timestamp,x,y,..."
  std::string times_path;  // KITTI times file
  bool has_stamps = true;  // false: KITTI without times (stamp i = i seconds)
  size_t rows = 0;         // data rows in the file
  size_t duplicates_dropped = 0;
  long first_duplicate_line = 0;  // line of the first dropped row (0: none)
  bool sorted = false;            // --sort was given
  size_t rows_out_of_order = 0;   // rows moved by sorting
  long first_out_of_order_line = 0;
  size_t quaternions_normalised = 0;  // rows with | |q| - 1 | > 1e-6
  double max_quaternion_norm_error = 0.0;
  bool has_velocity = false;  // v_W read from the file
  bool has_biases = false;    // b_g, b_a read from the file
  bool had_bom = false, had_crlf = false;
  // A LOG:TOPIC: the log reader's notes (ULog: dropped repeated or earlier stamps and PX4 "invalid"
  // markers, truncated or corrupt messages), each "LOG: note".
  std::vector<std::string> log_notes;
};

// Velocity and biases of one pose, when the file has them.
struct TrajectoryMotion {
  Eigen::Vector3d v_W = Eigen::Vector3d::Zero();
  Eigen::Vector3d b_g = Eigen::Vector3d::Zero();  // gyro bias, rad/s
  Eigen::Vector3d b_a = Eigen::Vector3d::Zero();  // accelerometer bias, m/s^2
};

// The poses alone unless the file has velocities or biases (a million poses: 64 MB).
struct LoadedTrajectory {
  std::vector<StampedPose> poses;        // sorted, unique stamps
  std::vector<TrajectoryMotion> motion;  // one per pose when report.has_velocity or has_biases
  TrajectoryReadReport report;
  const std::vector<StampedPose>& Poses() const { return poses; }
  std::vector<GroundTruthState> States() const;  // poses with their motion (zero without)
};

// Throws InputError (file:line, field) for anything it cannot read: missing file, no data rows, a
// field that is not a finite number, a wrong number of fields, an undetectable format, a
// quaternion or rotation far from unit, rows out of order (without sort), a times file whose
// count differs from the poses'.
LoadedTrajectory ReadTrajectory(const std::string& path, const TrajectoryReadOptions& options = {});

// One line for the terminal and the report when rows were dropped or sorted (empty otherwise):
// "F: 3 rows with a repeated timestamp dropped (kept the first), first at F:12".
std::string DescribeRowFixes(const TrajectoryReadReport& report);

// How many of the file's data rows became poses, and why the others did not: "" when every row
// did, else "146 of 7228 rows (7082 with a repeated timestamp dropped, kept the first)".
std::string DescribeRowsKept(const TrajectoryReadReport& report, size_t poses);

}  // namespace mavloc
