#include "frontends/features/grid_detector.h"

#include <algorithm>
#include <cmath>
#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>

namespace mavloc {

namespace {

struct Cell {
  cv::Rect roi;
  int have = 0;
};

// The grid cells, with the existing tracks counted in them.
std::vector<Cell> MakeCells(const cv::Size& size, const std::vector<cv::Point2f>& existing,
                            const GridDetectorOptions& o) {
  std::vector<Cell> cells;
  for (int r = 0; r < o.grid_rows; ++r) {
    for (int c = 0; c < o.grid_cols; ++c) {
      const int x0 = c * size.width / o.grid_cols, x1 = (c + 1) * size.width / o.grid_cols;
      const int y0 = r * size.height / o.grid_rows, y1 = (r + 1) * size.height / o.grid_rows;
      cells.push_back({cv::Rect(x0, y0, x1 - x0, y1 - y0), 0});
    }
  }
  for (const cv::Point2f& p : existing) {
    const int c = std::clamp(static_cast<int>(p.x * o.grid_cols / size.width), 0, o.grid_cols - 1);
    const int r = std::clamp(static_cast<int>(p.y * o.grid_rows / size.height), 0, o.grid_rows - 1);
    ++cells[r * o.grid_cols + c].have;
  }
  return cells;
}

// FAST corners inside roi (image coordinates), strongest first.
std::vector<cv::KeyPoint> FastInCell(const cv::Mat& gray, const cv::Rect& roi, int threshold) {
  std::vector<cv::KeyPoint> keypoints;
  cv::FAST(gray(roi), keypoints, threshold, true);
  for (auto& k : keypoints)
    k.pt += cv::Point2f(static_cast<float>(roi.x), static_cast<float>(roi.y));
  std::sort(keypoints.begin(), keypoints.end(),
            [](const cv::KeyPoint& a, const cv::KeyPoint& b) { return a.response > b.response; });
  return keypoints;
}

}  // namespace

std::vector<cv::Point2f> DetectInGrid(const cv::Mat& gray, const std::vector<cv::Point2f>& existing,
                                      const GridDetectorOptions& o) {
  std::vector<cv::Point2f> added;
  const int cells_count = o.grid_cols * o.grid_rows;
  if (gray.empty() || cells_count <= 0 || static_cast<int>(existing.size()) >= o.max_features)
    return added;
  // Occupancy: a pixel is taken when it lies within min_distance_px of a track or a new corner.
  cv::Mat taken(gray.size(), CV_8U, cv::Scalar(0));
  const int radius = std::max(1, static_cast<int>(std::lround(o.min_distance_px)));
  for (const cv::Point2f& p : existing) cv::circle(taken, p, radius, cv::Scalar(255), cv::FILLED);
  const int per_cell = (o.max_features + cells_count - 1) / cells_count;
  int budget = o.max_features - static_cast<int>(existing.size());
  const cv::Rect inside(o.border_px, o.border_px, gray.cols - 2 * o.border_px,
                        gray.rows - 2 * o.border_px);
  if (inside.width <= 0 || inside.height <= 0) return added;
  for (const Cell& cell : MakeCells(gray.size(), existing, o)) {
    if (budget <= 0) break;
    int wanted = std::min(per_cell - cell.have, budget);
    if (wanted <= 0) continue;
    const cv::Rect roi = cell.roi & inside;
    if (roi.width < 7 || roi.height < 7) continue;  // FAST needs a radius-3 circle
    std::vector<cv::KeyPoint> candidates = FastInCell(gray, roi, o.fast_threshold);
    if (candidates.empty()) candidates = FastInCell(gray, roi, o.fast_threshold_low);
    for (const cv::KeyPoint& k : candidates) {
      if (wanted <= 0) break;
      const cv::Point pixel(static_cast<int>(k.pt.x), static_cast<int>(k.pt.y));
      if (taken.at<uint8_t>(pixel) != 0) continue;
      added.push_back(k.pt);
      cv::circle(taken, k.pt, radius, cv::Scalar(255), cv::FILLED);
      --wanted;
      --budget;
    }
  }
  return added;
}

}  // namespace mavloc
