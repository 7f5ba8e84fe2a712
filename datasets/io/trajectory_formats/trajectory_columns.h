// Which column holds what: the positional layouts of TUM and EuRoC files, the header-name mapping
// of ASL-style CSVs (Kimera-VIO, EuRoC, OpenVINS, `rostopic echo -p` CSVs), and the detection of a
// file's format from its content (rules in trajectory_format.h).
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "datasets/io/trajectory_formats/trajectory_format.h"
#include "datasets/io/trajectory_formats/trajectory_text.h"

namespace mavloc {

enum class StampUnit { kSeconds, kNanoseconds };

struct PoseColumnLayout {
  TrajectoryFormat format = TrajectoryFormat::kTum;
  std::string description;  // for the report
  int t = -1;
  std::array<int, 3> p{-1, -1, -1};
  std::array<int, 4> q_wxyz{-1, -1, -1, -1};
  // Attitude as roll, pitch, yaw (R = Rz(yaw) Ry(pitch) Rx(roll), core/rotation.h) when the header
  // names these and no quaternion: mavloc's own quantity CSVs (`mavloc run --out FILE.csv`).
  std::array<int, 3> rpy{-1, -1, -1};
  double rpy_to_rad = 1.0;  // 1 for radians, pi/180 for a header stating degrees
  std::array<int, 3> v{-1, -1, -1};
  std::array<int, 3> b_g{-1, -1, -1};
  std::array<int, 3> b_a{-1, -1, -1};
  StampUnit unit = StampUnit::kSeconds;
  bool unit_stated = false;        // the header states the stamp's unit ("[ns]", "(s)", "_ns")
  size_t min_fields = 8;           // every row needs at least this many fields
  size_t exact_fields = 0;         // when > 0, every row needs exactly this many
  std::vector<std::string> names;  // column names for messages (index -> name)

  std::string Name(size_t k) const;  // names[k], or "column k+1"
  bool HasVelocity() const { return v[0] >= 0 && v[1] >= 0 && v[2] >= 0; }
  bool HasQuaternion() const;
  bool HasRollPitchYaw() const;
  bool HasBiases() const;
};

// TUM: t [s] tx ty tz qx qy qz qw (fields: 8, or 20 for ov_eval's pose + covariance).
PoseColumnLayout TumLayout(size_t fields);
// EuRoC positional: t [ns], p, q (w,x,y,z), then v, b_w, b_a when there are 17 or more fields.
PoseColumnLayout EurocLayout(size_t fields);
// The layout the header's names give, or nullopt when they do not name a timestamp, a position
// and a quaternion. The stamp unit: as the header states it, else seconds for TUM names and
// whitespace tables, nanoseconds for CSVs whose first stamp is an integer.
std::optional<PoseColumnLayout> LayoutFromHeader(const TrajectoryText& text);

// The format of a file (never kAuto): throws InputError (file:line) when no rule applies.
TrajectoryFormat DetectTrajectoryFormat(const TrajectoryText& text);

}  // namespace mavloc
