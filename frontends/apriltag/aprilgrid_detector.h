// Detecting Kalibr aprilgrids (core/aprilgrid.h) with libapriltag (Wang & Olson, "AprilTag 2",
// IROS 2016) and the 2-bit-border family of aprilgrid_family.h: why plain libapriltag loses tags
// on an aprilgrid, the remedy, and sub-pixel corners at the grid's X-junctions. TagDetector
// (tag_detector.h) runs these steps for the families "aprilgrid" / "tag36h11b2".
//
// Why tags are lost (established on the real EuRoC pair of ../shared/data/euroc_cam_april/images
// with libapriltag's debug images; plain detection finds 21/36 (cam0) and 25/36 (cam1) tags).
// In an aprilgrid a black corner square touches each tag's black border at the tag corner, at a
// single point: an X-junction (a saddle point of the image). libapriltag thresholds the image
// (local min/max over 4x4 tiles), then forms connected components, 4-connected for black and
// 8-connected for white, precisely so that two black regions touching diagonally stay apart; and it
// clusters boundary pixels per (black component, white component) pair, each cluster being a quad
// candidate. With 4-connected black the tags and squares would indeed stay separate components on
// an ideal image (with 8-connected black the whole printed grid is ONE component: measured 30057 px
// in cam0). But the pixel that straddles an X-junction sees half black, half white, i.e. exactly
// the threshold: with blur, noise and the sub-pixel position of the junction, it (or a neighbour)
// is classified black at many junctions and forms a 4-connected bridge between the tag and the
// square. The tag's component then includes one or more corner squares (cam0: 4 components of
// 1700-2300 px, bounding boxes of about 2 x 2 tags, are two tags chained through a square; a tag
// alone is 600-1400 px), its boundary cluster is a tag outline with square bumps at the corners,
// and the quad fit either fails or snaps a corner to the square's far corner (seen in
// libapriltag's debug_segmentation / debug_quads_raw images). The brief's first guess, that all
// tags and squares form ONE black component, holds only for 8-connectivity, which libapriltag does
// not use for black. Decoding is not the problem: every tag whose outline is found decodes with
// hamming 0. The same losses appear on rendered grids (plain libapriltag: 2-25 of 36).
//
// Remedy. (1) SeparateDiagonalJunctions: before segmentation, a grey-level dilation (maximum) over
// the smallest structuring element, 2x2 pixels. It erodes every black region by one pixel on its
// right and bottom sides, which turns every junction pixel white and breaks all the bridges, while
// the tags' data cells (>= 3 px wide in practice) survive, so libapriltag decodes on the same image
// (a 3x3 dilation also separates all 36 tags but erodes the data cells enough to lose ~10 of them
// at decoding). Result on the EuRoC pair: 36/36 tags in both images, hamming 0.
// (2) UndoJunctionSeparation: the erosion moves each quad edge with outward normal n inwards by
// max(0, n_x) + max(0, n_y) px (the support function of the 2x2 element); the edges are moved back
// and the corners re-intersected. (3) RefineAprilgridCorners: each corner is an X-junction, so it
// is measured on the ORIGINAL image with cv::cornerSubPix (Foerstner's estimate: the point q such
// that the image gradient at every window pixel p is orthogonal to p - q; Kalibr refines its
// aprilgrid corners the same way). The X-junction is a point feature, so lens distortion does not
// bias it (unlike libapriltag's straight-line fits: no rectification is needed). The window half
// size is window_fraction x the tag's shortest edge in pixels, clamped: 0.14 keeps the window
// within the pure junction (the 2-cell tag border and the 3-cell square; tag edge = 10 cells).
// A corner that moves farther than max_shift from its initial estimate (occlusion, a corrupted
// junction) drops the tag.
//
// Measured on the EuRoC pair (tests/frontends/aprilgrid_detector_test.cc): PnP of the 144 corners
// with EuRoC's intrinsics and distortion: RMS 0.83 px with libapriltag's corners on the separated
// image, 0.24 / 0.25 px after UndoJunctionSeparation, 0.17 px (cam0) and 0.15 px (cam1) after the
// X-junction refinement. On rendered grids (tests/evaluation/aprilgrid_render_detect_test.cc, EuRoC
// cam0 model, 6 poses, 1 grey level of noise): every visible tag, corner error mean 0.04 px, max
// 0.29 px (libapriltag's corners: mean 0.13 px).
//
// Limit: the 2x2 erosion costs small tags their thinnest data cells. Rendered 6x6 grids lose no tag
// down to a shortest tag edge of about 19 px (cells of 1.9 px); below, tags drop (13-15 px edges
// near the distorted image corner: 12-26 of 36 found, plain libapriltag 10-13).
//
// Hand-held frames (the 10 real Intel D435i frames of ../shared/data/d435i_aprilgrid: 640x480
// JPEG, motion blur, over-exposure, tags of about 18-40 px; yac's detections as reference;
// tests/frontends/aprilgrid_handheld_test.cc). The separated image alone finds 250 of yac's 339
// tags (yac's 5 detections that lie off the board's grid are not counted). Why the 89 are lost,
// measured with libapriltag's own quad stage (apriltag_quad_thresh) and the tag's code sampled
// through yac's corners: 73 have a quad on the separated image within 1 px of yac's corners and
// their code reads with 0 bit errors on the original image, but libapriltag decodes them on the
// separated image, where the 2x2 erosion has eaten their thinnest data cells (cells of 2.1-2.8 px;
// 66 of the 73 are found by libapriltag on the original image); 7 have no quad within 5 px of
// yac's corners (6 of them board-corner tags, see below); 8 are found and then dropped by the
// corner refinement's max_shift (all board-corner tags, where the motion-capture markers of this
// board sit on the corner squares and the X-junction is not clean); 1 has a quad only on the
// original image. Neither quad_sigma (0.6, 0.8: fewer tags), decode_sharpening (0, 0.5: +-4 tags)
// nor a larger max_shift (more tags, corners off by up to 7 px) is the remedy. Two steps are: (4)
// unseparated_pass: libapriltag runs a second time on the original image, and its tags that the
// separated image lacked join them (their quads are not eroded, so UndoJunctionSeparation is
// skipped; a quad snapped to a corner square fails the refinement's shift test): 315 / 339.
// (5) With the board known (options.target), PredictMissingAprilgridTags puts every missing tag
// where a homography fitted to its nearest found neighbours says, its corners are refined as
// X-junctions from there, and the tag is kept only when its code, sampled on the original image
// through the refined corners, is its id's within predicted_max_hamming bits (and its white ring is
// brighter than its black border): 330 / 339, median corner distance to yac's 0.08 px, no false
// id. The 9 still lost are all board-corner tags (0, 5, 30, 35) whose outer corner is covered by a
// marker; the largest corner distances (1-2.6 px) are at the same outer corners.
//
// Pixel convention: mavloc's (pixel centres at integers), see tag_detector.h.
#pragma once

#include <Eigen/Core>
#include <array>
#include <opencv2/core.hpp>
#include <vector>

#include "core/aprilgrid.h"

struct apriltag_family;

namespace mavloc {

struct AprilgridDetectOptions {
  bool separate_junctions = true;  // the 2x2 grey-level dilation before segmentation
  // A second libapriltag pass on the original image; its tags join those of the separated image
  // (by id, the separated image's detection first). See "Hand-held frames" above.
  bool unseparated_pass = true;
  // The board (rows, cols, spacing; tag_size_m is not used). When valid, tags that neither pass
  // found are predicted from the found ones (PredictMissingAprilgridTags); tag_rows = 0: unknown.
  AprilgridTarget target;
  // A predicted tag is accepted when its 36 data bits, sampled on the original image through its
  // refined corners, differ from its id's code in at most this many bits, and its white ring is
  // brighter than its black border by at least predicted_min_contrast_grey.
  int predicted_max_hamming = 2;
  double predicted_min_contrast_grey = 20.0;
  bool refine_corners = true;     // X-junction refinement on the original image
  double window_fraction = 0.14;  // half window / shortest tag edge (px / px)
  // Gaussian blur of the image the corners are refined on (0: none), see RefinementImage.
  double refine_blur_sigma_px = 0.8;
  int min_half_window_px = 2;
  int max_half_window_px = 10;
  // A refined corner may move at most max(max_shift_px, max_shift_fraction x shortest edge).
  double max_shift_px = 2.0;
  double max_shift_fraction = 0.08;
};

// out(u, v) = max of gray over (u..u+1, v..v+1) (the last row/column repeat the border): black
// regions lose one pixel on their right and bottom sides. 8-bit greyscale in and out.
cv::Mat SeparateDiagonalJunctions(const cv::Mat& gray);

// The quad of a black region found on SeparateDiagonalJunctions' output, moved back to the
// region's outline in the original image: each edge (outward normal n) moves outwards by
// max(0, n_x) + max(0, n_y) px. Corners in any consistent winding; mavloc pixel convention.
std::array<Eigen::Vector2d, 4> UndoJunctionSeparation(const std::array<Eigen::Vector2d, 4>& quad);

// The image corners are refined on: the original 8-bit image as CV_32F, blurred with a Gaussian of
// refine_blur_sigma_px. The blur does not move an X-junction: the junction of the aprilgrid is
// point-symmetric (I(c + d) = I(c - d) near the junction c: black tag and black square opposite,
// white gaps opposite), a Gaussian keeps that symmetry, so the saddle stays at c. It removes the
// pixel locking of cornerSubPix on very sharp edges (one mixed pixel across an edge weights the
// gradient centroid towards the pixel centre: up to ~0.07 px per edge on area-sampled renders
// without optical blur) and averages noise.
cv::Mat RefinementImage(const cv::Mat& gray, const AprilgridDetectOptions& options);

// Refines the 4 corners of one aprilgrid tag in place on `image` (RefinementImage of the original
// image). Returns false
// (corners unchanged) when a corner is too close to the image border for the smallest window or
// moves farther than allowed.
bool RefineAprilgridCorners(const cv::Mat& image, const AprilgridDetectOptions& options,
                            std::array<Eigen::Vector2d, 4>* corners_px);

// Bits of tag `id` of `family` (the aprilgrid family, aprilgrid_family.h) that differ from the
// image: each data cell is sampled (bilinear) at its centre through the homography of `corners_px`
// (mavloc order: the black square's corners) and thresholded halfway between the mean of the
// black border's outer ring and the mean of the white ring outside it. `contrast_grey` (optional)
// receives white mean - black mean. Returns the number of bits (0..nbits), or -1 when a sample
// falls outside the image.
int AprilgridCodeDistance(const cv::Mat& gray, const struct apriltag_family& family, int id,
                          const std::array<Eigen::Vector2d, 4>& corners_px,
                          double* contrast_grey = nullptr);

// One predicted tag: its id and its corners (mavloc order and pixel convention).
struct PredictedAprilgridTag {
  int id = 0;
  std::array<Eigen::Vector2d, 4> corners_px{};
};

// Where the tags of options.target that are not in `found_ids` lie in the image, from the tags that
// were found (`found_ids[i]` with corners `found_corners_px[i]`): per missing tag, a homography
// board plane -> image fitted to the corners of the (up to 8) found tags nearest to it on the grid
// (nearest first, at least 2 tags), so that lens distortion enters only through the neighbourhood.
// Tags whose predicted white ring is not inside the image by border_px are left out.
std::vector<PredictedAprilgridTag> PredictMissingAprilgridTags(
    const AprilgridTarget& target, const std::vector<int>& found_ids,
    const std::vector<std::array<Eigen::Vector2d, 4>>& found_corners_px, const cv::Size& image_size,
    double border_px);

}  // namespace mavloc
