// Refines a loose tag map from the log: one bundle adjustment over the camera poses of the frames
// and the poses of the tags they see, as TagSLAM (Pfrommer & Daniilidis, "TagSLAM: Robust SLAM
// with Fiducial Markers", arXiv:1910.00679) does for its tag and camera poses.
//
// Unknowns: T_W_B of every frame given (first poses from the per-frame PnP, corner_pnp_ransac.h)
// and T_W_T of every map tag seen in them. Cost (Triggs et al., "Bundle Adjustment — a Modern
// Synthesis", 2000):
//   sum_f,t,k rho(|pi(T_B_C^-1 T_W_B_f^-1 T_W_T_t c_k) - uv_f,t,k|^2)
//     + sum_t |L [Log(q_W_T_map^-1 q_W_T); p_W_T - p_W_T_map]|^2
// with pi the pinhole + distortion projection of core/camera_model.h (CameraModel::ProjectT, on the
// detected, distorted pixels), c_k the tag corners of core/tag_geometry.h, rho a Huber or Cauchy
// loss of scale loss_scale_px, and L = diag(1/tag_sigma_rad x 3, 1/tag_sigma_m x 3) the prior that
// ties each tag to its map pose. The prior fixes the gauge (the map's frame) and keeps a tag seen
// in one frame only, or with no other tag, where the map put it: a lone tag only moves the camera
// of its frame, never itself. Quaternions live on ceres::EigenQuaternionManifold.
//
// The loss scale is graduated (tag_map_refine.cc SolveGraduated): it starts at the corners' median
// error under the first poses and shrinks to loss_scale_px.
// Outliers: after this first solve, every corner whose reprojection error is above gate_px is
// dropped (a wrong-id tag, a blurred corner) and the problem is solved again from the first
// solution. The caller then re-runs its per-frame PnP on the refined map (tag_pnp_estimator.cc).
#pragma once

#include <map>
#include <string>
#include <vector>

#include "core/dataset.h"
#include "core/pose.h"
#include "solver/estimator.h"

namespace mavloc {

enum class TagMapRefineLoss { kHuber, kCauchy };

// refine_map=0|1|auto: auto refines when the map check (tag_map_check.h) names a tag that the
// other tags of its frames disagree with, i.e. when the log shows the map is loose; a map the log
// agrees with is used as given.
enum class TagMapRefineMode { kOff, kOn, kAuto };

struct TagMapRefineOptions {
  TagMapRefineMode mode = TagMapRefineMode::kAuto;    // refine_map
  double tag_sigma_m = 0.1;                           // refine_sigma_m: map position prior
  double tag_sigma_rad = 0.1;                         // refine_sigma_rad: map rotation prior
  TagMapRefineLoss loss = TagMapRefineLoss::kCauchy;  // refine_loss=huber|cauchy
  double loss_scale_px = 2.0;                         // refine_loss_px
  double gate_px = 8.0;        // refine_gate_px: corners dropped after pass 1
  int min_tags_per_frame = 2;  // frames with fewer map tags tell nothing about the tags
  int max_iterations = 100;
};

// From `--option refine_map=0|1|auto, refine_sigma_m (> 0), refine_sigma_rad (> 0),
// refine_loss=huber|cauchy, refine_loss_px (> 0), refine_gate_px (> 0)`; throws InputError naming
// a bad option.
TagMapRefineOptions ParseTagMapRefineOptions(const EstimatorOptions& options);

// One frame of the log: its tag observations (map ids or not) and its first body pose.
struct TagMapRefineFrame {
  std::vector<TagObservation> observations;
  Pose T_W_B;
};

// How far one tag moved from its map pose.
struct TagShift {
  int id = 0;
  double shift_m = 0.0;    // |p_W_T - p_W_T_map|
  double angle_rad = 0.0;  // angle of q_W_T_map^-1 q_W_T
};

struct TagMapRefinement {
  bool ok = false;
  std::string reason;            // why !ok (the map is then returned unchanged)
  std::map<int, TagInfo> tags;   // every map tag; those not refined keep their map pose
  std::vector<Pose> T_W_B;       // per input frame (unchanged for frames not used)
  std::vector<TagShift> shifts;  // per refined tag, largest shift first
  int frames_used = 0;           // frames with at least min_tags_per_frame map tags
  int corners_used = 0;          // in the final solve
  int corners_dropped = 0;       // by the gate after the first solve
  double rms_before_px = 0.0;    // corner reprojection RMS over the corners used, map poses
  double rms_after_px = 0.0;     // the same, refined poses

  double MaxShift_m() const;
  double MedianShift_m() const;
  // "tag map refined over 309 frames (...): the 20 tags seen with another tag moved median 0.032
  // m, max 0.242 m (most: tag 79 0.242 m 1.6 deg, ...)", for the report's events.
  std::string Summary(int top = 5) const;
};

TagMapRefinement RefineTagMap(const std::vector<TagMapRefineFrame>& frames,
                              const std::map<int, TagInfo>& tags, const CameraSensor& camera,
                              const TagMapRefineOptions& options);

}  // namespace mavloc
