#include "datasets/rendering/tag_renderer.h"

#include <apriltag/apriltag.h>
#include <apriltag/tag16h5.h>
#include <apriltag/tag25h9.h>
#include <apriltag/tag36h11.h>
#include <apriltag/tagStandard41h12.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>

#include "core/errors.h"
#include "core/random.h"

namespace mavloc {

namespace {

struct Family {
  const char* name;
  apriltag_family_t* (*create)();
  void (*destroy)(apriltag_family_t*);
};

constexpr Family kFamilies[] = {
    {"tag36h11", tag36h11_create, tag36h11_destroy},
    {"tag25h9", tag25h9_create, tag25h9_destroy},
    {"tag16h5", tag16h5_create, tag16h5_destroy},
    {"tagStandard41h12", tagStandard41h12_create, tagStandard41h12_destroy},
};

// Kalibr's aprilgrid tags: tag36h11 with one more black ring inside the white one
// (frontends/apriltag/aprilgrid_family.h builds the same family for the detector; the detector's
// tests check that its bitmaps are these).
bool IsAprilgrid(const std::string& name) { return name == "aprilgrid" || name == "tag36h11b2"; }

// Owns one libapriltag family for the duration of a call.
class FamilyHandle {
 public:
  explicit FamilyHandle(const std::string& requested) {
    const std::string name = IsAprilgrid(requested) ? "tag36h11" : requested;
    for (const auto& family : kFamilies) {
      if (name == family.name) {
        functions_ = &family;
        family_ = family.create();
        return;
      }
    }
    throw InputError("", 0, "family", "unknown tag family '" + requested + "' for rendering");
  }
  ~FamilyHandle() { functions_->destroy(family_); }
  FamilyHandle(const FamilyHandle&) = delete;
  FamilyHandle& operator=(const FamilyHandle&) = delete;
  apriltag_family_t* get() const { return family_; }

 private:
  const Family* functions_ = nullptr;
  apriltag_family_t* family_ = nullptr;
};

// Smooth value noise in [-1, 1] on a unit lattice (deterministic hash of the lattice point).
double TextureLatticeValue(int64_t i, int64_t j, uint64_t salt) {
  const uint64_t h = SplitMix64(static_cast<uint64_t>(i) * 0x9E3779B97F4A7C15ull ^
                                SplitMix64(static_cast<uint64_t>(j) + salt));
  return static_cast<double>(h >> 11) * (2.0 / 9007199254740992.0) - 1.0;
}

double TextureNoise(double x, double y, uint64_t salt) {
  const double fx = std::floor(x), fy = std::floor(y);
  const int64_t i = static_cast<int64_t>(fx), j = static_cast<int64_t>(fy);
  double sx = x - fx, sy = y - fy;
  sx = sx * sx * (3.0 - 2.0 * sx);
  sy = sy * sy * (3.0 - 2.0 * sy);
  const double a = TextureLatticeValue(i, j, salt), b = TextureLatticeValue(i + 1, j, salt);
  const double c = TextureLatticeValue(i, j + 1, salt), d = TextureLatticeValue(i + 1, j + 1, salt);
  return (a * (1 - sx) + b * sx) * (1 - sy) + (c * (1 - sx) + d * sx) * sy;
}

// Inverse of the plane-to-normalized-image homography of plane frame P seen from camera C.
Eigen::Matrix3d NormalizedToPlaneHomography(const Pose& T_C_P) {
  Eigen::Matrix3d G;
  const Eigen::Matrix3d R = T_C_P.R();
  G.col(0) = R.col(0);
  G.col(1) = R.col(1);
  G.col(2) = T_C_P.p;
  return G.inverse();
}

constexpr double kFloorStepM = 0.005;

}  // namespace

cv::Mat TagFamilyBitmap(const std::string& family_name, int id) {
  const FamilyHandle family(family_name);
  if (id < 0 || static_cast<uint32_t>(id) >= family.get()->ncodes)
    throw InputError("", 0, "tag id",
                     "id " + std::to_string(id) + " is not in family " + family_name);
  image_u8_t* image = apriltag_to_image(family.get(), id);
  cv::Mat bitmap(image->height, image->width, CV_8UC1);
  for (int r = 0; r < image->height; ++r)
    for (int c = 0; c < image->width; ++c)
      bitmap.at<uint8_t>(r, c) = image->buf[r * image->stride + c];
  // libapriltag allocates the image with calloc and does not export image_u8_destroy.
  std::free(image->buf);
  std::free(image);
  if (!IsAprilgrid(family_name)) return bitmap;
  // White ring, then two black rings (tag36h11's black ring widened), then the 6 x 6 data.
  cv::Mat wide(bitmap.rows + 2, bitmap.cols + 2, CV_8UC1, cv::Scalar(0));
  bitmap(cv::Rect(1, 1, bitmap.cols - 2, bitmap.rows - 2))
      .copyTo(wide(cv::Rect(2, 2, bitmap.cols - 2, bitmap.rows - 2)));
  wide.row(0).setTo(255);
  wide.row(wide.rows - 1).setTo(255);
  wide.col(0).setTo(255);
  wide.col(wide.cols - 1).setTo(255);
  return wide;
}

int TagFamilyBorderCells(const std::string& family_name) {
  const FamilyHandle family(family_name);
  return family.get()->width_at_border + (IsAprilgrid(family_name) ? 2 : 0);
}

TagRenderer::TagRenderer(const CameraModel& camera, const std::map<int, TagInfo>& tags,
                         const TagRenderOptions& options, const TagRenderExtras& extras)
    : camera_(camera), options_(options) {
  if (options.supersampling < 1) throw InputError("", 0, "supersampling", "must be >= 1");
  const int border_cells = TagFamilyBorderCells(options.family);
  for (const auto& [id, info] : tags) {
    PlaneTag tag;
    tag.id = id;
    tag.T_W_T = info.T_W_T;
    tag.bitmap = TagFamilyBitmap(options.family, id);
    total_cells_ = tag.bitmap.cols;
    tag.cell_m = info.size_m / border_cells;
    tag.half_x_m = tag.half_y_m =
        0.5 * tag.cell_m * (total_cells_ + 2.0 * options.page_margin_cells);
    tags_.push_back(tag);
  }
  auto add_rectangles = [&](const std::vector<RenderRectangle>& rectangles, PlaneTag::Kind kind) {
    for (const auto& rectangle : rectangles) {
      if (!(rectangle.half_x_m > 0.0 && rectangle.half_y_m > 0.0))
        throw InputError("", 0, "rectangle", "half extents must be positive");
      PlaneTag item;
      item.kind = kind;
      item.T_W_T = rectangle.T_W_R;
      item.half_x_m = rectangle.half_x_m;
      item.half_y_m = rectangle.half_y_m;
      tags_.push_back(item);
    }
  };
  add_rectangles(extras.black_squares, PlaneTag::Kind::kSquare);
  add_rectangles(extras.papers, PlaneTag::Kind::kPaper);
  // The floor texture on a grid 3 m beyond the tags (procedural outside it).
  double x_min = 0.0, x_max = 0.0, y_min = 0.0, y_max = 0.0;
  for (const auto& tag : tags_) {
    x_min = std::min(x_min, tag.T_W_T.p.x());
    x_max = std::max(x_max, tag.T_W_T.p.x());
    y_min = std::min(y_min, tag.T_W_T.p.y());
    y_max = std::max(y_max, tag.T_W_T.p.y());
  }
  floor_x0_ = x_min - 3.0;
  floor_y0_ = y_min - 3.0;
  floor_ = cv::Mat(static_cast<int>((y_max - y_min + 6.0) / kFloorStepM) + 2,
                   static_cast<int>((x_max - x_min + 6.0) / kFloorStepM) + 2, CV_32F);
  for (int r = 0; r < floor_.rows; ++r) {
    float* row = floor_.ptr<float>(r);
    for (int c = 0; c < floor_.cols; ++c)
      row[c] = static_cast<float>(
          FloorGreyProcedural(floor_x0_ + c * kFloorStepM, floor_y0_ + r * kFloorStepM));
  }
  const int W = camera.width(), H = camera.height();
  corner_x_ = cv::Mat(H + 1, W + 1, CV_64F);
  corner_y_ = cv::Mat(H + 1, W + 1, CV_64F);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (int j = 0; j <= H; ++j) {
    for (int i = 0; i <= W; ++i) {
      const auto xy = camera.PixelToNormalized(Eigen::Vector2d(i - 0.5, j - 0.5));
      corner_x_.at<double>(j, i) = xy ? xy->x() : nan;
      corner_y_.at<double>(j, i) = xy ? xy->y() : nan;
    }
  }
}

double TagRenderer::FloorGrey(double x_W, double y_W) const {
  const double gx = (x_W - floor_x0_) / kFloorStepM, gy = (y_W - floor_y0_) / kFloorStepM;
  if (!(gx >= 0.0 && gy >= 0.0 && gx < floor_.cols - 1 && gy < floor_.rows - 1))
    return FloorGreyProcedural(x_W, y_W);
  const int c = static_cast<int>(gx), r = static_cast<int>(gy);
  const double s = gx - c, t = gy - r;
  const float* row0 = floor_.ptr<float>(r);
  const float* row1 = floor_.ptr<float>(r + 1);
  return (1 - t) * ((1 - s) * row0[c] + s * row0[c + 1]) +
         t * ((1 - s) * row1[c] + s * row1[c + 1]);
}

double TagRenderer::FloorGreyProcedural(double x_W, double y_W) const {
  // Concrete-like: two octaves of value noise, and darker grout lines every metre (1.5 cm wide).
  double g = options_.floor_grey +
             options_.floor_contrast * (0.7 * TextureNoise(x_W / 0.35, y_W / 0.35, 1) +
                                        0.3 * TextureNoise(x_W / 0.06, y_W / 0.06, 2));
  const double fx = x_W - std::round(x_W), fy = y_W - std::round(y_W);
  if (std::abs(fx) < 0.0075 || std::abs(fy) < 0.0075) g *= 0.6;
  return std::clamp(g, 0.0, 1.0);
}

cv::Mat TagRenderer::RenderIdeal(const Pose& T_W_C) const {
  const int W = camera_.width(), H = camera_.height();
  cv::Mat image(H, W, CV_32F);
  const Pose T_C_W = T_W_C.Inverse();
  const Eigen::Matrix3d H_floor = NormalizedToPlaneHomography(T_C_W);

  // Per tag: the homography and the pixel box that may see its page.
  struct Visible {
    const PlaneTag* tag;
    Eigen::Matrix3d H;
    int u0, u1, v0, v1;
  };
  std::vector<Visible> visible;
  for (const auto& tag : tags_) {
    const Pose T_C_T = T_C_W * tag.T_W_T;
    const double hx = tag.half_x_m, hy = tag.half_y_m;
    double u_min = 1e18, u_max = -1e18, v_min = 1e18, v_max = -1e18;
    bool behind = false;
    const int n = 8;  // points per page edge (distortion bends the edges)
    for (int e = 0; e < 4 && !behind; ++e) {
      for (int k = 0; k < n; ++k) {
        const double f = -1.0 + 2.0 * k / n;  // along the edge, in [-1, 1)
        const Eigen::Vector3d p_T = e == 0   ? Eigen::Vector3d(f * hx, -hy, 0)
                                    : e == 1 ? Eigen::Vector3d(hx, f * hy, 0)
                                    : e == 2 ? Eigen::Vector3d(-f * hx, hy, 0)
                                             : Eigen::Vector3d(-hx, -f * hy, 0);
        const Eigen::Vector3d p_C = T_C_T * p_T;
        if (p_C.z() <= 1e-3) {
          behind = true;
          break;
        }
        const Eigen::Vector2d uv = camera_.NormalizedToPixel(p_C.head<2>() / p_C.z());
        u_min = std::min(u_min, uv.x());
        u_max = std::max(u_max, uv.x());
        v_min = std::min(v_min, uv.y());
        v_max = std::max(v_max, uv.y());
      }
    }
    Visible vis{&tag, NormalizedToPlaneHomography(T_C_T), 0, W - 1, 0, H - 1};
    if (!behind) {
      // Outside the image after distortion or too far out: skip; otherwise a 2 px safety margin.
      if (u_max < -2 || v_max < -2 || u_min > W + 1 || v_min > H + 1) continue;
      vis.u0 = std::max(0, static_cast<int>(std::floor(u_min)) - 2);
      vis.u1 = std::min(W - 1, static_cast<int>(std::ceil(u_max)) + 2);
      vis.v0 = std::max(0, static_cast<int>(std::floor(v_min)) - 2);
      vis.v1 = std::min(H - 1, static_cast<int>(std::ceil(v_max)) + 2);
    }
    visible.push_back(vis);
  }

  const double half_bitmap_cells = 0.5 * total_cells_;
  // The grey seen along normalized ray (x, y, 1): nearest item in front (coplanar items within a
  // relative depth of 1e-9: the higher kind wins), else the floor. *label names the uniform region
  // hit (-1 floor, else one value per tag cell, per page margin and per square or paper).
  constexpr double kCoplanar = 1e-9;
  auto trace = [&](double x, double y, const std::vector<const Visible*>& candidates,
                   int* label) -> double {
    double best_depth = std::numeric_limits<double>::infinity();
    int best_kind = -1;
    double grey = -1.0;
    *label = -1;
    for (const Visible* vis : candidates) {
      const Eigen::Vector3d q = vis->H * Eigen::Vector3d(x, y, 1.0);
      if (q.z() <= 0.0) continue;
      const double depth = 1.0 / q.z();
      const PlaneTag& tag = *vis->tag;
      const int kind = static_cast<int>(tag.kind);
      if (depth > best_depth * (1.0 + kCoplanar)) continue;
      if (depth >= best_depth * (1.0 - kCoplanar) && kind <= best_kind) continue;
      const double qx = q.x() * depth, qy = q.y() * depth;
      if (std::abs(qx) > tag.half_x_m || std::abs(qy) > tag.half_y_m) continue;
      best_depth = depth;
      best_kind = kind;
      const int base = static_cast<int>(vis - visible.data()) * (total_cells_ * total_cells_ + 1);
      if (tag.kind == PlaneTag::Kind::kSquare) {
        grey = options_.ink_grey;
        *label = base;
        continue;
      }
      if (tag.kind == PlaneTag::Kind::kPaper) {
        grey = options_.paper_grey;
        *label = base;
        continue;
      }
      // Bitmap column from -x to +x, row from +y (row 0) to -y.
      const double col = qx / tag.cell_m + half_bitmap_cells;
      const double row = half_bitmap_cells - qy / tag.cell_m;
      if (col >= 0.0 && col < total_cells_ && row >= 0.0 && row < total_cells_) {
        const int r = static_cast<int>(row), c = static_cast<int>(col);
        grey = tag.bitmap.at<uint8_t>(r, c) < 128 ? options_.ink_grey : options_.paper_grey;
        *label = base + r * total_cells_ + c;
      } else {
        grey = options_.paper_grey;
        *label = base + total_cells_ * total_cells_;
      }
    }
    if (grey >= 0.0) return grey;
    const Eigen::Vector3d q = H_floor * Eigen::Vector3d(x, y, 1.0);
    if (q.z() <= 0.0) return 0.0;  // looking above the horizon: black
    return FloorGrey(q.x() / q.z(), q.y() / q.z());
  };

  // Region labels at the pixel corners of the boxes that may see a tag: a pixel whose four corners
  // lie in the same tag cell (or page margin) is uniform and takes one sample; the others (edges)
  // are supersampled.
  cv::Mat corner_label(H + 1, W + 1, CV_32S, cv::Scalar(-2));
  std::vector<const Visible*> candidates;
  auto candidates_at = [&](int u, int v) {
    candidates.clear();
    for (const auto& vis : visible) {
      if (u >= vis.u0 && u <= vis.u1 && v >= vis.v0 && v <= vis.v1) candidates.push_back(&vis);
    }
  };
  for (const auto& vis : visible) {
    for (int j = vis.v0; j <= vis.v1 + 1; ++j) {
      for (int i = vis.u0; i <= vis.u1 + 1; ++i) {
        int& label = corner_label.at<int>(j, i);
        if (label != -2) continue;
        const double x = corner_x_.at<double>(j, i), y = corner_y_.at<double>(j, i);
        if (std::isnan(x)) {
          label = -3;
          continue;
        }
        candidates_at(std::min(i, W - 1), std::min(j, H - 1));
        // A corner can belong to a neighbouring box too: use every tag box touching it.
        for (const auto& other : visible) {
          if (i >= other.u0 && i <= other.u1 + 1 && j >= other.v0 && j <= other.v1 + 1 &&
              std::find(candidates.begin(), candidates.end(), &other) == candidates.end())
            candidates.push_back(&other);
        }
        trace(x, y, candidates, &label);
      }
    }
  }

  const int S = options_.supersampling;
  for (int v = 0; v < H; ++v) {
    const double* x0 = corner_x_.ptr<double>(v);
    const double* x1 = corner_x_.ptr<double>(v + 1);
    const double* y0 = corner_y_.ptr<double>(v);
    const double* y1 = corner_y_.ptr<double>(v + 1);
    const int* l0 = corner_label.ptr<int>(v);
    const int* l1 = corner_label.ptr<int>(v + 1);
    float* out = image.ptr<float>(v);
    for (int u = 0; u < W; ++u) {
      if (std::isnan(x0[u]) || std::isnan(x0[u + 1]) || std::isnan(x1[u]) ||
          std::isnan(x1[u + 1])) {
        out[u] = 0.0f;
        continue;
      }
      candidates_at(u, v);
      int label = 0;
      bool uniform = candidates.empty() ||
                     (l0[u] >= -1 && l0[u] == l0[u + 1] && l0[u] == l1[u] && l0[u] == l1[u + 1]);
      // Four corners in one convex region (a tag cell, a square) mean the whole pixel is in it;
      // but a square drawn over paper or a tag's ring leaves those regions non-convex: a square's
      // tip may enter a pixel whose corners all see the paper. Pixels near a square are sampled.
      for (const Visible* vis : candidates) {
        if (!uniform) break;
        if (vis->tag->kind == PlaneTag::Kind::kSquare &&
            l0[u] != static_cast<int>(vis - visible.data()) * (total_cells_ * total_cells_ + 1))
          uniform = false;
      }
      if (uniform) {
        const double x = 0.25 * (x0[u] + x0[u + 1] + x1[u] + x1[u + 1]);
        const double y = 0.25 * (y0[u] + y0[u + 1] + y1[u] + y1[u + 1]);
        out[u] = static_cast<float>(trace(x, y, candidates, &label));
        continue;
      }
      double sum = 0.0;
      for (int b = 0; b < S; ++b) {
        const double t = (b + 0.5) / S;
        for (int a = 0; a < S; ++a) {
          const double s = (a + 0.5) / S;
          // Bilinear interpolation between the four pixel corners.
          const double x =
              (1 - t) * ((1 - s) * x0[u] + s * x0[u + 1]) + t * ((1 - s) * x1[u] + s * x1[u + 1]);
          const double y =
              (1 - t) * ((1 - s) * y0[u] + s * y0[u + 1]) + t * ((1 - s) * y1[u] + s * y1[u + 1]);
          sum += trace(x, y, candidates, &label);
        }
      }
      out[u] = static_cast<float>(sum / (S * S));
    }
  }
  return image;
}

cv::Mat TagRenderer::Render(const std::vector<Pose>& T_W_C_over_exposure,
                            uint64_t noise_seed) const {
  const int W = camera_.width(), H = camera_.height();
  cv::Mat mean = cv::Mat::zeros(H, W, CV_32F);
  for (const Pose& T_W_C : T_W_C_over_exposure) mean += RenderIdeal(T_W_C);
  if (!T_W_C_over_exposure.empty()) mean /= static_cast<double>(T_W_C_over_exposure.size());
  // Sensor noise from OpenCV's own generator (multiply-with-carry + ziggurat: deterministic for a
  // seed, and fast enough for a frame of Gaussian draws).
  if (options_.noise_sigma_grey > 0.0) {
    cv::Mat noise(H, W, CV_32F);
    cv::RNG rng(noise_seed == 0 ? 1 : noise_seed);
    rng.fill(noise, cv::RNG::NORMAL, 0.0, options_.noise_sigma_grey / 255.0);
    mean += noise;
  }
  cv::Mat image;
  mean.convertTo(image, CV_8UC1, 255.0);  // rounds to nearest and saturates to [0, 255]
  return image;
}

}  // namespace mavloc
