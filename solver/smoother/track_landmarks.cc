#include "solver/smoother/track_landmarks.h"

#include <algorithm>

namespace mavloc {

namespace {

int KeyframeIndexAt(const std::vector<TimeNs>& times, TimeNs t_ns) {
  auto it = std::lower_bound(times.begin(), times.end(), t_ns);
  return it != times.end() && *it == t_ns ? static_cast<int>(it - times.begin()) : -1;
}

}  // namespace

std::map<int, AnchoredTrack> AnchorTracks(const Dataset& dataset, const std::vector<TimeNs>& times,
                                          const std::vector<Pose>& T_W_B,
                                          const std::map<int, Eigen::Vector3d>& initial_W,
                                          const TrackLandmarkOptions& options) {
  std::map<int, AnchoredTrack> tracks;
  if (dataset.cameras.empty()) return tracks;
  const Pose& T_B_C0 = dataset.cameras.front().T_B_C;
  for (const FeatureObservation& obs : dataset.features) {
    if (tracks.count(obs.landmark_id)) continue;
    const int k = KeyframeIndexAt(times, obs.t_ns);
    if (k < 0) continue;
    AnchoredTrack track;
    track.anchor_keyframe = k;
    track.b_anchor_C0 = Eigen::Vector3d(obs.xy.x(), obs.xy.y(), 1.0).normalized();
    track.rho[0] = options.rho_prior_mean_per_m;
    auto it = initial_W.find(obs.landmark_id);
    if (it != initial_W.end()) {
      const Eigen::Vector3d p_C = (T_W_B[k] * T_B_C0).Inverse() * it->second;
      const double depth_m = p_C.dot(track.b_anchor_C0);
      if (depth_m > 0.0)
        track.rho[0] = std::clamp(1.0 / depth_m, options.min_rho_per_m, options.max_rho_per_m);
    }
    tracks[obs.landmark_id] = track;
  }
  return tracks;
}

Eigen::Vector3d TrackPositionW(const AnchoredTrack& track, const Pose& T_W_B_anchor,
                               const Pose& T_B_C0) {
  return (T_W_B_anchor * T_B_C0) * Eigen::Vector3d(track.b_anchor_C0 / track.rho[0]);
}

}  // namespace mavloc
