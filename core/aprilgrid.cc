#include "core/aprilgrid.h"

#include <cmath>
#include <sstream>

namespace mavloc {

std::string AprilgridTarget::Validate() const {
  std::ostringstream why;
  if (tag_rows <= 0)
    why << "tag_rows must be positive (got " << tag_rows << ")";
  else if (tag_cols <= 0)
    why << "tag_cols must be positive (got " << tag_cols << ")";
  else if (!(tag_size_m > 0.0) || !std::isfinite(tag_size_m))
    why << "tag_size must be a positive length in metres (got " << tag_size_m << ")";
  else if (!(tag_spacing >= 0.0) || !std::isfinite(tag_spacing))
    why << "tag_spacing must be a non-negative ratio (got " << tag_spacing << ")";
  return why.str();
}

Eigen::Vector3d AprilgridCorner(const AprilgridTarget& target, int tag_id, int corner_idx) {
  const int row = tag_id / target.tag_cols;
  const int col = tag_id % target.tag_cols;
  const double s = target.tag_size_m;
  const double x0 = col * target.PitchM();
  const double y0 = row * target.PitchM();
  const bool right = corner_idx == 1 || corner_idx == 2;
  const bool top = corner_idx >= 2;
  return Eigen::Vector3d(x0 + (right ? s : 0.0), y0 + (top ? s : 0.0), 0.0);
}

int KalibrPointIndex(const AprilgridTarget& target, int tag_id, int corner_idx) {
  const int row = tag_id / target.tag_cols;
  const int col = tag_id % target.tag_cols;
  const int right = (corner_idx == 1 || corner_idx == 2) ? 1 : 0;
  const int top = corner_idx >= 2 ? 1 : 0;
  return (2 * row + top) * 2 * target.tag_cols + 2 * col + right;
}

std::map<int, TagInfo> AprilgridTags(const AprilgridTarget& target) {
  std::map<int, TagInfo> tags;
  const double h = 0.5 * target.tag_size_m;
  for (int id = 0; id < target.NumTags(); ++id) {
    TagInfo tag;
    tag.id = id;
    tag.size_m = target.tag_size_m;
    tag.T_W_T = Pose(Eigen::Quaterniond::Identity(),
                     AprilgridCorner(target, id, 0) + Eigen::Vector3d(h, h, 0.0));
    tags[id] = tag;
  }
  return tags;
}

}  // namespace mavloc
