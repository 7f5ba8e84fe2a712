// Checks the tag map against the log: a tag whose map pose is wrong (a tag that moved after the
// survey, a loose entry of a hand-made map, a duplicated id) gives a wrong pose in every frame
// where it is seen alone, which no per-frame test can catch. Seen with other tags it shows: the
// frame's consensus pose (corner_pnp_ransac.h, from the other tags) does not reproject its corners.
//
// Over the frames whose RANSAC finds a consensus of at least two tags, each tag of the frame is
// counted as agreeing (an inlier of the consensus) or disagreeing (an outlier). A frame of two tags
// that disagree has no consensus and counts for neither: nothing says which of the two is wrong.
// A tag that disagrees in at least min_disagreements frames and in more than
// max_disagreement_fraction of the frames that checked it is named in the report, so that the user
// can fix the map. The estimate does not change: on a map whose every tag is loose by 10-20 cm
// (TagSLAM's test 11) the tags named are not those that spoil the lone-tag frames, and leaving
// them out made the per-frame estimate worse (docs/commands/logs.md). map_check=0 skips the check.
#pragma once

#include <map>
#include <set>
#include <string>
#include <vector>

#include "core/dataset.h"
#include "solver/estimator.h"
#include "solver/pose/corner_pnp_ransac.h"

namespace mavloc {

struct TagMapCheckOptions {
  bool enabled = true;                     // map_check
  int min_disagreements = 3;               // frames in which a tag must disagree to be left out
  double max_disagreement_fraction = 0.5;  // of the frames that checked it
};

// From `--option map_check=0|1`.
TagMapCheckOptions ParseTagMapCheckOptions(const EstimatorOptions& options);

struct TagMapCheckCount {
  int agree = 0;
  int disagree = 0;
};

struct TagMapCheck {
  std::map<int, TagMapCheckCount> counts;  // per tag id checked
  std::set<int> disagreeing;               // tag ids named in the report
  std::vector<std::string> events;         // one line per tag named, for the report
};

// `frames`: the frames' observations (one vector per frame, map ids or not).
TagMapCheck CheckTagMap(const std::vector<std::vector<TagObservation>>& frames,
                        const std::map<int, TagInfo>& tags, const CameraSensor& camera,
                        const CornerRansacOptions& ransac, const TagMapCheckOptions& options);

}  // namespace mavloc
