// New corners for the feature tracker, spread over the image: the image is cut into a grid of
// cells and each cell is filled up to its share of the target count with FAST corners (Rosten &
// Drummond, ECCV 2006), strongest first, none closer than min_distance_px to an existing track or
// to a corner already taken. A cell where the global FAST threshold finds nothing is searched
// again with the lower threshold (low-contrast walls still get corners; a flat or black cell gets
// none: FAST's threshold is absolute).
#pragma once

#include <opencv2/core.hpp>
#include <vector>

namespace mavloc {

struct GridDetectorOptions {
  int grid_cols = 8;
  int grid_rows = 5;
  int max_features = 150;  // target of tracks + new corners over the whole image
  double min_distance_px = 20.0;
  int fast_threshold = 20;     // intensity difference (8-bit grey levels)
  int fast_threshold_low = 7;  // second try in cells where the first found nothing
  int border_px = 10;          // no corner closer than this to the image edge
};

// Corners (pixel centres, OpenCV convention) to add to `existing`, at most max_features minus the
// existing count in all.
std::vector<cv::Point2f> DetectInGrid(const cv::Mat& gray, const std::vector<cv::Point2f>& existing,
                                      const GridDetectorOptions& options);

}  // namespace mavloc
