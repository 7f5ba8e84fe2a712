// AprilTag detection with libapriltag (Wang & Olson, "AprilTag 2", IROS 2016), the detector of the
// AprilTag paper (de Almeida Barbosa et al., III-A). Wraps apriltag_detector_t with its settings
// exposed (family, quad_decimate, nthreads, refine_edges, quad_sigma, decode_sharpening, bits
// corrected).
//
// Corner order. libapriltag's p[0..3] wrap around the tag starting at the corner at tag
// coordinates (-1, +1) of its own tag frame (x right, y DOWN in the tag bitmap), i.e. the
// bitmap's bottom-left, then bottom-right, top-right, top-left. mavloc's tag frame
// (core/tag_geometry.h) has x right, y UP, z out of the tag, corners 0..3 = bottom-left,
// bottom-right, top-right, top-left; the bitmap's top row is at +y. The two orders therefore
// coincide: kMavlocCornerFromApriltag is the identity. This is verified, not assumed, by
// tests/frontends/tag_detector_test.cc on a rendered image (datasets/rendering draws row 0 of
// apriltag_to_image at the tag's +y edge). `raw_output` keeps libapriltag's order and pixel
// convention, for comparisons with upstream reference files.
//
// Pixel convention. mavloc (like OpenCV and Kalibr) puts the centre of pixel (i, j) at (i, j);
// libapriltag puts the top-left corner of pixel (0, 0) at (0, 0), i.e. pixel centres at
// (i + 0.5, j + 0.5) (discussed upstream: github.com/AprilRobotics/apriltag/issues/121 and /334).
// Detections are shifted by -0.5 px into mavloc's convention unless `raw_output` is set.
//
// Aprilgrids. The families "aprilgrid" / "tag36h11b2" (Kalibr's tag36h11 with a 2-bit border,
// aprilgrid_family.h) run the aprilgrid steps of aprilgrid_detector.h: segmentation on an image
// whose diagonal black junctions are separated, and corners refined as X-junctions on the original
// image (options `aprilgrid`). Their corners are point features, valid on the raw distorted image.
//
// refine_edges. Debian's libapriltag 3.3.0 still has the refine_edges coordinate bug that upstream
// has since fixed (AprilRobotics/apriltag pull request 346): on exact images with pixel-aligned,
// non-anti-aliased edges it moves corners by 0.1-0.25 px. On area-integrated edges, what a camera
// (and datasets/rendering) produces, it is the better choice: on noiseless renders of the arena
// (rectified, see detect_tags.h) the corner error is mean 0.06 px / max 0.14 px with it, and mean
// 0.10 px / max 0.35 px with a -0.05 px bias without. mavloc keeps upstream's default (true) at
// decimate 1.
#pragma once

#include <Eigen/Core>
#include <array>
#include <memory>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "frontends/apriltag/aprilgrid_detector.h"

namespace mavloc {

struct TagDetectorOptions {
  std::string family = "tag36h11";  // tag36h11, aprilgrid, tag25h9, tag16h5, tagStandard41h12, ...
  double decimate = 1.0;            // quad_decimate (upstream default 2.0)
  int threads = 1;                  // nthreads
  bool refine_edges = true;         // refine_edges (see above)
  double sigma = 0.0;               // quad_sigma: Gaussian blur before segmentation (px)
  double decode_sharpening = 0.25;  // decode_sharpening
  int bits_corrected = 2;           // maximum Hamming distance accepted when decoding
  bool raw_output = false;          // true: libapriltag's p[] order and pixel convention
  // Detections with a corner closer than this to the image border are dropped: libapriltag
  // extrapolates the corners of tags cut by the border (errors of pixels). 0 keeps everything.
  double min_border_px = 3.0;
  // Families "aprilgrid" / "tag36h11b2" only.
  AprilgridDetectOptions aprilgrid;
};

// Names accepted by TagDetectorOptions::family.
std::vector<std::string> SupportedTagFamilies();

struct TagDetection {
  int id = 0;
  int hamming = 0;  // bits corrected
  // libapriltag's decoding confidence; 0 for an aprilgrid tag predicted from the grid (its code is
  // verified by AprilgridCodeDistance, `hamming` holds that distance).
  double decision_margin = 0.0;
  Eigen::Vector2d center_px = Eigen::Vector2d::Zero();
  // Corners in pixels (distorted, as seen), in mavloc's order (core/tag_geometry.h) and pixel
  // convention unless raw_output.
  std::array<Eigen::Vector2d, 4> corners_px{};
};

// Index into libapriltag's p[] of mavloc corner k, and the shift from libapriltag's pixel
// coordinates to mavloc's.
inline constexpr std::array<int, 4> kMavlocCornerFromApriltag = {0, 1, 2, 3};
inline constexpr double kMavlocFromApriltagPixelShift = -0.5;

class TagDetector {
 public:
  // Throws InputError for an unknown family or out-of-range settings (user input).
  explicit TagDetector(const TagDetectorOptions& options);
  ~TagDetector();
  TagDetector(const TagDetector&) = delete;
  TagDetector& operator=(const TagDetector&) = delete;

  const TagDetectorOptions& options() const { return options_; }

  // Detects tags in an 8-bit greyscale image. Detections are sorted by id, then by the first
  // corner (x, then y), so the output is deterministic. Not thread-safe (libapriltag keeps state).
  std::vector<TagDetection> Detect(const cv::Mat& gray);

 private:
  // The aprilgrid steps after libapriltag (aprilgrid_detector.h); false drops the detection.
  // `image`: RefinementImage of the original image (empty when corners are not refined);
  // `separated`: the detection comes from SeparateDiagonalJunctions' output.
  bool RefineAprilgrid(const cv::Mat& image, bool separated, TagDetection* detection) const;
  // One libapriltag run on `segmented` (`separated`: SeparateDiagonalJunctions' output of `gray`),
  // then (aprilgrid) the corner steps on `gray` and the border rule. `refinement_image` is made on
  // first use.
  std::vector<TagDetection> DetectPass(const cv::Mat& segmented, bool separated,
                                       const cv::Mat& gray, cv::Mat* refinement_image);
  // Aprilgrid with a known target: the tags the grid predicts where none was found, refined and
  // verified by their code (aprilgrid_detector.h), appended to `detections`.
  void AddPredictedAprilgridTags(const cv::Mat& gray, const cv::Mat& refinement_image,
                                 std::vector<TagDetection>* detections) const;
  // The border rule (min_border_px).
  bool NearBorder(const TagDetection& detection, const cv::Size& size) const;

  struct Impl;
  TagDetectorOptions options_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace mavloc
