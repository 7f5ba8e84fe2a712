#include "frontends/apriltag/aprilgrid_detector.h"

#include <apriltag/apriltag.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <opencv2/calib3d.hpp>
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

namespace {

// The homography from the tag bitmap's cell coordinates (x right, y down; the black square spans
// [border, border + width] on both axes) to the image, from the 4 corners in mavloc order
// (bottom-left, bottom-right, top-right, top-left seen with the bitmap's top row up).
cv::Matx33d AprilgridBitmapToImage(double border, double width,
                                   const std::array<Eigen::Vector2d, 4>& corners_px) {
  const double lo = border, hi = border + width;
  const std::vector<cv::Point2f> bitmap = {{static_cast<float>(lo), static_cast<float>(hi)},
                                           {static_cast<float>(hi), static_cast<float>(hi)},
                                           {static_cast<float>(hi), static_cast<float>(lo)},
                                           {static_cast<float>(lo), static_cast<float>(lo)}};
  std::vector<cv::Point2f> image;
  for (const auto& c : corners_px)
    image.emplace_back(static_cast<float>(c.x()), static_cast<float>(c.y()));
  return cv::Matx33d(cv::getPerspectiveTransform(bitmap, image));
}

// Bilinear sample of an 8-bit image at (x, y) (pixel centres at integers); false outside.
bool AprilgridSampleBilinear(const cv::Mat& gray, double x, double y, double* value) {
  if (!(x >= 0.0 && y >= 0.0 && x <= gray.cols - 1.0 && y <= gray.rows - 1.0)) return false;
  const int x0 = std::min(static_cast<int>(x), gray.cols - 2);
  const int y0 = std::min(static_cast<int>(y), gray.rows - 2);
  const double fx = x - x0, fy = y - y0;
  const auto at = [&](int v, int u) { return static_cast<double>(gray.at<uint8_t>(v, u)); };
  *value = (1 - fy) * ((1 - fx) * at(y0, x0) + fx * at(y0, x0 + 1)) +
           fy * ((1 - fx) * at(y0 + 1, x0) + fx * at(y0 + 1, x0 + 1));
  return true;
}

}  // namespace

int AprilgridCodeDistance(const cv::Mat& gray, const struct apriltag_family& family, int id,
                          const std::array<Eigen::Vector2d, 4>& corners_px, double* contrast_grey) {
  if (id < 0 || id >= static_cast<int>(family.ncodes) || gray.cols < 2 || gray.rows < 2) return -1;
  const int width = family.width_at_border;
  const int border = (family.total_width - width) / 2;  // the white ring's cells
  const cv::Matx33d H = AprilgridBitmapToImage(border, width, corners_px);
  bool inside = true;
  const auto sample = [&](double cell_x, double cell_y) {
    const cv::Vec3d p = H * cv::Vec3d(cell_x + 0.5, cell_y + 0.5, 1.0);
    double value = 0.0;
    if (!(std::abs(p[2]) > 1e-12) ||
        !AprilgridSampleBilinear(gray, p[0] / p[2], p[1] / p[2], &value))
      inside = false;
    return value;
  };
  // The white ring (cells just outside the black square) and the black square's outer ring.
  double white = 0.0, black = 0.0;
  int n_white = 0, n_black = 0;
  for (int i = border; i < border + width; ++i) {
    for (const auto& [x, y] : {std::pair{i, border - 1}, std::pair{i, border + width},
                               std::pair{border - 1, i}, std::pair{border + width, i}}) {
      white += sample(x, y);
      ++n_white;
    }
    for (const auto& [x, y] : {std::pair{i, border}, std::pair{i, border + width - 1},
                               std::pair{border, i}, std::pair{border + width - 1, i}}) {
      black += sample(x, y);
      ++n_black;
    }
  }
  white /= n_white;
  black /= n_black;
  if (contrast_grey != nullptr) *contrast_grey = white - black;
  const double threshold = 0.5 * (white + black);
  // libapriltag's bit layout: bit i (most significant first) at (bit_x, bit_y) from the black
  // square's first cell; a set bit is white.
  const uint64_t code = family.codes[id];
  int distance = 0;
  for (uint32_t i = 0; i < family.nbits; ++i) {
    const bool expect_white = ((code >> (family.nbits - 1 - i)) & 1u) != 0;
    const bool white_cell = sample(border + family.bit_x[i], border + family.bit_y[i]) > threshold;
    distance += expect_white != white_cell;
  }
  return inside ? distance : -1;
}

std::vector<PredictedAprilgridTag> PredictMissingAprilgridTags(
    const AprilgridTarget& target, const std::vector<int>& found_ids,
    const std::vector<std::array<Eigen::Vector2d, 4>>& found_corners_px, const cv::Size& image_size,
    double border_px) {
  std::vector<PredictedAprilgridTag> predicted;
  if (!target.Validate().empty() || found_ids.size() != found_corners_px.size()) return predicted;
  // Board coordinates in units of the tag size (the homography is scale-free).
  const AprilgridTarget unit{target.tag_rows, target.tag_cols, 1.0, target.tag_spacing};
  std::vector<bool> found(target.NumTags(), false);
  for (const int id : found_ids)
    if (id >= 0 && id < target.NumTags()) found[id] = true;
  constexpr size_t kMaxNeighbours = 8;
  for (int id = 0; id < target.NumTags(); ++id) {
    if (found[id]) continue;
    const int row = id / target.tag_cols, col = id % target.tag_cols;
    // The found tags, nearest on the grid first (ties: by index, i.e. deterministic).
    std::vector<size_t> order;
    for (size_t i = 0; i < found_ids.size(); ++i)
      if (found_ids[i] >= 0 && found_ids[i] < target.NumTags()) order.push_back(i);
    const auto grid_distance = [&](size_t i) {
      const int r = found_ids[i] / target.tag_cols, c = found_ids[i] % target.tag_cols;
      return (r - row) * (r - row) + (c - col) * (c - col);
    };
    std::stable_sort(order.begin(), order.end(),
                     [&](size_t a, size_t b) { return grid_distance(a) < grid_distance(b); });
    if (order.size() > kMaxNeighbours) order.resize(kMaxNeighbours);
    if (order.size() < 2) continue;
    std::vector<cv::Point2d> board, image;
    for (const size_t i : order) {
      for (int k = 0; k < 4; ++k) {
        const Eigen::Vector3d p = AprilgridCorner(unit, found_ids[i], k);
        board.emplace_back(p.x(), p.y());
        image.emplace_back(found_corners_px[i][k].x(), found_corners_px[i][k].y());
      }
    }
    const cv::Mat H = cv::findHomography(board, image, 0);
    if (H.empty()) continue;
    const cv::Matx33d Hx(H);
    PredictedAprilgridTag tag;
    tag.id = id;
    bool inside = true;
    const Eigen::Vector3d centre =
        0.25 * (AprilgridCorner(unit, id, 0) + AprilgridCorner(unit, id, 2));
    for (int k = 0; k < 4; ++k) {
      const Eigen::Vector3d p = AprilgridCorner(unit, id, k);
      // The corner, and the corner of the white ring (0.1 tag sizes further out).
      for (const double scale : {1.0, 1.2}) {
        const Eigen::Vector3d q = centre + scale * (p - centre);
        const cv::Vec3d uv = Hx * cv::Vec3d(q.x(), q.y(), 1.0);
        if (!(uv[2] > 1e-12 || uv[2] < -1e-12)) {
          inside = false;
          continue;
        }
        const double u = uv[0] / uv[2], v = uv[1] / uv[2];
        if (!(u >= border_px && v >= border_px && u <= image_size.width - 1 - border_px &&
              v <= image_size.height - 1 - border_px))
          inside = false;
        if (scale == 1.0) tag.corners_px[k] = Eigen::Vector2d(u, v);
      }
    }
    if (inside) predicted.push_back(tag);
  }
  return predicted;
}

}  // namespace mavloc
