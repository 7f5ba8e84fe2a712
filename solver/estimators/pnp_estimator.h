// pnp: the PIXHAWK paper's vision-only baseline (Meier et al. 2012, 3.1 and 7.2: the 4-point
// ARToolKit+ pose, "without the 2-point algorithm"): per frame, T_W_B from all the corners of the
// markers in view (solver/pose/corner_pnp.h: IPPE for the coplanar floor board + LM on the pixel
// reprojection error), no IMU and no filtering; markers that disagree with the frame's consensus
// pose are left out (solver/pose/corner_pnp_ransac.h; ransac=0 uses every marker, as the paper's
// baseline does). Output at each frame: x, y, z, roll, pitch, yaw, inlier_tags and the pose. On a
// board map (MapFrame::kBoard) the map is first put into the gravity-aligned W of
// core/board_frame.h from the first gravity_init_s seconds of PnP poses and IMU
// (solver/board/board_world.h); every frame, those of the window included, is then solved in W,
// and the estimate carries T_W_M and board_roll, board_pitch. Options: image_delay_ms (0):
// subtracted from the frame stamps (a known transfer delay); gravity_init_s (2), gravity_min_tags
// (2); ransac (1), ransac_threshold_px (4), ransac_min_tags (2), single_tag (1),
// min_ambiguity_ratio (0), map_check (1: tags that disagree with the map are named in the report,
// solver/pose/tag_map_check.h).
#pragma once

#include "solver/board/board_world.h"
#include "solver/estimator.h"
#include "solver/pose/corner_pnp_ransac.h"
#include "solver/pose/tag_map_check.h"

namespace mavloc {

class PnpEstimator : public Estimator {
 public:
  explicit PnpEstimator(const EstimatorOptions& options);
  std::string name() const override { return "pnp"; }
  Applicability AppliesTo(const Dataset& dataset) const override;
  Estimate Run(const Dataset& dataset) override;

 private:
  Estimate RunInWorld(const Dataset& dataset) const;

  double image_delay_ms_;
  BoardInitOptions board_;
  CornerRansacOptions ransac_;
  TagMapCheckOptions map_check_;
};

}  // namespace mavloc
