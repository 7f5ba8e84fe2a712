// tag-pnp: the vision-only baseline of the AprilTag paper (III-A): for every tags0 frame, the pose
// T_W_B from the frame's tag corners (solver/pose/corner_pnp.h: IPPE + LM on the reprojection
// error), with no IMU and no filtering. Tags that disagree with the frame's consensus pose are left
// out (solver/pose/corner_pnp_ransac.h; ransac=0 uses every tag, as the paper does) and counted as
// rejections. Tags whose map pose the other tags of their frames disagree with are named in the
// report's events (solver/pose/tag_map_check.h; map_check=0 skips the check). Frames with no tag in
// the map, or where the PnP fails or no two
// tags agree, are counted as failures by reason. Reports x, y, z, roll, pitch, yaw and inlier_tags.
// On a board map (MapFrame::kBoard) the map is first put into the gravity-aligned W of
// core/board_frame.h from the first gravity_init_s seconds of PnP poses and IMU
// (solver/board/board_world.h); every frame, those of the window included, is then solved in W,
// and the estimate carries T_W_M and board_roll, board_pitch.
// refine_map=1 first refines the map's tag poses from the log (solver/pose/tag_map_refine.h: one
// bundle adjustment over the first pass's posed frames and the tags, each tag tied to its map pose)
// and then poses every frame again on the refined map; how far the tags moved is reported in the
// events and as the parameters map_shift_max and map_shift_median (m). refine_map=auto (the
// default) does so when the map check names a tag, i.e. when the log disagrees with the map.
// neighbour_gate_m > 0 then refuses the poses that lie that far from where their neighbouring
// posed frames put them (solver/pose/neighbour_gate.h), counted as failures by that reason.
// Options: camera (default: the tags' camera, cameras[0]), gravity_init_s (2), gravity_min_tags
// (2), ransac (1), ransac_threshold_px (4), ransac_min_tags (2), single_tag (1),
// min_ambiguity_ratio (0), map_check (1), refine_map (auto), refine_sigma_m (0.1),
// refine_sigma_rad (0.1), refine_loss (cauchy), refine_loss_px (2), refine_gate_px (8),
// neighbour_gate_m (0.2; 0: off), neighbour_frames (20), neighbour_window_s (1.5).
#pragma once

#include <map>
#include <string>
#include <vector>

#include "solver/board/board_world.h"
#include "solver/estimator.h"
#include "solver/pose/corner_pnp_ransac.h"
#include "solver/pose/neighbour_gate.h"
#include "solver/pose/tag_map_check.h"
#include "solver/pose/tag_map_refine.h"

namespace mavloc {

class TagPnpEstimator : public Estimator {
 public:
  explicit TagPnpEstimator(const EstimatorOptions& options);
  std::string name() const override { return "tag-pnp"; }
  Applicability AppliesTo(const Dataset& dataset) const override;
  Estimate Run(const Dataset& dataset) override;

 private:
  Estimate RunInWorld(const Dataset& dataset) const;
  // The map refined from the first pass's poses (refine_map=1), its summary in the estimate.
  std::map<int, TagInfo> RefinedMap(const std::vector<std::vector<TagObservation>>& frames,
                                    const std::map<int, TagInfo>& tags, const CameraSensor& camera,
                                    Estimate* estimate) const;
  // neighbour_gate_m: the posed frames far from their neighbours become failures.
  void RefuseNeighbourOutliers(const std::vector<TimeNs>& frame_t_ns,
                               std::vector<CornerRansacResult>* results) const;

  std::string camera_name_;
  BoardInitOptions board_;
  CornerRansacOptions ransac_;
  TagMapCheckOptions map_check_;
  TagMapRefineOptions refine_;
  NeighbourGateOptions neighbour_gate_;
};

}  // namespace mavloc
