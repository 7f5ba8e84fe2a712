// Initial positions of feature-track landmarks from keyframe poses: the least-squares intersection
// of the track's rays from every keyframe observation in cam0 and cam1 (sum of the projectors
// I - d d^T onto the planes normal to each ray direction d; stereo gives a baseline in a single
// keyframe, mono needs the motion between keyframes). A track is left out (the smoother then starts
// it at the inverse-depth prior's mean) when its rays span less than min_parallax_rad, when the
// intersection is behind any observing camera, or when any observation's angular error at the
// intersection exceeds max_error_rad.
#pragma once

#include <Eigen/Core>
#include <map>
#include <set>
#include <vector>

#include "core/dataset.h"
#include "solver/smoother/smoother_problem.h"

namespace mavloc {

struct TrackTriangulationOptions {
  double min_parallax_rad = 0.0175;  // 1 deg
  double max_error_rad = 0.01;
};

// Tracks of features0/features1 at the keyframes' times; `skip` ids are not triangulated.
std::map<int, Eigen::Vector3d> TriangulateTracks(const Dataset& dataset,
                                                 const std::vector<SmootherKeyframe>& keyframes,
                                                 const std::set<int>& skip,
                                                 const TrackTriangulationOptions& options);

}  // namespace mavloc
