#include "solver/board/frame_pnp.h"

#include <algorithm>

#include "solver/pose/corner_pnp.h"
#include "solver/pose/tags_camera.h"

namespace mavloc {

namespace {

// Calls visit(t_ns, begin, end, map tags seen) for every run of tags0 rows with one stamp.
template <typename Visit>
void ForEachFrame(const Dataset& dataset, Visit&& visit) {
  const std::vector<TagObservation>& tags = dataset.tags;
  for (size_t begin = 0; begin < tags.size();) {
    size_t end = begin;
    int in_map = 0;
    while (end < tags.size() && tags[end].t_ns == tags[begin].t_ns) {
      in_map += dataset.map.tags.count(tags[end].tag_id) > 0 ? 1 : 0;
      ++end;
    }
    if (!visit(tags[begin].t_ns, begin, end, in_map)) return;
    begin = end;
  }
}

}  // namespace

int ResolveMinTags(const Dataset& dataset, int min_tags) {
  int most = 0;
  ForEachFrame(dataset, [&](TimeNs, size_t, size_t, int in_map) {
    most = std::max(most, in_map);
    return most < min_tags;
  });
  return std::max(1, std::min(min_tags, most));
}

std::optional<TimeNs> FirstMapTagTime(const Dataset& dataset, int min_tags) {
  std::optional<TimeNs> first;
  ForEachFrame(dataset, [&](TimeNs t, size_t, size_t, int in_map) {
    if (in_map >= std::max(1, min_tags)) first = t;
    return !first.has_value();
  });
  return first;
}

std::vector<StampedPose> FramePnpPoses(const Dataset& dataset, TimeNs t_begin_ns, TimeNs t_end_ns,
                                       std::map<std::string, int>* failures, int min_tags) {
  std::vector<StampedPose> poses;
  const CameraSensor* camera = TagsCamera(dataset);
  if (camera == nullptr) {
    if (failures) ++(*failures)["no camera calibration"];
    return poses;
  }
  ForEachFrame(dataset, [&](TimeNs t, size_t begin, size_t end, int in_map) {
    if (t > t_end_ns) return false;
    if (t < t_begin_ns || in_map < std::max(1, min_tags)) return true;
    const std::vector<TagObservation> frame(dataset.tags.begin() + begin,
                                            dataset.tags.begin() + end);
    const CornerPnpResult result = CornerPnp(frame, dataset.map.tags, *camera);
    if (result.ok) {
      poses.push_back({t, result.T_W_B});
    } else if (failures) {
      ++(*failures)[result.reason];
    }
    return true;
  });
  return poses;
}

}  // namespace mavloc
