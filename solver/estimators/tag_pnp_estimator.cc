#include "solver/estimators/tag_pnp_estimator.h"

#include <fmt/format.h>

#include "solver/pose/corner_pnp_ransac.h"
#include "solver/pose/neighbour_gate.h"
#include "solver/pose/tag_map_check.h"
#include "solver/pose/tags_camera.h"

namespace mavloc {

TagPnpEstimator::TagPnpEstimator(const EstimatorOptions& options)
    : camera_name_(options.GetString("camera", "")),
      board_(ParseBoardInitOptions(options)),
      ransac_(ParseCornerRansacOptions(options)),
      map_check_(ParseTagMapCheckOptions(options)),
      refine_(ParseTagMapRefineOptions(options)),
      neighbour_gate_(ParseNeighbourGateOptions(options)) {}

Applicability TagPnpEstimator::AppliesTo(const Dataset& dataset) const {
  if (dataset.tags.empty()) return Applicability::No("needs tags0 observations");
  if (dataset.map.tags.empty()) return Applicability::No("needs the tags of map.yaml");
  const std::string camera = TagsCameraMissing(dataset, camera_name_);
  if (!camera.empty()) return Applicability::No(camera);
  const std::string board = BoardWorldMissing(dataset);
  if (!board.empty()) return Applicability::No(board);
  return Applicability::Yes();
}

Estimate TagPnpEstimator::Run(const Dataset& dataset) {
  return RunInWorldFrame(dataset, board_, [&](const Dataset& dataset_W, const BoardWorld*) {
    return RunInWorld(dataset_W);
  });
}

Estimate TagPnpEstimator::RunInWorld(const Dataset& dataset) const {
  Estimate estimate;
  estimate.quantities = MakeQuantityTable(FramePoseQuantityNames());
  const CameraSensor& camera = *TagsCamera(dataset, camera_name_);
  // tags0 is time-ordered: one frame is a run of rows with the same stamp.
  std::vector<std::vector<TagObservation>> frames;
  for (size_t begin = 0; begin < dataset.tags.size();) {
    size_t end = begin;
    while (end < dataset.tags.size() && dataset.tags[end].t_ns == dataset.tags[begin].t_ns) ++end;
    frames.emplace_back(dataset.tags.begin() + begin, dataset.tags.begin() + end);
    begin = end;
  }
  const TagMapCheck check = CheckTagMap(frames, dataset.map.tags, camera, ransac_, map_check_);
  estimate.events = check.events;
  const bool refine = refine_.mode == TagMapRefineMode::kOn ||
                      (refine_.mode == TagMapRefineMode::kAuto && !check.disagreeing.empty());
  const std::map<int, TagInfo> tags =
      refine ? RefinedMap(frames, dataset.map.tags, camera, &estimate) : dataset.map.tags;
  if (refine && refine_.mode == TagMapRefineMode::kAuto && !estimate.events.empty())
    estimate.events.back() =
        fmt::format("{} (refine_map=auto: the map check named {} tag{})", estimate.events.back(),
                    check.disagreeing.size(), check.disagreeing.size() == 1 ? "" : "s");
  std::vector<CornerRansacResult> results;
  std::vector<TimeNs> frame_t_ns;
  results.reserve(frames.size());
  for (const std::vector<TagObservation>& frame : frames) {
    results.push_back(CornerPnpRansac(frame, tags, camera, ransac_));
    frame_t_ns.push_back(frame.front().t_ns);
  }
  RefuseNeighbourOutliers(frame_t_ns, &results);
  for (size_t f = 0; f < frames.size(); ++f)
    RecordFramePose(results[f], frames[f].front().t_ns, &estimate);
  return estimate;
}

void TagPnpEstimator::RefuseNeighbourOutliers(const std::vector<TimeNs>& frame_t_ns,
                                              std::vector<CornerRansacResult>* results) const {
  if (!neighbour_gate_.enabled()) return;
  std::vector<size_t> posed;
  std::vector<double> times_s;
  std::vector<Eigen::Vector3d> positions_W;
  for (size_t f = 0; f < results->size(); ++f) {
    if (!(*results)[f].pnp.ok) continue;
    posed.push_back(f);
    times_s.push_back(NsToSeconds(frame_t_ns[f] - frame_t_ns.front()));
    positions_W.push_back((*results)[f].pnp.T_W_B.p);
  }
  const std::vector<bool> refused = NeighbourGateRefusals(times_s, positions_W, neighbour_gate_);
  for (size_t k = 0; k < posed.size(); ++k) {
    if (!refused[k]) continue;
    CornerRansacResult& result = (*results)[posed[k]];
    result.pnp.ok = false;
    result.pnp.reason = NeighbourGateReason(neighbour_gate_);
    result.outlier_tags.clear();
  }
}

std::map<int, TagInfo> TagPnpEstimator::RefinedMap(
    const std::vector<std::vector<TagObservation>>& frames, const std::map<int, TagInfo>& tags,
    const CameraSensor& camera, Estimate* estimate) const {
  // First poses: the per-frame RANSAC PnP; a frame whose tags do not agree on the loose map (no
  // two within the threshold) starts from its best single tag, and the bundle adjustment decides.
  CornerRansacOptions any_tag = ransac_;
  any_tag.min_inlier_tags = 1;
  std::vector<TagMapRefineFrame> posed;
  for (const std::vector<TagObservation>& frame : frames) {
    CornerRansacResult first = CornerPnpRansac(frame, tags, camera, ransac_);
    if (!first.pnp.ok && ransac_.enabled) first = CornerPnpRansac(frame, tags, camera, any_tag);
    if (first.pnp.ok) posed.push_back({frame, first.pnp.T_W_B});
  }
  const TagMapRefinement refined = RefineTagMap(posed, tags, camera, refine_);
  if (!refined.ok) {
    estimate->events.push_back("tag map not refined: " + refined.reason);
    return tags;
  }
  estimate->events.push_back(refined.Summary());
  estimate->parameters["map_shift_max"] = {refined.MaxShift_m(), std::nullopt, "m"};
  estimate->parameters["map_shift_median"] = {refined.MedianShift_m(), std::nullopt, "m"};
  return refined.tags;
}

}  // namespace mavloc
