// KITTI odometry pose files (Geiger et al., CVPR 2012, devkit readme): one pose per line, the
// first three rows of the 4x4 matrix T_W_C, row-major, 12 numbers separated by spaces; evo's
// read_kitti_poses_file reads the same. Stamps come from a separate times file (KITTI's
// sequences/NN/times.txt: one stamp in seconds per line).
#pragma once

#include <string>
#include <vector>

#include "core/pose.h"
#include "datasets/io/trajectory_formats/trajectory_text.h"

namespace mavloc {

struct KittiRowsResult {
  std::vector<Pose> poses;
  std::vector<long> lines;
  size_t rotations_projected = 0;  // rows with max |R^T R - I| > 1e-6 (projected onto SO(3))
  double max_orthonormality_error = 0.0;
};

// Every row must have exactly 12 finite numbers with a rotation block within
// kQuaternionNormTolerance of orthonormal and det > 0; throws InputError (file:line, field) else.
KittiRowsResult ParseKittiRows(const TrajectoryText& text);

// One stamp [s] per non-comment line (exact decimal conversion to ns); throws InputError.
struct KittiTimes {
  std::vector<TimeNs> t_ns;
  std::vector<long> lines;
};
KittiTimes ReadKittiTimes(const std::string& path);

// The text of a KITTI pose file and of its times file (seconds with 9 decimals).
std::string KittiPosesText(const std::vector<StampedPose>& poses);
std::string KittiTimesText(const std::vector<StampedPose>& poses);

}  // namespace mavloc
