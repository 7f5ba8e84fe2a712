#include "frontends/apriltag/aprilgrid_detector.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>
#include <vector>

namespace mavloc {

cv::Mat SeparateDiagonalJunctions(const cv::Mat& gray) {
  cv::Mat out;
  // Anchor (0, 0): the element covers (u..u+1, v..v+1).
  cv::dilate(gray, out, cv::Mat::ones(2, 2, CV_8U), cv::Point(0, 0), 1, cv::BORDER_REPLICATE);
  return out;
}

std::array<Eigen::Vector2d, 4> UndoJunctionSeparation(const std::array<Eigen::Vector2d, 4>& quad) {
  const Eigen::Vector2d centre = 0.25 * (quad[0] + quad[1] + quad[2] + quad[3]);
  // Edge k runs from quad[k] to quad[k + 1]: n . p = c with n the outward unit normal.
  std::array<Eigen::Vector2d, 4> normal;
  std::array<double, 4> offset;
  for (int k = 0; k < 4; ++k) {
    const Eigen::Vector2d& a = quad[k];
    const Eigen::Vector2d& b = quad[(k + 1) % 4];
    const Eigen::Vector2d t = b - a;
    Eigen::Vector2d n(t.y(), -t.x());
    if (n.norm() == 0.0) return quad;
    n.normalize();
    if (n.dot(a - centre) < 0.0) n = -n;
    normal[k] = n;
    offset[k] = n.dot(a) + std::max(0.0, n.x()) + std::max(0.0, n.y());
  }
  std::array<Eigen::Vector2d, 4> out;
  for (int k = 0; k < 4; ++k) {
    // Corner k joins edge k - 1 and edge k.
    const int prev = (k + 3) % 4;
    Eigen::Matrix2d A;
    A.row(0) = normal[prev].transpose();
    A.row(1) = normal[k].transpose();
    const double det = A.determinant();
    if (std::abs(det) < 1e-9) return quad;
    out[k] = A.inverse() * Eigen::Vector2d(offset[prev], offset[k]);
  }
  return out;
}

cv::Mat RefinementImage(const cv::Mat& gray, const AprilgridDetectOptions& options) {
  cv::Mat image;
  gray.convertTo(image, CV_32F);
  if (options.refine_blur_sigma_px > 0.0)
    cv::GaussianBlur(image, image, cv::Size(), options.refine_blur_sigma_px,
                     options.refine_blur_sigma_px, cv::BORDER_REPLICATE);
  return image;
}

bool RefineAprilgridCorners(const cv::Mat& image, const AprilgridDetectOptions& options,
                            std::array<Eigen::Vector2d, 4>* corners_px) {
  auto& corners = *corners_px;
  double shortest_px = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 4; ++k)
    shortest_px = std::min(shortest_px, (corners[(k + 1) % 4] - corners[k]).norm());
  int half = static_cast<int>(std::lround(options.window_fraction * shortest_px));
  half = std::clamp(half, options.min_half_window_px, options.max_half_window_px);
  const double max_shift_px =
      std::max(options.max_shift_px, options.max_shift_fraction * shortest_px);
  // The window (and cornerSubPix's one-pixel gradient margin) must lie inside the image: near the
  // border the window shrinks, down to min_half_window_px.
  double border_px = std::numeric_limits<double>::infinity();
  std::vector<cv::Point2f> points;
  for (const auto& c : corners) {
    border_px = std::min({border_px, c.x(), c.y(), image.cols - 1 - c.x(), image.rows - 1 - c.y()});
    points.emplace_back(static_cast<float>(c.x()), static_cast<float>(c.y()));
  }
  if (!(border_px >= 0.0)) return false;
  half = std::min(half, static_cast<int>(std::floor(border_px)) - 2);
  if (half < options.min_half_window_px) return false;
  cv::cornerSubPix(image, points, cv::Size(half, half), cv::Size(-1, -1),
                   cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 50, 1e-3));
  std::array<Eigen::Vector2d, 4> refined;
  for (int k = 0; k < 4; ++k) {
    refined[k] = Eigen::Vector2d(points[k].x, points[k].y);
    if (!((refined[k] - corners[k]).norm() <= max_shift_px)) return false;
  }
  corners = refined;
  return true;
}

}  // namespace mavloc
