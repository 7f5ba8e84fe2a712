// Rendering Kalibr aprilgrids (core/aprilgrid.h) with TagRenderer: the tags (tag36h11 with a 2-cell
// black border, family "aprilgrid"), a black square of edge tag_spacing x tag_size at every tag
// corner (tag_rows + 1) x (tag_cols + 1) squares, touching the tags' corners at single points as
// on Kalibr's printed target), and the white board under them, with a margin around the outermost
// squares. Rendered images go through the real detector (frontends/apriltag, family "aprilgrid")
// like real aprilgrid frames, so rendered datasets run images -> detection -> estimators.
//
// Frames: the board frame M of core/aprilgrid.h (origin at the outer corner of tag 0, z out of the
// board); a tag's bitmap row 0 lies at its +y_M edge, as on the real target (checked by the PnP of
// tests/frontends/aprilgrid_detector_test.cc on the real EuRoC frames).
#pragma once

#include <cstdint>
#include <opencv2/core.hpp>

#include "core/aprilgrid.h"
#include "core/camera_model.h"
#include "core/pose.h"
#include "datasets/rendering/tag_renderer.h"

namespace mavloc {

struct AprilgridScene {
  std::map<int, TagInfo> tags;  // T_W_T of every tag of the grid
  TagRenderExtras extras;       // the corner squares and the board
};

// The grid placed at T_W_M. margin_m: white board beyond the outer squares (< 0: one square edge).
// Throws InputError for an invalid target.
AprilgridScene MakeAprilgridScene(const AprilgridTarget& target, const Pose& T_W_M,
                                  double margin_m = -1.0);

// A renderer of the grid at T_W_M (options.family is set to "aprilgrid" and the tags' own page
// margin to 0: the board is the paper). Render it from camera poses T_W_C (renderer.Render({T_W_C},
// seed)). Build it once per camera for a sequence: construction takes ~0.45 s (floor texture,
// per-pixel undistortion), a 752x480 frame ~0.16 s (supersampling 4) / 0.22 s (8) on one core.
// For sub-0.1 px corner checks use supersampling 8: with 4, an axis-aligned edge's coverage is
// quantized to quarter pixels (rendered edges off by up to 0.125 px).
TagRenderer MakeAprilgridRenderer(const CameraModel& camera, const AprilgridTarget& target,
                                  const Pose& T_W_M, TagRenderOptions options = {});

// The 8-bit image of the grid seen with the board at T_C_M in the camera frame (one pose, no
// blur; options.noise_sigma_grey of noise drawn from noise_seed). Builds a renderer per call. The
// board stands 0.3 m in front of the floor texture of TagRenderer (z_W = 0; W = M shifted by 0.3 m
// along z_M).
cv::Mat RenderAprilgrid(const CameraModel& camera, const AprilgridTarget& target, const Pose& T_C_M,
                        const TagRenderOptions& options = {}, uint64_t noise_seed = 1);

}  // namespace mavloc
