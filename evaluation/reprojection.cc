#include "evaluation/reprojection.h"

#include <algorithm>
#include <cmath>

#include "core/tag_geometry.h"
#include "evaluation/association.h"

namespace mavloc {

namespace {

constexpr double kMinDepthM = 0.05;

ReprojectionStatistics Reproject(const Dataset& dataset, const Estimate& estimate,
                                 const std::vector<TagObservation>& observations,
                                 const CameraSensor& camera, double max_gap_s) {
  ReprojectionStatistics stats;
  stats.camera = camera.name;
  const auto extrinsic = estimate.extrinsics.find(camera.name);
  const Pose T_B_C =
      extrinsic != estimate.extrinsics.end() ? extrinsic->second.T_B_C : camera.T_B_C;
  const Pose T_W_M = estimate.T_W_M.value_or(Pose());

  // The estimate's pose at every observation stamp (interpolated; AssociatePoses pairs each
  // query stamp with the estimate there).
  std::vector<StampedPose> queries;
  for (const auto& obs : observations)
    if (queries.empty() || queries.back().t_ns != obs.t_ns) queries.push_back({obs.t_ns, Pose()});
  const auto pairs = AssociatePoses(queries, estimate.poses, max_gap_s);
  std::map<TimeNs, Pose> T_W_B_at;
  for (const auto& pair : pairs) T_W_B_at[pair.t_ns] = pair.T_W_B_gt;

  std::vector<double> errors;
  for (const auto& obs : observations) {
    const auto tag = dataset.map.tags.find(obs.tag_id);
    const auto pose = T_W_B_at.find(obs.t_ns);
    if (tag == dataset.map.tags.end()) continue;  // not a map tag: nothing to reproject
    if (pose == T_W_B_at.end()) {
      stats.unmatched += 4;
      continue;
    }
    const Pose T_C_W = (pose->second * T_B_C).Inverse();
    const auto corners_M = TagCornersInWorld(tag->second);  // map frame (W or M)
    for (int k = 0; k < 4; ++k) {
      // A corner closer than 5 cm to the camera plane (a pose far off) would project anywhere:
      // it counts as unmatched rather than as an error of 1e12 px.
      const auto uv = camera.model.Project(T_C_W * (T_W_M * corners_M[k]), kMinDepthM);
      if (!uv) {
        ++stats.unmatched;
        continue;
      }
      // Beyond half an image outside the frame the distortion polynomial is outside its valid
      // field and its pixel value is meaningless (radial-tangential diverges): a gross failure,
      // counted, not averaged.
      if (!camera.model.IsInside(*uv, -0.5 * camera.model.width())) {
        ++stats.off_image;
        continue;
      }
      errors.push_back((*uv - obs.corners_px[k]).norm());
    }
  }
  stats.corners = static_cast<int>(errors.size());
  if (errors.empty()) return stats;
  double sum_sq = 0.0;
  for (double e : errors) {
    sum_sq += e * e;
    stats.max_px = std::max(stats.max_px, e);
    if (e > 3.0) ++stats.over_3px;
  }
  stats.rms_px = std::sqrt(sum_sq / errors.size());
  std::nth_element(errors.begin(), errors.begin() + errors.size() / 2, errors.end());
  stats.median_px = errors[errors.size() / 2];
  return stats;
}

}  // namespace

std::vector<ReprojectionStatistics> ComputeTagReprojection(const Dataset& dataset,
                                                           const Estimate& estimate,
                                                           double max_gap_s) {
  std::vector<ReprojectionStatistics> out;
  if (estimate.poses.empty() || dataset.map.tags.empty()) return out;
  const std::vector<TagObservation>* streams[2] = {&dataset.tags, &dataset.tags1};
  for (int c = 0; c < 2; ++c) {
    if (streams[c]->empty() || c >= static_cast<int>(dataset.cameras.size())) continue;
    const auto stats = Reproject(dataset, estimate, *streams[c], dataset.cameras[c], max_gap_s);
    if (stats.corners + stats.unmatched + stats.off_image > 0) out.push_back(stats);
  }
  return out;
}

}  // namespace mavloc
