#include "datasets/rendering/aprilgrid_renderer.h"

#include "core/errors.h"

namespace mavloc {

namespace {

// The board frame M in the world of RenderAprilgrid: 0.3 m above the floor z_W = 0.
Pose BoardInRenderWorld() {
  return Pose(Eigen::Quaterniond::Identity(), Eigen::Vector3d(0.0, 0.0, 0.3));
}

}  // namespace

AprilgridScene MakeAprilgridScene(const AprilgridTarget& target, const Pose& T_W_M,
                                  double margin_m) {
  const std::string why = target.Validate();
  if (!why.empty()) throw InputError("", 0, "aprilgrid", why);
  AprilgridScene scene;
  for (const auto& [id, tag] : AprilgridTags(target)) {
    TagInfo placed = tag;
    placed.T_W_T = T_W_M * tag.T_W_T;  // AprilgridTags gives T_M_T
    scene.tags[id] = placed;
  }
  const double gap_m = target.tag_spacing * target.tag_size_m;
  const double pitch_m = target.PitchM();
  if (margin_m < 0.0) margin_m = gap_m;
  // Square (i, j) fills the gap before tag column i and tag row j: x in [i pitch - gap, i pitch].
  if (gap_m > 0.0) {
    for (int j = 0; j <= target.tag_rows; ++j) {
      for (int i = 0; i <= target.tag_cols; ++i) {
        const Eigen::Vector3d centre_M(i * pitch_m - 0.5 * gap_m, j * pitch_m - 0.5 * gap_m, 0.0);
        scene.extras.black_squares.push_back(
            {T_W_M * Pose(Eigen::Quaterniond::Identity(), centre_M), 0.5 * gap_m, 0.5 * gap_m});
      }
    }
  }
  // The board: from the outer squares' outer edges plus the margin.
  const double x0 = -gap_m - margin_m, x1 = target.tag_cols * pitch_m + margin_m;
  const double y0 = -gap_m - margin_m, y1 = target.tag_rows * pitch_m + margin_m;
  const Eigen::Vector3d centre_M(0.5 * (x0 + x1), 0.5 * (y0 + y1), 0.0);
  scene.extras.papers.push_back(
      {T_W_M * Pose(Eigen::Quaterniond::Identity(), centre_M), 0.5 * (x1 - x0), 0.5 * (y1 - y0)});
  return scene;
}

TagRenderer MakeAprilgridRenderer(const CameraModel& camera, const AprilgridTarget& target,
                                  const Pose& T_W_M, TagRenderOptions options) {
  options.family = "aprilgrid";
  options.page_margin_cells = 0.0;
  const AprilgridScene scene = MakeAprilgridScene(target, T_W_M);
  return TagRenderer(camera, scene.tags, options, scene.extras);
}

cv::Mat RenderAprilgrid(const CameraModel& camera, const AprilgridTarget& target, const Pose& T_C_M,
                        const TagRenderOptions& options, uint64_t noise_seed) {
  const Pose T_W_M = BoardInRenderWorld();
  const TagRenderer renderer = MakeAprilgridRenderer(camera, target, T_W_M, options);
  return renderer.Render({T_W_M * T_C_M.Inverse()}, noise_seed);
}

}  // namespace mavloc
