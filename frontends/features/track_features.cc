#include "frontends/features/track_features.h"

#include <fmt/format.h>
#include <algorithm>
#include <chrono>
#include <filesystem>
#include <set>

#include "core/errors.h"
#include "frontends/features/gyro_rotation.h"
#include "frontends/image_io.h"

namespace mavloc {

namespace {

constexpr TimeNs kSameFrameNs = 1'000'000;  // a cam1 frame within 1 ms is cam0's stereo partner

std::set<std::string> MissingSet(const CameraSensor& camera) {
  return {camera.missing_images.begin(), camera.missing_images.end()};
}

// The image of a frame, checked against the calibration's resolution.
cv::Mat LoadFrame(const CameraSensor& camera, const CameraFrame& frame) {
  cv::Mat gray = LoadGrayImage(frame.image_path);
  if (gray.cols != camera.model.width() || gray.rows != camera.model.height())
    throw InputError(
        frame.image_path, 0, "resolution",
        fmt::format("the image is {} x {} px, but {}/sensor.yaml states {} x {}", gray.cols,
                    gray.rows, camera.name, camera.model.width(), camera.model.height()));
  return gray;
}

// cam1's frame index for every cam0 frame (-1 where none is within kSameFrameNs), when stereo
// can run: every partner frame has its image. Otherwise empty, with a warning.
std::vector<int> StereoPartners(const Dataset& dataset, std::vector<std::string>* warnings) {
  const CameraSensor& cam0 = dataset.cameras[0];
  const CameraSensor& cam1 = dataset.cameras[1];
  const std::set<std::string> missing = MissingSet(cam1);
  std::vector<int> partner(cam0.frames.size(), -1);
  size_t j = 0;
  int paired = 0, without_image = 0;
  for (size_t i = 0; i < cam0.frames.size(); ++i) {
    const TimeNs t = cam0.frames[i].t_ns;
    while (j < cam1.frames.size() && cam1.frames[j].t_ns < t - kSameFrameNs) ++j;
    if (j < cam1.frames.size() && std::abs(cam1.frames[j].t_ns - t) <= kSameFrameNs) {
      partner[i] = static_cast<int>(j);
      ++paired;
      if (missing.count(cam1.frames[j].image_path)) ++without_image;
    }
  }
  if (paired == 0) {
    warnings->push_back(fmt::format("{} has no frame at {}'s times: tracking mono ({} only)",
                                    cam1.name, cam0.name, cam0.name));
    return {};
  }
  if (without_image > 0) {
    warnings->push_back(
        fmt::format("cam1: {} of the {} frames at cam0's times have no image on disk (listed in "
                    "cam1/data.csv): tracking mono (cam0 only)",
                    without_image, paired));
    return {};
  }
  return partner;
}

}  // namespace

double FeatureTrackingResult::MeanTrackLength() const {
  if (track_lengths.empty()) return 0.0;
  double sum = 0.0;
  for (int l : track_lengths) sum += l;
  return sum / static_cast<double>(track_lengths.size());
}

double FeatureTrackingResult::MeanTracksPerFrame() const {
  if (frames.empty()) return 0.0;
  return static_cast<double>(features0.size()) / static_cast<double>(frames.size());
}

double FeatureTrackingResult::InlierRatio() const {
  double entering = 0.0, passed = 0.0;
  for (const auto& f : frames) {
    entering += f.tracked + f.lost + f.rejected_forward_backward + f.rejected_ransac;
    passed += f.tracked;
  }
  return entering > 0.0 ? passed / entering : 0.0;
}

double FeatureTrackingResult::MeanTimeMsPerFrame() const {
  if (frames.empty()) return 0.0;
  double sum = 0.0;
  for (const auto& f : frames) sum += f.time_ms;
  return sum / static_cast<double>(frames.size());
}

FeatureTrackingResult TrackFeaturesInDataset(const Dataset& dataset,
                                             const FeatureTrackingSettings& settings) {
  const std::string options_error = ValidateFeatureTrackerOptions(settings.tracker);
  if (!options_error.empty()) throw InputError("track-features: " + options_error);
  if (dataset.cameras.empty())
    throw InputError(dataset.root, 0, "cam0", "the dataset has no camera to track features in");
  const CameraSensor& cam0 = dataset.cameras[0];
  if (cam0.frames.empty() || cam0.missing_images.size() == cam0.frames.size())
    throw InputError(
        dataset.root + "/mav0/" + cam0.name + "/data.csv", 0, "filename",
        cam0.frames.empty() ? "no frames listed" : "none of the listed images exists on disk");
  FeatureTrackingResult result;
  std::vector<int> partner;
  if (settings.stereo && dataset.cameras.size() > 1 && !dataset.cameras[1].frames.empty())
    partner = StereoPartners(dataset, &result.warnings);
  result.stereo = !partner.empty();
  FeatureTracker tracker(cam0, result.stereo ? &dataset.cameras[1] : nullptr, settings.tracker);
  const std::set<std::string> missing = MissingSet(cam0);
  std::optional<TimeNs> previous_t;
  int frames_without_corners = 0;
  std::optional<TimeNs> first_without_corners;
  for (size_t i = 0; i < cam0.frames.size(); ++i) {
    const CameraFrame& frame = cam0.frames[i];
    if (missing.count(frame.image_path)) {
      ++result.frames_missing;
      continue;
    }
    const auto load_start = std::chrono::steady_clock::now();
    const cv::Mat gray0 = LoadFrame(cam0, frame);
    cv::Mat gray1;
    if (result.stereo && partner[i] >= 0)
      gray1 = LoadFrame(dataset.cameras[1], dataset.cameras[1].frames[partner[i]]);
    result.load_ms +=
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - load_start)
            .count();
    std::optional<Eigen::Quaterniond> q_Bprev_Bcurr;
    if (previous_t) q_Bprev_Bcurr = GyroRotation(dataset.imu.samples, *previous_t, frame.t_ns);
    FeatureFrameOutput out = tracker.Track(frame.t_ns, gray0, gray1, q_Bprev_Bcurr);
    previous_t = frame.t_ns;
    if (out.cam0.empty()) {
      ++frames_without_corners;
      if (!first_without_corners) first_without_corners = frame.t_ns;
    }
    result.features0.insert(result.features0.end(), out.cam0.begin(), out.cam0.end());
    result.features1.insert(result.features1.end(), out.cam1.begin(), out.cam1.end());
    result.track_lengths.insert(result.track_lengths.end(), out.ended_track_lengths.begin(),
                                out.ended_track_lengths.end());
    result.frames.push_back(out.statistics);
  }
  for (int l : tracker.AliveTrackLengths()) result.track_lengths.push_back(l);
  if (result.frames_missing > 0)
    result.warnings.push_back(fmt::format("cam0: {} of {} listed frames have no image (skipped)",
                                          result.frames_missing, cam0.frames.size()));
  if (frames_without_corners > 0)
    result.warnings.push_back(fmt::format(
        "cam0: {} frames without any corner (flat, black or saturated images), the first at "
        "t = {} ns",
        frames_without_corners, *first_without_corners));
  return result;
}

std::string FeatureStatisticsCsv(const FeatureTrackingResult& result) {
  std::string csv =
      "#timestamp [ns],tracked,new,lost,rejected_forward_backward,rejected_ransac,stereo_matched,"
      "stereo_rejected,stereo_rejected_epipolar,mean_track_length [frames],time [ms]\n";
  for (const auto& f : result.frames)
    csv +=
        fmt::format("{},{},{},{},{},{},{},{},{},{:.3f},{:.4f}\n", f.t_ns, f.tracked, f.new_tracks,
                    f.lost, f.rejected_forward_backward, f.rejected_ransac, f.stereo_matched,
                    f.stereo_rejected, f.stereo_rejected_epipolar, f.mean_track_length, f.time_ms);
  return csv;
}

namespace {
const char* RejectionName(FrameOutlierRejection r) {
  switch (r) {
    case FrameOutlierRejection::kTwoPoint:
      return "two-point";
    case FrameOutlierRejection::kFivePoint:
      return "five-point";
    case FrameOutlierRejection::kNone:
      return "none";
  }
  return "none";
}
}  // namespace

std::string FeatureTrackingYaml(const FeatureTrackingResult& r, const FeatureTrackingSettings& s) {
  const FeatureTrackerOptions& o = s.tracker;
  std::string y = "# mavloc track-features: the frontend's settings and summary\n";
  y += fmt::format("stereo: {}\n", r.stereo ? 1 : 0);
  y += fmt::format(
      "settings:\n  grid: {} x {}\n  max_features: {}\n  min_distance_px: {}\n"
      "  fast_threshold: {}\n  fast_threshold_low: {}\n  klt_window_px: {}\n"
      "  klt_pyramid_levels: {}\n  forward_backward_px: {}\n  use_gyro: {}\n"
      "  rejection: {}\n  ransac_threshold_px: {}\n  stereo_epipolar_px: {}\n",
      o.detector.grid_cols, o.detector.grid_rows, o.detector.max_features,
      o.detector.min_distance_px, o.detector.fast_threshold, o.detector.fast_threshold_low,
      o.klt_window_px, o.klt_pyramid_levels, o.forward_backward_px, o.use_gyro ? 1 : 0,
      RejectionName(o.rejection), o.ransac_threshold_px, o.stereo_epipolar_px);
  y += fmt::format(
      "summary:\n  frames: {}\n  frames_missing: {}\n  tracks: {}\n  features0: {}\n"
      "  features1: {}\n  mean_tracks_per_frame: {:.2f}\n  mean_track_length_frames: {:.2f}\n"
      "  inlier_ratio: {:.4f}\n  mean_time_ms_per_frame: {:.3f}\n",
      r.frames.size(), r.frames_missing, r.track_lengths.size(), r.features0.size(),
      r.features1.size(), r.MeanTracksPerFrame(), r.MeanTrackLength(), r.InlierRatio(),
      r.MeanTimeMsPerFrame());
  if (!r.warnings.empty()) {
    y += "warnings:\n";
    for (const auto& w : r.warnings) y += "  - \"" + w + "\"\n";
  }
  return y;
}

}  // namespace mavloc
