// The unknown landmarks of feature tracks (features0/features1 written by frontends/features/) in
// the smoother: each track is anchored in the first keyframe whose cam0 sees it and parameterised
// by its inverse depth along that first bearing (residuals/anchored_bearing_factor.h). The anchor
// observation itself defines the bearing (no residual); every later cam0 or cam1 observation is an
// AnchoredBearingFactor, the anchor keyframe's own cam1 observation (a stereo match) an
// AnchorStereoBearingFactor, and each track gets the weak InverseDepthPriorFactor.
#pragma once

#include <Eigen/Core>
#include <array>
#include <map>
#include <vector>

#include "core/dataset.h"
#include "core/pose.h"

namespace mavloc {

struct TrackLandmarkOptions {
  // The weak inverse-depth prior: mean 1/3 m^-1 (a point 3 m away), sigma 1 m^-1 (depths from
  // 0.5 m to infinity within one sigma). Its information (1 m^2) is that of a single bearing of
  // 1 px over a baseline of a few millimetres: it decides nothing a parallax can decide.
  double rho_prior_mean_per_m = 1.0 / 3.0;
  double rho_prior_sigma_per_m = 1.0;
  double min_rho_per_m = 1e-3;  // lower bound: 1 km (behind the camera is rho < 0)
  double max_rho_per_m = 20.0;  // upper bound: 5 cm
};

struct AnchoredTrack {
  int anchor_keyframe = -1;
  Eigen::Vector3d b_anchor_C0 = Eigen::Vector3d::UnitZ();  // unit bearing in the anchor's cam0
  std::array<double, 1> rho{1.0 / 3.0};                    // the parameter block, 1/m
};

// Anchors every track id of features0 that has a cam0 observation at a keyframe time (times
// sorted): the first such observation. The inverse depth starts from initial_W when it holds the
// track (1 / its depth in the anchor camera, clamped to the bounds; the prior mean when it is
// behind the camera) and from the prior mean otherwise.
std::map<int, AnchoredTrack> AnchorTracks(const Dataset& dataset, const std::vector<TimeNs>& times,
                                          const std::vector<Pose>& T_W_B,
                                          const std::map<int, Eigen::Vector3d>& initial_W,
                                          const TrackLandmarkOptions& options);

// The landmark in W: p_W = T_W_C0(anchor) (b_anchor / rho).
Eigen::Vector3d TrackPositionW(const AnchoredTrack& track, const Pose& T_W_B_anchor,
                               const Pose& T_B_C0);

}  // namespace mavloc
