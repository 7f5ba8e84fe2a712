#include "solver/pose/tag_map_check.h"

#include <fmt/format.h>

namespace mavloc {

TagMapCheckOptions ParseTagMapCheckOptions(const EstimatorOptions& options) {
  TagMapCheckOptions out;
  out.enabled = options.GetBool("map_check", out.enabled);
  return out;
}

TagMapCheck CheckTagMap(const std::vector<std::vector<TagObservation>>& frames,
                        const std::map<int, TagInfo>& tags, const CameraSensor& camera,
                        const CornerRansacOptions& ransac, const TagMapCheckOptions& options) {
  TagMapCheck check;
  if (!options.enabled || !ransac.enabled) return check;
  for (const std::vector<TagObservation>& frame : frames) {
    int map_tags = 0;
    for (const TagObservation& o : frame) map_tags += tags.count(o.tag_id) ? 1 : 0;
    if (map_tags < 2) continue;
    const CornerRansacResult result = CornerPnpRansac(frame, tags, camera, ransac);
    if (!result.pnp.ok || result.inlier_tags.size() < 2) continue;
    for (const int id : result.inlier_tags) ++check.counts[id].agree;
    for (const int id : result.outlier_tags) ++check.counts[id].disagree;
  }
  for (const auto& [id, count] : check.counts) {
    const int checked = count.agree + count.disagree;
    if (count.disagree < options.min_disagreements ||
        !(count.disagree > options.max_disagreement_fraction * checked))
      continue;
    check.disagreeing.insert(id);
    check.events.push_back(fmt::format(
        "tag {} disagrees with the map: the other tags of the frame do not reproject its corners "
        "in {} of the {} frames where it was seen with agreeing tags (check its pose in map.yaml)",
        id, count.disagree, checked));
  }
  return check;
}

}  // namespace mavloc
