// Kalibr's aprilgrid calibration target (kalibr/aslam_cv "GridCalibrationTargetAprilgrid"):
// tagRows x tagCols tag36h11 tags with a 2-bit black border, edge length tag_size_m (the black
// square, edge to edge), separated by tag_spacing * tag_size_m, with a black square of that size at
// every tag corner. The board frame M has its origin at the outer corner of tag 0, x along the
// rows, y along the columns, z out of the board towards the camera (z = 0 on the board).
//
// Numbering, exactly as Kalibr (and yac's per-image corner files, `tag_id, corner_idx`):
//   tag id = row * tag_cols + col, row 0 at y = 0, col 0 at x = 0;
//   corner_idx 0..3 = (0, 0), (s, 0), (s, s), (0, s) from the tag's origin corner
//     (bottom-left, bottom-right, top-right, top-left seen from +z, s = tag_size_m), which is
//     mavloc's own corner order (core/tag_geometry.h), so a tag's frame in M is a translation;
//   Kalibr's grid point index (2 * tag_rows x 2 * tag_cols points, row-major from the origin):
//     point = (2 row + (corner_idx >= 2)) * 2 tag_cols + 2 col + (corner_idx == 1 || corner_idx ==
//     2)
//       12-----13  14-----15
//       | TAG 2 |  | TAG 3 |
//       8-------9  10-----11
//       4-------5  6-------7
//       | TAG 0 |  | TAG 1 |
//       0-------1  2-------3
#pragma once

#include <Eigen/Core>
#include <map>

#include "core/dataset.h"

namespace mavloc {

struct AprilgridTarget {
  int tag_rows = 0;
  int tag_cols = 0;
  double tag_size_m = 0.0;   // black square edge to edge
  double tag_spacing = 0.0;  // gap between tags as a ratio of tag_size_m

  int NumTags() const { return tag_rows * tag_cols; }
  // Centre-to-centre distance of neighbouring tags.
  double PitchM() const { return tag_size_m * (1.0 + tag_spacing); }
  // Empty when valid, else what is wrong (non-positive rows/cols/size, negative spacing).
  std::string Validate() const;
};

// Corner corner_idx (0..3) of tag tag_id in the board frame M.
Eigen::Vector3d AprilgridCorner(const AprilgridTarget& target, int tag_id, int corner_idx);
// Kalibr's grid point index of a tag corner (see above).
int KalibrPointIndex(const AprilgridTarget& target, int tag_id, int corner_idx);
// The target's tags as map tags (TagInfo::T_W_T holds T_M_T: identity rotation, translation to the
// tag centre), ids 0 .. NumTags() - 1.
std::map<int, TagInfo> AprilgridTags(const AprilgridTarget& target);

}  // namespace mavloc
