// Per-frame vision-only poses from tags0 on the map exactly as it is given: T_W_B on a world map,
// T_M_B on a board map (MapFrame::kBoard). One CornerPnp (solver/pose/corner_pnp.h: IPPE + LM on
// all the frame's corners) per tags0 stamp, with the camera of the tags (cameras[0], its model and
// T_B_C). The board initialisation (board_world.h) and tag-ekf's window initialisation use it.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/dataset.h"
#include "core/pose.h"

namespace mavloc {

// The number of map tags a tags0 frame must see to be used: min_tags, or the most any frame sees
// when no frame sees that many (a map of single markers far apart).
int ResolveMinTags(const Dataset& dataset, int min_tags);

// The first tags0 stamp that sees at least min_tags tags of the map, or nullopt.
std::optional<TimeNs> FirstMapTagTime(const Dataset& dataset, int min_tags = 1);

// The PnP pose of every tags0 frame with t_begin_ns <= t <= t_end_ns that sees at least min_tags
// tags of the map, in the map's frame. Frames where the PnP fails are left out and counted by
// reason in *failures (when given).
std::vector<StampedPose> FramePnpPoses(const Dataset& dataset, TimeNs t_begin_ns, TimeNs t_end_ns,
                                       std::map<std::string, int>* failures = nullptr,
                                       int min_tags = 1);

}  // namespace mavloc
