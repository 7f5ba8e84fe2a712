#include "evaluation/feature_frontend.h"

#include <fmt/format.h>
#include <algorithm>
#include <filesystem>

#include "core/atomic_file.h"
#include "core/errors.h"
#include "core/interrupt.h"
#include "datasets/io/euroc_io.h"

namespace mavloc {

namespace fs = std::filesystem;

bool NeedsFeatureTracks(const Dataset& dataset, const std::vector<std::string>& estimators) {
  if (std::find(estimators.begin(), estimators.end(), "smoother") == estimators.end()) return false;
  if (!dataset.features.empty() || !dataset.laser.empty() || dataset.cameras.empty()) return false;
  for (const auto& obs : dataset.tags)
    if (dataset.map.tags.count(obs.tag_id)) return false;
  const CameraSensor& cam0 = dataset.cameras.front();
  return !cam0.frames.empty() && cam0.missing_images.size() < cam0.frames.size();
}

FeatureFrontendRun AddFeatureTracks(Dataset* dataset, const FeatureTrackingSettings& settings) {
  FeatureFrontendRun run;
  run.settings = settings;
  run.result = TrackFeaturesInDataset(*dataset, settings);
  dataset->features = run.result.features0;
  dataset->features1 = run.result.features1;
  run.note = fmt::format(
      "feature tracks from the images ({}): {} frames, {} tracks, {:.1f} per frame, {:.1f} frames "
      "long on average, {:.1f} % kept by the forward-backward and RANSAC tests, {:.2f} ms per "
      "frame",
      run.result.stereo ? "stereo cam0 + cam1" : "mono cam0", run.result.frames.size(),
      run.result.track_lengths.size(), run.result.MeanTracksPerFrame(),
      run.result.MeanTrackLength(), 100.0 * run.result.InlierRatio(),
      run.result.MeanTimeMsPerFrame());
  return run;
}

void WriteFeatureTracks(const FeatureFrontendRun& run, const std::string& dataset_root,
                        bool replace) {
  const fs::path mav0 = fs::path(dataset_root) / "mav0";
  const fs::path features0 = mav0 / "features0";
  if (fs::exists(features0 / "data.csv") && !replace)
    throw InputError((features0 / "data.csv").string(), 0, "",
                     "exists: the dataset has a feature stream already (--force replaces it)");
  CreateOutputDirectories(features0);
  WriteFileAtomically((features0 / "data.csv").string(), FeaturesCsv(run.result.features0));
  WriteFileAtomically((features0 / "tracking.csv").string(), FeatureStatisticsCsv(run.result));
  WriteFileAtomically((features0 / "frontend.yaml").string(),
                      FeatureTrackingYaml(run.result, run.settings));
  const fs::path features1 = mav0 / "features1" / "data.csv";
  if (run.result.stereo) {
    CreateOutputDirectories(features1.parent_path());
    WriteFileAtomically(features1.string(), FeaturesCsv(run.result.features1));
  } else if (fs::exists(features1)) {
    fs::remove(features1);  // a stale stereo stream of an earlier run would not match the ids
  }
}

namespace {

double Sum(const FeatureTrackingResult& r, int FeatureFrameStatistics::*field) {
  double sum = 0.0;
  for (const auto& f : r.frames) sum += f.*field;
  return sum;
}

}  // namespace

void AddFeatureFrontendToReport(const FeatureFrontendRun& run, Report* report) {
  const FeatureTrackingResult& r = run.result;
  ReportTable table;
  table.name = "feature_frontend";
  table.title = std::string("Feature frontend (") + (r.stereo ? "stereo" : "mono") +
                "): what happened to the tracks, over all frames";
  table.columns = {{"quantity", "", ""}, {"value", "", ""}, {"unit", "", ""}};
  const auto row = [&](const std::string& name, double value, const std::string& unit) {
    table.rows.push_back({name, value, unit});
  };
  row("frames", static_cast<double>(r.frames.size()), "");
  row("tracks", static_cast<double>(r.track_lengths.size()), "");
  row("tracks per frame (mean)", r.MeanTracksPerFrame(), "");
  row("track length (mean)", r.MeanTrackLength(), "frames");
  row("kept by forward-backward and RANSAC", 100.0 * r.InlierRatio(), "%");
  row("lost (Lucas-Kanade failed, left the image)", Sum(r, &FeatureFrameStatistics::lost), "");
  row("rejected: forward-backward", Sum(r, &FeatureFrameStatistics::rejected_forward_backward), "");
  row("rejected: RANSAC", Sum(r, &FeatureFrameStatistics::rejected_ransac), "");
  row("stereo matches", Sum(r, &FeatureFrameStatistics::stereo_matched), "");
  row("stereo rejected: epipolar", Sum(r, &FeatureFrameStatistics::stereo_rejected_epipolar), "");
  row("stereo rejected: tracking or depth", Sum(r, &FeatureFrameStatistics::stereo_rejected), "");
  row("tracking time per frame (mean)", r.MeanTimeMsPerFrame(), "ms");
  row("image loading per frame (mean)",
      r.frames.empty() ? 0.0 : r.load_ms / static_cast<double>(r.frames.size()), "ms");
  report->tables.push_back(table);
  const FeatureTrackerOptions& o = run.settings.tracker;
  report->details["frontend"] = {
      {"stereo", r.stereo},
      {"grid", {o.detector.grid_cols, o.detector.grid_rows}},
      {"max_features", o.detector.max_features},
      {"min_distance_px", o.detector.min_distance_px},
      {"fast_threshold", o.detector.fast_threshold},
      {"klt_window_px", o.klt_window_px},
      {"klt_pyramid_levels", o.klt_pyramid_levels},
      {"forward_backward_px", o.forward_backward_px},
      {"use_gyro", o.use_gyro},
      {"rejection", o.rejection == FrameOutlierRejection::kTwoPoint    ? "two-point"
                    : o.rejection == FrameOutlierRejection::kFivePoint ? "five-point"
                                                                       : "none"},
      {"ransac_threshold_px", o.ransac_threshold_px},
      {"stereo_epipolar_px", o.stereo_epipolar_px},
      {"mean_time_s_per_frame", r.MeanTimeMsPerFrame() * 1e-3}};
  for (const auto& w : r.warnings) report->warnings.push_back("feature frontend: " + w);
  report->sections.push_back({"Feature frontend", run.note + ".\n", true});
  report->files["feature_tracking.csv"] = FeatureStatisticsCsv(r);
}

}  // namespace mavloc
