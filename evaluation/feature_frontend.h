// The natural-feature frontend (frontends/features/track_features.h) as `compare`, `run` and
// `track-features` use it: when an image log has no feature stream, the smoother's visual
// residuals come from tracking features in its images first; the tracks go into the dataset in
// memory (compare, run) or into its folder (track-features), and the report gets the frontend's
// settings and statistics.
#pragma once

#include <string>
#include <vector>

#include "core/dataset.h"
#include "evaluation/report/report.h"
#include "frontends/features/track_features.h"

namespace mavloc {

struct FeatureFrontendRun {
  FeatureTrackingSettings settings;
  FeatureTrackingResult result;
  std::string note;  // one line for people: what ran, on which cameras, and what it gave
};

// Whether the estimators need tracks first: the smoother is among them, the dataset has cam0
// frames with images on disk, no features0, and nothing else the smoother would use instead (tags
// of the map, the laser spot).
bool NeedsFeatureTracks(const Dataset& dataset, const std::vector<std::string>& estimators);

// Tracks features in the dataset's images and puts them into dataset->features / features1.
FeatureFrontendRun AddFeatureTracks(Dataset* dataset, const FeatureTrackingSettings& settings);

// Writes mav0/features0/data.csv (and features1/data.csv for stereo), and beside features0 its
// per-frame statistics (tracking.csv) and the settings and summary (frontend.yaml), each file
// atomically. Refuses to replace an existing features0 unless `replace`.
void WriteFeatureTracks(const FeatureFrontendRun& run, const std::string& dataset_root,
                        bool replace);

// The report's part: a table of the frontend's statistics, its settings in details["frontend"],
// its warnings, and tracking.csv among the files.
void AddFeatureFrontendToReport(const FeatureFrontendRun& run, Report* report);

}  // namespace mavloc
