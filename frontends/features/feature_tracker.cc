#include "frontends/features/feature_tracker.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>

#include "core/rotation.h"
#include "frontends/features/five_point_ransac.h"
#include "frontends/features/two_point_ransac.h"

namespace mavloc {

namespace {

cv::TermCriteria KltCriteria(const FeatureTrackerOptions& o) {
  return cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, o.klt_max_iterations,
                          o.klt_epsilon_px);
}

bool Inside(const cv::Point2f& p, const cv::Size& size, int border_px) {
  return p.x >= border_px && p.y >= border_px && p.x <= size.width - 1 - border_px &&
         p.y <= size.height - 1 - border_px;
}

Eigen::Vector3d Bearing(const Eigen::Vector2d& xy) { return Eigen::Vector3d(xy.x(), xy.y(), 1.0); }

// Where a pixel with normalized coordinates xy goes under a pure rotation R_Cb_Ca of the camera
// (a point at infinity), in pixels of `model`; nullopt when it turns behind the camera.
std::optional<cv::Point2f> RotatedPixel(const CameraModel& model, const Eigen::Matrix3d& R_Cb_Ca,
                                        const Eigen::Vector2d& xy) {
  const std::optional<Eigen::Vector2d> uv = model.Project(R_Cb_Ca * Bearing(xy), 1e-3);
  if (!uv) return std::nullopt;
  return cv::Point2f(static_cast<float>(uv->x()), static_cast<float>(uv->y()));
}

std::optional<Eigen::Vector2d> Normalized(const CameraModel& model, const cv::Point2f& p) {
  return model.PixelToNormalized(Eigen::Vector2d(p.x, p.y));
}

// Lucas-Kanade from pyramid a to pyramid b, started at *to (the prediction; the result on return),
// then back from the result to a. Per point: whether the forward pass succeeded, and the return
// error |back - from| in pixels (infinite when the backward pass failed).
struct ForwardBackward {
  std::vector<uchar> forward_ok;
  std::vector<double> return_error_px;
};

ForwardBackward TrackForwardBackward(const std::vector<cv::Mat>& a, const std::vector<cv::Mat>& b,
                                     const std::vector<cv::Point2f>& from,
                                     std::vector<cv::Point2f>* to, int levels,
                                     const FeatureTrackerOptions& o) {
  const cv::Size window(o.klt_window_px, o.klt_window_px);
  ForwardBackward result;
  std::vector<uchar> back_ok;
  std::vector<float> error;
  cv::calcOpticalFlowPyrLK(a, b, from, *to, result.forward_ok, error, window, levels,
                           KltCriteria(o), cv::OPTFLOW_USE_INITIAL_FLOW);
  std::vector<cv::Point2f> back = from;
  cv::calcOpticalFlowPyrLK(b, a, *to, back, back_ok, error, window, levels, KltCriteria(o),
                           cv::OPTFLOW_USE_INITIAL_FLOW);
  for (size_t i = 0; i < from.size(); ++i)
    result.return_error_px.push_back(back_ok[i] ? cv::norm(back[i] - from[i])
                                                : std::numeric_limits<double>::infinity());
  return result;
}

}  // namespace

std::string ValidateFeatureTrackerOptions(const FeatureTrackerOptions& o) {
  const GridDetectorOptions& d = o.detector;
  if (d.grid_cols < 1 || d.grid_cols > 64 || d.grid_rows < 1 || d.grid_rows > 64)
    return "grid_cols and grid_rows must be in [1, 64]";
  if (d.max_features < 1 || d.max_features > 5000) return "max_features must be in [1, 5000]";
  if (!(d.min_distance_px >= 1.0 && d.min_distance_px <= 200.0))
    return "min_distance_px must be in [1, 200]";
  if (d.fast_threshold < 1 || d.fast_threshold > 255 || d.fast_threshold_low < 1 ||
      d.fast_threshold_low > d.fast_threshold)
    return "fast_threshold must be in [1, 255] and fast_threshold_low in [1, fast_threshold]";
  if (o.klt_window_px < 5 || o.klt_window_px > 101 || o.klt_window_px % 2 == 0)
    return "klt_window_px must be odd and in [5, 101]";
  if (o.klt_pyramid_levels < 0 || o.klt_pyramid_levels > 8 || o.stereo_pyramid_levels < 0 ||
      o.stereo_pyramid_levels > 8)
    return "klt_pyramid_levels and stereo_pyramid_levels must be in [0, 8]";
  if (!(o.forward_backward_px > 0.0 && o.forward_backward_px <= 50.0))
    return "forward_backward_px must be in (0, 50]";
  if (!(o.ransac_threshold_px > 0.0 && o.ransac_threshold_px <= 50.0))
    return "ransac_threshold_px must be in (0, 50]";
  if (!(o.ransac_confidence > 0.5 && o.ransac_confidence < 1.0))
    return "ransac_confidence must be in (0.5, 1)";
  if (o.ransac_max_iterations < 1 || o.ransac_max_iterations > 100000)
    return "ransac_max_iterations must be in [1, 100000]";
  if (!(o.stereo_epipolar_px > 0.0 && o.stereo_epipolar_px <= 50.0))
    return "stereo_epipolar_px must be in (0, 50]";
  return "";
}

FeatureTracker::FeatureTracker(const CameraSensor& cam0, const CameraSensor* cam1,
                               const FeatureTrackerOptions& options)
    : model0_(cam0.model), T_B_C0_(cam0.T_B_C), options_(options) {
  if (cam1) {
    model1_ = cam1->model;
    T_C1_C0_ = cam1->T_B_C.Inverse() * cam0.T_B_C;
  }
}

std::vector<int> FeatureTracker::AliveTrackLengths() const {
  std::vector<int> lengths;
  for (const TrackState& t : tracks_) lengths.push_back(t.length);
  return lengths;
}

FeatureFrameOutput FeatureTracker::Track(TimeNs t_ns, const cv::Mat& gray0, const cv::Mat& gray1,
                                         const std::optional<Eigen::Quaterniond>& q_Bprev_Bcurr) {
  const auto start = std::chrono::steady_clock::now();
  FeatureFrameOutput out;
  out.statistics.t_ns = t_ns;
  std::vector<cv::Mat> pyramid;
  const cv::Size window(options_.klt_window_px, options_.klt_window_px);
  cv::buildOpticalFlowPyramid(
      gray0, pyramid, window,
      std::max(options_.klt_pyramid_levels, options_.stereo_pyramid_levels));
  if (!previous_pyramid_.empty() && !tracks_.empty()) TrackIntoFrame(pyramid, q_Bprev_Bcurr, &out);
  AddNewTracks(gray0, &out);
  for (const TrackState& t : tracks_) out.cam0.push_back({t_ns, t.id, t.xy, 0});
  if (model1_ && !gray1.empty()) MatchIntoCam1(pyramid, gray1, &out);
  if (!tracks_.empty()) {
    double sum = 0.0;
    for (const TrackState& t : tracks_) sum += t.length;
    out.statistics.mean_track_length = sum / static_cast<double>(tracks_.size());
  }
  previous_pyramid_ = std::move(pyramid);
  ++frame_index_;
  out.statistics.time_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return out;
}

void FeatureTracker::TrackIntoFrame(const std::vector<cv::Mat>& pyramid,
                                    const std::optional<Eigen::Quaterniond>& q_Bprev_Bcurr,
                                    FeatureFrameOutput* out) {
  const cv::Size size = pyramid.front().size();
  // R_Ccurr_Cprev = R_C_B R_Bcurr_Bprev R_B_C: what a point at infinity does between the frames.
  const bool gyro = options_.use_gyro && q_Bprev_Bcurr.has_value();
  const Eigen::Matrix3d R_B_C = T_B_C0_.q.toRotationMatrix();
  const Eigen::Matrix3d R_Ccurr_Cprev =
      gyro ? Eigen::Matrix3d(R_B_C.transpose() * q_Bprev_Bcurr->conjugate().toRotationMatrix() *
                             R_B_C)
           : Eigen::Matrix3d::Identity();
  std::vector<cv::Point2f> previous, current;
  for (const TrackState& t : tracks_) {
    previous.push_back(t.px);
    const std::optional<cv::Point2f> predicted =
        gyro ? RotatedPixel(model0_, R_Ccurr_Cprev, t.xy) : std::nullopt;
    current.push_back(predicted && Inside(*predicted, size, 0) ? *predicted : t.px);
  }
  const ForwardBackward lk = TrackForwardBackward(previous_pyramid_, pyramid, previous, &current,
                                                  options_.klt_pyramid_levels, options_);
  std::vector<TrackState> kept;
  std::vector<Eigen::Vector3d> f_prev, f_curr;
  for (size_t i = 0; i < tracks_.size(); ++i) {
    std::optional<Eigen::Vector2d> xy;
    if (lk.forward_ok[i] && Inside(current[i], size, options_.detector.border_px / 2))
      xy = Normalized(model0_, current[i]);
    if (!xy) {
      ++out->statistics.lost;
      out->ended_track_lengths.push_back(tracks_[i].length);
      continue;
    }
    if (!(lk.return_error_px[i] <= options_.forward_backward_px)) {
      ++out->statistics.rejected_forward_backward;
      out->ended_track_lengths.push_back(tracks_[i].length);
      continue;
    }
    f_prev.push_back(Bearing(tracks_[i].xy).normalized());
    f_curr.push_back(Bearing(*xy).normalized());
    TrackState t = tracks_[i];
    t.px = current[i];
    t.xy = *xy;
    ++t.length;
    kept.push_back(t);
  }
  const std::vector<bool> inlier = RejectOutliers(f_prev, f_curr, gyro, R_Ccurr_Cprev);
  tracks_.clear();
  for (size_t i = 0; i < kept.size(); ++i) {
    if (inlier[i]) {
      tracks_.push_back(kept[i]);
    } else {
      ++out->statistics.rejected_ransac;
      out->ended_track_lengths.push_back(kept[i].length);
    }
  }
  out->statistics.tracked = static_cast<int>(tracks_.size());
}

std::vector<bool> FeatureTracker::RejectOutliers(const std::vector<Eigen::Vector3d>& f_prev,
                                                 const std::vector<Eigen::Vector3d>& f_curr,
                                                 bool gyro, const Eigen::Matrix3d& R_Ccurr_Cprev) {
  std::vector<bool> keep(f_prev.size(), true);
  if (options_.rejection == FrameOutlierRejection::kNone) return keep;
  EpipolarRansacOptions ransac;
  ransac.threshold_rad = ThresholdFromPixels(options_.ransac_threshold_px, model0_.fu());
  ransac.confidence = options_.ransac_confidence;
  ransac.max_iterations = options_.ransac_max_iterations;
  ransac.seed = options_.seed + frame_index_;
  // Without the gyro's rotation the 2-point RANSAC has nothing to stand on: the 5-point then.
  const bool two_point = gyro && options_.rejection == FrameOutlierRejection::kTwoPoint;
  const EpipolarRansacResult result = two_point
                                          ? TwoPointRansac(f_prev, f_curr, R_Ccurr_Cprev, ransac)
                                          : FivePointRansac(f_prev, f_curr, ransac);
  // Too few matches or a degenerate set cannot be tested: the tracks are kept.
  if (result.status == EpipolarRansacStatus::kOk ||
      result.status == EpipolarRansacStatus::kPureRotation)
    keep = result.inlier;
  return keep;
}

void FeatureTracker::AddNewTracks(const cv::Mat& gray0, FeatureFrameOutput* out) {
  std::vector<cv::Point2f> existing;
  for (const TrackState& t : tracks_) existing.push_back(t.px);
  for (const cv::Point2f& p : DetectInGrid(gray0, existing, options_.detector)) {
    const std::optional<Eigen::Vector2d> xy = Normalized(model0_, p);
    if (!xy) continue;
    tracks_.push_back({next_id_++, p, *xy, 1});
    ++out->statistics.new_tracks;
  }
}

void FeatureTracker::MatchIntoCam1(const std::vector<cv::Mat>& pyramid0, const cv::Mat& gray1,
                                   FeatureFrameOutput* out) {
  out->statistics.cam1_used = true;
  if (tracks_.empty()) return;
  const cv::Size window(options_.klt_window_px, options_.klt_window_px);
  std::vector<cv::Mat> pyramid1;
  cv::buildOpticalFlowPyramid(gray1, pyramid1, window, options_.stereo_pyramid_levels);
  const Eigen::Matrix3d R_C1_C0 = T_C1_C0_.q.toRotationMatrix();
  const Eigen::Vector3d t_C1_C0 = T_C1_C0_.p;
  std::vector<cv::Point2f> in0, in1;
  for (const TrackState& t : tracks_) {
    in0.push_back(t.px);
    const std::optional<cv::Point2f> predicted = RotatedPixel(*model1_, R_C1_C0, t.xy);
    in1.push_back(predicted && Inside(*predicted, gray1.size(), 0) ? *predicted : t.px);
  }
  const ForwardBackward lk =
      TrackForwardBackward(pyramid0, pyramid1, in0, &in1, options_.stereo_pyramid_levels, options_);
  // x1^T E x0 = 0 with E = [t]x R (normalized homogeneous coordinates).
  const Eigen::Matrix3d E = Skew(t_C1_C0) * R_C1_C0;
  for (size_t i = 0; i < tracks_.size(); ++i) {
    std::optional<Eigen::Vector2d> xy1;
    if (lk.forward_ok[i] && lk.return_error_px[i] <= options_.forward_backward_px &&
        Inside(in1[i], gray1.size(), options_.detector.border_px / 2))
      xy1 = Normalized(*model1_, in1[i]);
    if (!xy1) {
      ++out->statistics.stereo_rejected;
      continue;
    }
    const Eigen::Vector3d x0 = Bearing(tracks_[i].xy), x1 = Bearing(*xy1);
    const Eigen::Vector3d line = E * x0;
    const double distance = std::abs(x1.dot(line)) / std::max(line.head<2>().norm(), 1e-12);
    if (distance * model1_->fu() > options_.stereo_epipolar_px) {
      ++out->statistics.stereo_rejected_epipolar;
      continue;
    }
    // Depth along x0 in C0 from the two rays: x1 ~ R x0 d + t, least squares over d.
    const Eigen::Vector3d a = x1.cross(R_C1_C0 * x0), b = -x1.cross(t_C1_C0);
    const double depth_m = a.squaredNorm() > 1e-18 ? a.dot(b) / a.squaredNorm() : -1.0;
    if (!(depth_m > options_.stereo_min_depth_m)) {
      ++out->statistics.stereo_rejected;
      continue;
    }
    out->cam1.push_back({out->statistics.t_ns, tracks_[i].id, *xy1, 1});
    ++out->statistics.stereo_matched;
  }
}

}  // namespace mavloc
