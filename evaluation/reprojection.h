// Reprojection statistics of an estimate on a dataset's tag corners: every tags0 / tags1 corner
// is reprojected through the estimated body pose at its stamp (interpolated between estimate
// poses no more than max_gap_s apart), the camera's T_B_C (the estimate's own when it estimated
// it, else the dataset's) and, on a board map, the estimate's T_W_M. This is the one measure of
// accuracy a log without ground truth still offers; it reads the estimate at the image stamps
// (a time offset an estimator estimated is not applied here: its own statistics include it).
#pragma once

#include <string>
#include <vector>

#include "core/dataset.h"
#include "core/estimate.h"

namespace mavloc {

struct ReprojectionStatistics {
  std::string camera;   // "cam0", "cam1"
  int corners = 0;      // corners reprojected
  int unmatched = 0;    // corners with no estimate pose at their stamp, or < 5 cm in front
  int off_image = 0;    // reprojected more than half an image outside it (a pose far off)
  double rms_px = 0.0;  // over the corners reprojected near the image
  double median_px = 0.0;
  double max_px = 0.0;
  int over_3px = 0;  // corners with an error above 3 px
};

// One entry per camera with tag observations; empty when the estimate has no poses, the map has
// no tags, or the dataset has no tag observations.
std::vector<ReprojectionStatistics> ComputeTagReprojection(const Dataset& dataset,
                                                           const Estimate& estimate,
                                                           double max_gap_s = 0.2);

}  // namespace mavloc
