#include "datasets/io/tum_io.h"

#include <fmt/format.h>

#include <iterator>

#include "core/atomic_file.h"
#include "datasets/io/trajectory_formats/trajectory_format.h"

namespace mavloc {

std::vector<StampedPose> ReadTumTrajectory(const std::string& path) {
  TrajectoryReadOptions options;
  options.format = TrajectoryFormat::kTum;
  options.refuse_duplicates = true;
  return ReadTrajectory(path, options).Poses();
}

std::string TumTrajectoryText(const std::vector<StampedPose>& poses) {
  std::string text = "# timestamp tx ty tz qx qy qz qw  (mavloc: T_W_B, timestamp in seconds)\n";
  // Formatted in place at the end of the text (no string per line); about 90 bytes a line.
  text.reserve(text.size() + 96 * poses.size());
  auto out = std::back_inserter(text);
  for (const auto& pose : poses) {
    const auto& p = pose.T_W_B.p;
    const auto& q = pose.T_W_B.q;
    fmt::format_to(out, "{}.{:09d} {:.12g} {:.12g} {:.12g} {:.12g} {:.12g} {:.12g} {:.12g}\n",
                   pose.t_ns / kNsPerSecond, pose.t_ns % kNsPerSecond, p.x(), p.y(), p.z(), q.x(),
                   q.y(), q.z(), q.w());
  }
  return text;
}

void WriteTumTrajectory(const std::vector<StampedPose>& poses, const std::string& path) {
  WriteFileAtomically(path, TumTrajectoryText(poses));
}

}  // namespace mavloc
