#include "solver/pose/corner_pnp_ransac.h"

#include <algorithm>
#include <limits>
#include <optional>

#include "core/tag_geometry.h"

namespace mavloc {

namespace {

// One map tag of the frame: its corners in W and their ideal pinhole pixels.
struct TagCorners {
  int id = 0;
  std::vector<Eigen::Vector3d> X_W;
  std::vector<Eigen::Vector2d> uv;
};

std::vector<TagCorners> MapTagsOfFrame(const std::vector<TagObservation>& observations,
                                       const std::map<int, TagInfo>& tags,
                                       const CameraSensor& camera) {
  std::vector<TagCorners> out;
  for (const auto& observation : observations) {
    const auto it = tags.find(observation.tag_id);
    if (it == tags.end()) continue;
    TagCorners tag;
    tag.id = observation.tag_id;
    const auto corners_W = TagCornersInWorld(it->second);
    for (int k = 0; k < 4; ++k) {
      const auto xy = camera.model.PixelToNormalized(observation.corners_px[k]);
      if (!xy) break;
      tag.X_W.push_back(corners_W[k]);
      tag.uv.emplace_back(camera.model.fu() * xy->x() + camera.model.cu(),
                          camera.model.fv() * xy->y() + camera.model.cv());
    }
    if (tag.X_W.size() == 4) out.push_back(std::move(tag));
  }
  return out;
}

// Largest reprojection error of the tag's corners under T_W_C (infinite behind the camera).
double WorstCornerError(const TagCorners& tag, const Pose& T_C_W, const Eigen::Matrix3d& K,
                        double* sum_cost, double threshold_sq) {
  double worst = 0.0;
  for (size_t k = 0; k < tag.X_W.size(); ++k) {
    const Eigen::Vector3d p_C = T_C_W * tag.X_W[k];
    double e_sq = std::numeric_limits<double>::infinity();
    if (p_C.z() > 1e-6) e_sq = ((K * (p_C / p_C.z())).head<2>() - tag.uv[k]).squaredNorm();
    *sum_cost += std::min(e_sq, threshold_sq);
    worst = std::max(worst, e_sq);
  }
  return std::sqrt(worst);
}

struct Consensus {
  double cost = std::numeric_limits<double>::infinity();
  std::vector<size_t> inliers;  // indices into the frame's tags
};

Consensus Score(const std::vector<TagCorners>& frame, const Pose& T_W_C, const Eigen::Matrix3d& K,
                double threshold_px) {
  Consensus c;
  c.cost = 0.0;
  const Pose T_C_W = T_W_C.Inverse();
  for (size_t i = 0; i < frame.size(); ++i) {
    if (WorstCornerError(frame[i], T_C_W, K, &c.cost, threshold_px * threshold_px) <= threshold_px)
      c.inliers.push_back(i);
  }
  return c;
}

CornerPnpResult PnpOn(const std::vector<TagCorners>& frame, const std::vector<size_t>& which,
                      const CameraSensor& camera, bool refine) {
  std::vector<Eigen::Vector3d> X_W;
  std::vector<Eigen::Vector2d> uv;
  for (const size_t i : which) {
    X_W.insert(X_W.end(), frame[i].X_W.begin(), frame[i].X_W.end());
    uv.insert(uv.end(), frame[i].uv.begin(), frame[i].uv.end());
  }
  CornerPnpOptions options;
  options.refine = refine;
  CornerPnpResult result = CornerPnpFromCorrespondences(X_W, uv, camera, options);
  result.num_tags = static_cast<int>(which.size());
  return result;
}

// The best MSAC consensus over the single-tag and tag-pair hypotheses.
Consensus BestConsensus(const std::vector<TagCorners>& frame, const CameraSensor& camera,
                        const CornerRansacOptions& options) {
  const Eigen::Matrix3d K = camera.model.K();
  Consensus best;
  auto try_hypothesis = [&](const std::vector<size_t>& sample) {
    const CornerPnpResult pose = PnpOn(frame, sample, camera, /*refine=*/false);
    if (!pose.ok) return;
    Consensus c = Score(frame, pose.T_W_C, K, options.threshold_px);
    if (c.cost < best.cost) best = std::move(c);
  };
  for (size_t i = 0; i < frame.size(); ++i) try_hypothesis({i});
  int pairs = 0;
  for (size_t i = 0; i < frame.size() && pairs < options.max_pair_hypotheses; ++i)
    for (size_t j = i + 1; j < frame.size() && pairs < options.max_pair_hypotheses; ++j, ++pairs)
      try_hypothesis({i, j});
  return best;
}

}  // namespace

std::vector<std::string> FramePoseQuantityNames() {
  std::vector<std::string> names = PoseQuantityNames(/*with_velocity=*/false);
  names.push_back("inlier_tags");
  return names;
}

void RecordFramePose(const CornerRansacResult& result, TimeNs t_ns, Estimate* estimate) {
  if (!result.outlier_tags.empty() && result.pnp.ok) {
    estimate->CountRejection("tag disagrees with the frame's other tags (RANSAC)",
                             static_cast<int>(result.outlier_tags.size()));
  }
  if (!result.pnp.ok) {
    estimate->CountFailure(result.pnp.reason);
    return;
  }
  std::vector<double> values = PoseQuantityValues(result.pnp.T_W_B);
  values.push_back(static_cast<double>(result.inlier_tags.size()));
  estimate->quantities.Append(t_ns, values);
  estimate->poses.push_back({t_ns, result.pnp.T_W_B});
}

// The ranges (threshold > 0, min tags >= 1, ratio >= 0) are checked when the estimator is
// created (solver/estimator_registry.cc, OptionRanges).
CornerRansacOptions ParseCornerRansacOptions(const EstimatorOptions& options) {
  CornerRansacOptions out;
  out.enabled = options.GetBool("ransac", out.enabled);
  out.threshold_px = options.GetDouble("ransac_threshold_px", out.threshold_px);
  out.min_inlier_tags = options.GetInt("ransac_min_tags", out.min_inlier_tags);
  out.single_tag = options.GetBool("single_tag", out.single_tag);
  out.min_ambiguity_ratio = options.GetDouble("min_ambiguity_ratio", out.min_ambiguity_ratio);
  return out;
}

CornerRansacResult CornerPnpRansac(const std::vector<TagObservation>& observations,
                                   const std::map<int, TagInfo>& tags, const CameraSensor& camera,
                                   const CornerRansacOptions& options) {
  CornerRansacResult out;
  const std::vector<TagCorners> frame = MapTagsOfFrame(observations, tags, camera);
  if (frame.empty()) {
    out.pnp.reason = "no observed tag is in the map";
    return out;
  }
  std::vector<size_t> inliers;
  std::optional<CornerPnpResult> solved;  // the refined PnP on `inliers`, when already solved
  if (!options.enabled || frame.size() == 1) {
    if (frame.size() == 1 && options.enabled && !options.single_tag) {
      out.pnp.reason = "one map tag in view (single_tag=0)";
      return out;
    }
    for (size_t i = 0; i < frame.size(); ++i) inliers.push_back(i);
  } else {
    const Consensus best = BestConsensus(frame, camera, options);
    inliers = best.inliers;
    const auto needed =
        static_cast<size_t>(std::min<int>(options.min_inlier_tags, static_cast<int>(frame.size())));
    if (inliers.size() < needed) {
      out.pnp.reason = "no pose on which " + std::to_string(needed) + " tags agree (RANSAC)";
      for (const auto& tag : frame) out.outlier_tags.push_back(tag.id);
      return out;
    }
    // Least squares on the consensus, then its inliers once more from the refined pose.
    CornerPnpResult refined = PnpOn(frame, inliers, camera, /*refine=*/true);
    if (refined.ok) {
      const Consensus again = Score(frame, refined.T_W_C, camera.model.K(), options.threshold_px);
      if (again.inliers == inliers)
        solved = std::move(refined);
      else if (again.inliers.size() >= inliers.size())
        inliers = again.inliers;
    }
  }
  out.pnp = solved ? std::move(*solved) : PnpOn(frame, inliers, camera, /*refine=*/true);
  // The reprojection gate: a pose that does not reproject its own corners (a collapsed or
  // degenerate detection, a diverged refinement) is no pose.
  if (options.enabled && out.pnp.ok && !(out.pnp.rms_reprojection_px <= options.threshold_px)) {
    out.pnp.ok = false;
    out.pnp.reason = "reprojection RMS above ransac_threshold_px";
  }
  if (options.enabled && out.pnp.ok && inliers.size() == 1 && options.min_ambiguity_ratio > 0.0 &&
      out.pnp.ambiguity_rms_px <
          options.min_ambiguity_ratio * std::max(out.pnp.rms_reprojection_px, 1.0)) {
    out.pnp.ok = false;
    out.pnp.reason = "one tag with an ambiguous planar pose (min_ambiguity_ratio)";
  }
  std::vector<bool> is_inlier(frame.size(), false);
  for (const size_t i : inliers) is_inlier[i] = true;
  for (size_t i = 0; i < frame.size(); ++i)
    (is_inlier[i] ? out.inlier_tags : out.outlier_tags).push_back(frame[i].id);
  out.inlier_corners = static_cast<int>(4 * inliers.size());
  return out;
}

}  // namespace mavloc
