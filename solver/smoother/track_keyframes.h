// Keyframes for feature tracks, so that a hover does not pile up frames: the first frame of
// features0, then a frame becomes a keyframe when the median displacement of the tracks it shares
// with the last keyframe exceeds min_parallax_px (normalized displacement times cam0's focal
// length; rotation included: a turn brings new structure into view too), when fewer than
// min_shared_ratio of the last keyframe's tracks are still seen, or when max_interval_s has passed
// (the IMU factors stay short and the biases' random walk is sampled).
#pragma once

#include <vector>

#include "core/dataset.h"

namespace mavloc {

struct TrackKeyframeOptions {
  double min_parallax_px = 10.0;
  double min_shared_ratio = 0.7;
  double max_interval_s = 0.5;
  double focal_px = 458.0;  // cam0's fu
};

// Sorted keyframe times among the frame times of features0 that lie within [t_min_ns, t_max_ns]
// (the IMU stream).
std::vector<TimeNs> SelectTrackKeyframes(const std::vector<FeatureObservation>& features0,
                                         const TrackKeyframeOptions& options, TimeNs t_min_ns,
                                         TimeNs t_max_ns);

// The frames of features0 at which the camera is at rest: the median displacement of the tracks it
// shares with the previous frame is below max_motion_px (normalized displacement times focal_px)
// over at least min_shared tracks. Sorted times.
std::vector<TimeNs> StationaryFrames(const std::vector<FeatureObservation>& features0,
                                     double max_motion_px, double focal_px, int min_shared = 10);

// The observations of `features` at the given (sorted) times.
std::vector<FeatureObservation> FeaturesAtTimes(const std::vector<FeatureObservation>& features,
                                                const std::vector<TimeNs>& times);

}  // namespace mavloc
