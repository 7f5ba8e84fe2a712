// Outlier rejection for the per-frame PnP on tag corners (corner_pnp.h). On real logs a frame can
// hold a tag whose id was misread, a tag that moved since the map was made, or corners of a
// badly blurred tag; one such tag drags the least-squares pose of the whole frame away.
//
// Hypotheses are the poses of single tags and of every pair of tags (IPPE on the 4 or SQPnP on the
// 8 corners; at most max_pair_hypotheses pairs, in a fixed order); each is scored by MSAC
// (Torr & Zisserman, CVIU 2000) over every corner of the frame, a corner costing
// min(e^2, threshold^2) with e its reprojection error in ideal pinhole pixels. A tag is an inlier
// when all four of its corners reproject within the threshold, so a wrong id or a moved tag is
// rejected as a whole. The pose is then the least-squares PnP (with LM refinement) on the inlier
// tags, whose inliers are found again once from that pose; a pose whose RMS reprojection error is
// above the threshold is refused (the reprojection gate). A frame of two or more map tags needs
// min_inlier_tags of them to agree; a frame with one map tag is used as it is (single_tag=1) or
// refused (single_tag=0), since nothing can check it.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "core/dataset.h"
#include "core/estimate.h"
#include "solver/estimator.h"
#include "solver/pose/corner_pnp.h"

namespace mavloc {

struct CornerRansacOptions {
  bool enabled = true;           // ransac=0: every tag is used (the papers' baseline)
  double threshold_px = 4.0;     // ransac_threshold_px
  int min_inlier_tags = 2;       // ransac_min_tags, for frames of two or more map tags
  bool single_tag = true;        // single_tag
  int max_pair_hypotheses = 45;  // all pairs of up to 10 tags
  // A pose from one tag is refused when the other planar pose (IPPE's second candidate)
  // reprojects within this factor of the chosen one's RMS (at least 1 px): the frame cannot tell
  // the two apart (min_ambiguity_ratio; 0 keeps every single-tag pose).
  double min_ambiguity_ratio = 0.0;
};

// From `--option ransac=0|1, ransac_threshold_px (> 0), ransac_min_tags (>= 1), single_tag=0|1,
// min_ambiguity_ratio (>= 0)`;
// throws InputError naming a bad option.
CornerRansacOptions ParseCornerRansacOptions(const EstimatorOptions& options);

struct CornerRansacResult {
  CornerPnpResult pnp;           // on the inlier tags; pnp.reason says why when !pnp.ok
  std::vector<int> inlier_tags;  // tag ids
  std::vector<int> outlier_tags;
  int inlier_corners = 0;
};

// The quantities of a per-frame PnP estimate: x, y, z, roll, pitch, yaw and inlier_tags.
std::vector<std::string> FramePoseQuantityNames();

// Appends the frame's pose at t_ns to the estimate (quantities of FramePoseQuantityNames, and
// poses), or counts the frame as a failure by reason; outlier tags are counted as rejections.
void RecordFramePose(const CornerRansacResult& result, TimeNs t_ns, Estimate* estimate);

CornerRansacResult CornerPnpRansac(const std::vector<TagObservation>& observations,
                                   const std::map<int, TagInfo>& tags, const CameraSensor& camera,
                                   const CornerRansacOptions& options);

}  // namespace mavloc
