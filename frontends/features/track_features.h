// Natural-feature tracks over a dataset's images (`mavloc track-features`, and `compare`/`run` on
// an image log without a feature stream): every cam0 frame through the FeatureTracker, with the
// gyro rotation between consecutive frames from imu0, and cam1's frame of the same time when the
// dataset has a second camera with all its images. Images are loaded one at a time
// (frontends/image_io.h): memory does not grow with the log.
//
// Output: features0 (cam0) and features1 (cam1) observations with the track id as landmark id
// (unknown landmarks), one row of statistics per frame, the length of every track, and warnings
// for what was skipped (missing images, a mono fallback, frames without any corner).
#pragma once

#include <string>
#include <vector>

#include "core/dataset.h"
#include "frontends/features/feature_tracker.h"

namespace mavloc {

struct FeatureTrackingSettings {
  FeatureTrackerOptions tracker;
  bool stereo = true;  // match into cam1 where the dataset has one with its images
};

struct FeatureTrackingResult {
  std::vector<FeatureObservation> features0;
  std::vector<FeatureObservation> features1;
  std::vector<FeatureFrameStatistics> frames;
  std::vector<int> track_lengths;  // every track's length in frames (lost ones and those alive)
  std::vector<std::string> warnings;
  bool stereo = false;     // whether cam1 was matched
  int frames_missing = 0;  // cam0 frames listed without an image (skipped)
  double load_ms = 0.0;    // image loading and decoding, all frames

  double MeanTrackLength() const;
  double MeanTracksPerFrame() const;
  // Share of the tracks entering a frame that pass forward-backward and RANSAC, over all frames.
  double InlierRatio() const;
  double MeanTimeMsPerFrame() const;
};

// Throws InputError when the dataset has no cam0 or no cam0 image at all, an image cannot be
// decoded, or its size is not the sensor.yaml's resolution (file and field named).
FeatureTrackingResult TrackFeaturesInDataset(const Dataset& dataset,
                                             const FeatureTrackingSettings& settings);

// "#timestamp [ns],tracked,new,lost,rejected_forward_backward,rejected_ransac,stereo_matched,
// stereo_rejected,stereo_rejected_epipolar,mean_track_length [frames],time [ms]".
std::string FeatureStatisticsCsv(const FeatureTrackingResult& result);

// The settings that ran and the summary, as YAML (features0/frontend.yaml).
std::string FeatureTrackingYaml(const FeatureTrackingResult& result,
                                const FeatureTrackingSettings& settings);

}  // namespace mavloc
