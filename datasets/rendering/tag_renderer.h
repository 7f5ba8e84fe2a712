// Renders camera images of a floor carrying AprilTags (the tag arena of the AprilTag paper, IV-B),
// so that the real detector (frontends/apriltag) runs on real pixels.
//
// Each pixel is traced back through the camera model with its distortion: the undistorted
// normalized coordinates (x, y) of the pixel corners are precomputed once per camera, sub-pixel
// samples are interpolated bilinearly between them. A plane (a tag's page, or the floor z_W = 0) is
// seen through the true homography from normalized coordinates to plane coordinates,
//   q ~ H (x, y, 1),   H = [r1 r2 t]^-1  with  T_C_P = [R_C_P | t]  (depth 1 / (H (x, y, 1))_z >
//   0),
// so the tag bitmap (libapriltag's apriltag_to_image, row 0 at the tag's +y edge, column 0 at its
// -x edge, see core/tag_geometry.h) is warped exactly, with no resampling of an intermediate image.
// Pixels crossed by an edge (a tag cell, page or floor boundary: their four corners do not all see
// the same uniform region) are supersampled (S x S samples, box filter: the pixel's area average,
// which is what a sensor integrates); the others take one sample (cells are uniform, the floor
// texture is smooth). Optional motion blur averages the ideal image over poses spread across the
// exposure; sensor noise is additive Gaussian in grey levels before 8-bit quantization.
//
// Besides tags, a scene may hold black squares and white paper rectangles on planes (the corner
// squares and the board of a Kalibr aprilgrid, aprilgrid_renderer.h). Coplanar items overlap in a
// fixed order: squares over tags over paper (the aprilgrid's corner squares cover the corners of
// the tags' white rings). The family "aprilgrid" (alias "tag36h11b2") draws tag36h11's bitmaps
// with a 2-cell black border (frontends/apriltag/aprilgrid_family.h; 12 x 12 cells).
//
// Pixel convention: the centre of pixel (i, j) is at (i, j) (mavloc, OpenCV); pixel (i, j) covers
// [i - 1/2, i + 1/2] x [j - 1/2, j + 1/2].
#pragma once

#include <cstdint>
#include <map>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "core/camera_model.h"
#include "core/dataset.h"
#include "core/pose.h"

namespace mavloc {

struct TagRenderOptions {
  std::string family = "tag36h11";  // also "aprilgrid" / "tag36h11b2"
  int supersampling = 4;            // samples per axis on pixels that may see a tag
  double page_margin_cells = 1.0;   // white paper beyond the bitmap's own white ring (cells)
  double ink_grey = 0.08;           // black cells, in [0, 1]
  double paper_grey = 0.92;         // white cells and paper
  double floor_grey = 0.45;         // mean floor brightness
  double floor_contrast = 0.12;     // amplitude of the floor texture
  double noise_sigma_grey = 2.0;    // sensor noise, grey levels (0..255)
};

// A rectangle of half extents (half_x_m, half_y_m) centred at the origin of its frame R, in the
// plane z_R = 0.
struct RenderRectangle {
  Pose T_W_R;
  double half_x_m = 0.0;
  double half_y_m = 0.0;
};

// Uniform items drawn with the tags: black squares (ink_grey) and white paper (paper_grey).
struct TagRenderExtras {
  std::vector<RenderRectangle> black_squares;
  std::vector<RenderRectangle> papers;
};

// The bitmap of one tag of a libapriltag family (total_width x total_width cells, 0 = black,
// 255 = white). Throws InputError for an unknown family or id.
cv::Mat TagFamilyBitmap(const std::string& family, int id);
// Cells of the black square's edge (width_at_border) and of the whole bitmap (total_width).
int TagFamilyBorderCells(const std::string& family);

class TagRenderer {
 public:
  // Throws InputError for an unknown family or a tag id outside the family.
  TagRenderer(const CameraModel& camera, const std::map<int, TagInfo>& tags,
              const TagRenderOptions& options = {}, const TagRenderExtras& extras = {});

  // The ideal (noise-free, blur-free) image seen from camera pose T_W_C, CV_32F in [0, 1].
  cv::Mat RenderIdeal(const Pose& T_W_C) const;
  // The 8-bit image: the mean of the ideal images over the given poses (one pose: no blur), plus
  // Gaussian noise drawn from noise_seed.
  cv::Mat Render(const std::vector<Pose>& T_W_C_over_exposure, uint64_t noise_seed) const;

  const CameraModel& camera() const { return camera_; }

 private:
  // A tag (bitmap on its page), a black square or a paper rectangle.
  struct PlaneTag {
    enum class Kind { kPaper = 0, kTag = 1, kSquare = 2 };  // value = drawing priority
    Kind kind = Kind::kTag;
    int id = 0;
    Pose T_W_T;
    double cell_m = 0.0;                    // edge of one bitmap cell (tags)
    double half_x_m = 0.0, half_y_m = 0.0;  // half extents (tags: the page, bitmap + margin)
    cv::Mat bitmap;                         // total_width x total_width (tags)
  };
  // The procedural floor texture, and its lookup through a precomputed 5 mm grid around the tags.
  double FloorGreyProcedural(double x_W, double y_W) const;
  double FloorGrey(double x_W, double y_W) const;

  CameraModel camera_;
  TagRenderOptions options_;
  std::vector<PlaneTag> tags_;
  int total_cells_ = 0;
  // Normalized undistorted coordinates of the pixel corners (i - 1/2, j - 1/2), (W + 1) x (H + 1);
  // NaN where undistortion fails.
  cv::Mat corner_x_, corner_y_;
  cv::Mat
      floor_;  // CV_32F, floor_(row, col) at (floor_x0_ + col * kFloorStep, floor_y0_ + row * ...)
  double floor_x0_ = 0.0, floor_y0_ = 0.0;
};

}  // namespace mavloc
