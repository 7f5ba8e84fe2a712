#include "solver/smoother/track_keyframes.h"

#include <algorithm>
#include <unordered_map>

namespace mavloc {

namespace {

// The frames of a time-ordered stream: [begin, end) index ranges of equal stamps.
std::vector<std::pair<size_t, size_t>> Frames(const std::vector<FeatureObservation>& features) {
  std::vector<std::pair<size_t, size_t>> frames;
  for (size_t i = 0; i < features.size();) {
    size_t j = i;
    while (j < features.size() && features[j].t_ns == features[i].t_ns) ++j;
    frames.emplace_back(i, j);
    i = j;
  }
  return frames;
}

// Median displacement in pixels of the tracks of frame b that frame a has too, and their count.
std::pair<double, int> MedianMotionPx(const std::vector<FeatureObservation>& f,
                                      std::pair<size_t, size_t> a, std::pair<size_t, size_t> b,
                                      double focal_px) {
  std::unordered_map<int, Eigen::Vector2d> in_a;
  for (size_t i = a.first; i < a.second; ++i) in_a[f[i].landmark_id] = f[i].xy;
  std::vector<double> moved_px;
  for (size_t i = b.first; i < b.second; ++i) {
    auto it = in_a.find(f[i].landmark_id);
    if (it != in_a.end()) moved_px.push_back((f[i].xy - it->second).norm() * focal_px);
  }
  if (moved_px.empty()) return {0.0, 0};
  std::nth_element(moved_px.begin(), moved_px.begin() + moved_px.size() / 2, moved_px.end());
  return {moved_px[moved_px.size() / 2], static_cast<int>(moved_px.size())};
}

}  // namespace

std::vector<TimeNs> StationaryFrames(const std::vector<FeatureObservation>& features0,
                                     double max_motion_px, double focal_px, int min_shared) {
  std::vector<TimeNs> stationary;
  const auto frames = Frames(features0);
  for (size_t j = 1; j < frames.size(); ++j) {
    const auto [median_px, shared] = MedianMotionPx(features0, frames[j - 1], frames[j], focal_px);
    if (shared >= min_shared && median_px < max_motion_px)
      stationary.push_back(features0[frames[j].first].t_ns);
  }
  return stationary;
}

std::vector<TimeNs> SelectTrackKeyframes(const std::vector<FeatureObservation>& features0,
                                         const TrackKeyframeOptions& o, TimeNs t_min_ns,
                                         TimeNs t_max_ns) {
  std::vector<TimeNs> keyframes;
  std::unordered_map<int, Eigen::Vector2d> at_keyframe;  // track id -> xy at the last keyframe
  const TimeNs max_interval_ns = static_cast<TimeNs>(o.max_interval_s * 1e9);
  for (const auto& [begin, end] : Frames(features0)) {
    const TimeNs t = features0[begin].t_ns;
    if (t < t_min_ns || t > t_max_ns) continue;
    bool take = keyframes.empty() || t - keyframes.back() >= max_interval_ns;
    if (!take) {
      std::vector<double> moved_px;
      for (size_t i = begin; i < end; ++i) {
        auto it = at_keyframe.find(features0[i].landmark_id);
        if (it != at_keyframe.end())
          moved_px.push_back((features0[i].xy - it->second).norm() * o.focal_px);
      }
      const double shared = at_keyframe.empty() ? 0.0
                                                : static_cast<double>(moved_px.size()) /
                                                      static_cast<double>(at_keyframe.size());
      if (moved_px.empty() || shared < o.min_shared_ratio) {
        take = true;
      } else {
        std::nth_element(moved_px.begin(), moved_px.begin() + moved_px.size() / 2, moved_px.end());
        take = moved_px[moved_px.size() / 2] > o.min_parallax_px;
      }
    }
    if (!take) continue;
    keyframes.push_back(t);
    at_keyframe.clear();
    for (size_t i = begin; i < end; ++i) at_keyframe[features0[i].landmark_id] = features0[i].xy;
  }
  return keyframes;
}

std::vector<FeatureObservation> FeaturesAtTimes(const std::vector<FeatureObservation>& features,
                                                const std::vector<TimeNs>& times) {
  std::vector<FeatureObservation> kept;
  for (const FeatureObservation& f : features)
    if (std::binary_search(times.begin(), times.end(), f.t_ns)) kept.push_back(f);
  return kept;
}

}  // namespace mavloc
