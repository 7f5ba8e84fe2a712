// SmootherEstimator on feature tracks (features0/features1 of unknown landmarks, written by
// frontends/features/): keyframes by parallax (track_keyframes.h), the first keyframe's state from
// the ground truth or a static start, then a growing window: keyframes predicted by the IMU from
// the last solved one, new tracks triangulated from the solved poses (track_triangulation.h), the
// window solved (inverse-depth landmarks anchored in their first keyframe, track_landmarks.h;
// keyframes older than track_window_s held constant), until every keyframe is in and the last
// solve is the whole batch; then the tracks whose reprojection error stays high are removed and
// the batch solved once more.
#include <fmt/format.h>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <set>

#include "core/rotation.h"
#include "solver/estimators/smoother_common.h"
#include "solver/estimators/smoother_estimator.h"
#include "solver/imu/imu_integrator.h"
#include "solver/smoother/smoother_windows.h"
#include "solver/smoother/track_keyframes.h"
#include "solver/smoother/track_triangulation.h"

namespace mavloc {

namespace {

constexpr double kStaticWindowS = 0.5;  // accelerometer mean for a start without ground truth
constexpr double kDefaultTrackStepS = 2.0;
// The sliding window of the growing solves: keyframes more than track_window_s before the newest
// are held constant, and of those only the last kContextS seconds (longer than most tracks live)
// stay in the problem. The last solve is the whole batch.
constexpr double kDefaultTrackWindowS = 10.0;
constexpr double kContextS = 3.0;
// Ceres' relative tolerances on the tracks: the solves otherwise creep on for dozens of
// iterations at relative cost changes of 1e-7, moving the poses by micrometres.
constexpr double kTrackFunctionTolerance = 1e-8;
constexpr double kSlidingTolerance = 1e-6;
constexpr double kDefaultTrackOutlierPx = 3.0;
// A frame whose tracks moved less than this since the previous frame shows the vehicle at rest:
// 0.3 px at EuRoC's 458 px focal length is 0.65 mrad, 2 mm at 3 m in 50 ms (4 cm/s).
constexpr double kStationaryPx = 0.3;

// The first keyframe's state: the ground truth's (interpolated) pose and velocity where the truth
// covers t0_ns; otherwise at rest at the origin with yaw 0, roll and pitch from the accelerometer's
// mean over kStaticWindowS. Biases start at zero (their prior is the smoother's).
ImuKeyframeState StartState(const Dataset& dataset, TimeNs t0_ns, std::string* how) {
  ImuKeyframeState s;
  const auto& truth = dataset.ground_truth;
  if (!truth.empty() && truth.front().t_ns <= t0_ns && t0_ns <= truth.back().t_ns) {
    const GroundTruthState gt = InterpolatedTruth(truth, t0_ns);
    s.q_W_B = gt.T_W_B.q;
    s.p_W = gt.T_W_B.p;
    s.v_W = gt.v_W;
    *how = "the first keyframe starts at the ground truth's pose and velocity";
    return s;
  }
  Eigen::Vector3d f_B = Eigen::Vector3d::Zero();
  int count = 0;
  for (const ImuSample& sample : dataset.imu.samples) {
    if (sample.t_ns < t0_ns) continue;
    if (NsToSeconds(sample.t_ns - t0_ns) > kStaticWindowS) break;
    f_B += sample.accel_m_s2;
    ++count;
  }
  if (count > 0 && f_B.norm() > 0.0) {
    // At rest the specific force is -g: R_W_B f_B points up.
    s.q_W_B = Eigen::Quaterniond::FromTwoVectors(f_B.normalized(), Eigen::Vector3d::UnitZ());
    const EulerRpy rpy = EulerFromQuaternion(s.q_W_B);
    s.q_W_B = QuaternionFromEuler({rpy.roll, rpy.pitch, 0.0});
  }
  *how = fmt::format(
      "no ground truth at the first keyframe: it starts at rest at the origin with yaw 0, roll and "
      "pitch from the accelerometer's mean over {:g} s",
      kStaticWindowS);
  return s;
}

SmootherKeyframe Predicted(const ImuIntegrator& integrator, const SmootherKeyframe& from,
                           TimeNs t_ns) {
  NavState state;
  state.t_ns = from.t_ns;
  state.q_W_B = from.state.q_W_B;
  state.p_W = from.state.p_W;
  state.v_W = from.state.v_W;
  const NavState next = integrator.Integrate(state, t_ns, from.state.biases);
  SmootherKeyframe kf;
  kf.t_ns = t_ns;
  kf.state.q_W_B = next.q_W_B;
  kf.state.p_W = next.p_W;
  kf.state.v_W = next.v_W;
  kf.state.biases = from.state.biases;
  return kf;
}

// Per track, the RMS angular error of its observations at the solution; tracks above max_rad are
// returned.
std::set<int> OutlierTracks(const Dataset& tracked, const SmootherResult& result, double max_rad) {
  std::vector<TimeNs> times;
  for (const auto& kf : result.keyframes) times.push_back(kf.t_ns);
  std::map<int, std::pair<double, int>> sum;  // id -> (sum of squared errors, count)
  for (const std::vector<FeatureObservation>* stream : {&tracked.features, &tracked.features1}) {
    for (const FeatureObservation& obs : *stream) {
      auto p = result.landmarks_W.find(obs.landmark_id);
      auto it = std::lower_bound(times.begin(), times.end(), obs.t_ns);
      if (p == result.landmarks_W.end() || it == times.end() || *it != obs.t_ns) continue;
      const ImuKeyframeState& s = result.keyframes[it - times.begin()].state;
      const Pose T_C_W = (Pose(s.q_W_B, s.p_W) * tracked.cameras[obs.camera].T_B_C).Inverse();
      const Eigen::Vector3d p_C = T_C_W * p->second;
      const Eigen::Vector3d b = Eigen::Vector3d(obs.xy.x(), obs.xy.y(), 1.0).normalized();
      const double error = std::acos(std::clamp(p_C.normalized().dot(b), -1.0, 1.0));
      auto& [sq, n] = sum[obs.landmark_id];
      sq += error * error;
      ++n;
    }
  }
  std::set<int> outliers;
  for (const auto& [id, acc] : sum)
    if (std::sqrt(acc.first / acc.second) > max_rad) outliers.insert(id);
  return outliers;
}

void RemoveTracks(const std::set<int>& ids, std::vector<FeatureObservation>* features) {
  features->erase(
      std::remove_if(features->begin(), features->end(),
                     [&](const FeatureObservation& f) { return ids.count(f.landmark_id) > 0; }),
      features->end());
}

// The keyframes' poses, velocities and biases (and pose covariances in roll, pitch, yaw).
void AppendKeyframeStates(const SmootherResult& result, Estimate* estimate) {
  for (size_t k = 0; k < result.keyframes.size(); ++k) {
    const SmootherKeyframe& kf = result.keyframes[k];
    const Pose T_W_B(kf.state.q_W_B, kf.state.p_W);
    std::vector<double> values = PoseQuantityValues(T_W_B, kf.state.v_W);
    const ImuBiases& b = kf.state.biases;
    values.insert(values.end(), {b.b_g.x(), b.b_g.y(), b.b_g.z(), b.b_a.x(), b.b_a.y(), b.b_a.z()});
    estimate->quantities.Append(kf.t_ns, values);
    estimate->poses.push_back({kf.t_ns, T_W_B});
    if (k < result.pose_covariances.size() && result.pose_covariances[k]) {
      Eigen::Matrix<double, 6, 6> J = Eigen::Matrix<double, 6, 6>::Identity();
      J.bottomRightCorner<3, 3>() = EulerJacobian(kf.state.q_W_B);
      estimate->covariances.push_back({kf.t_ns, J * *result.pose_covariances[k] * J.transpose()});
    }
  }
}

// The keyframes [begin, end) of `all` and the measurements between them; of the features, only the
// tracks that some keyframe at or after `free_begin` observes (the others touch constant poses
// alone).
Dataset SlidingWindowSlice(const Dataset& tracked, const std::vector<SmootherKeyframe>& all,
                           size_t begin, size_t free_begin) {
  Dataset slice = SliceForWindow(tracked, all[begin].t_ns, all.back().t_ns);
  std::set<int> seen_free;
  const TimeNs t_free = all[free_begin].t_ns;
  for (const auto* stream : {&slice.features, &slice.features1})
    for (const FeatureObservation& obs : *stream)
      if (obs.t_ns >= t_free) seen_free.insert(obs.landmark_id);
  for (auto* stream : {&slice.features, &slice.features1})
    std::erase_if(*stream,
                  [&](const FeatureObservation& obs) { return !seen_free.count(obs.landmark_id); });
  return slice;
}

}  // namespace

bool HasFeatureTracks(const Dataset& dataset) {
  return !dataset.features.empty() && dataset.map.landmarks_W.empty() &&
         dataset.map.parameters.count("D") == 0;
}

SmootherResult SmootherEstimator::SolveTracksGrowing(
    Dataset* tracked_io, const std::vector<TimeNs>& times, const ImuKeyframeState& start,
    const SmootherProblemOptions& options, std::string* timing, std::set<int>* removed) const {
  Dataset& tracked = *tracked_io;
  const double outlier_rad = options_.GetDouble("track_outlier_px", kDefaultTrackOutlierPx) /
                             tracked.cameras.front().model.fu();
  const auto seconds_since = [](std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
  };
  double sliding_s = 0.0;
  int sliding_solves = 0;
  const TimeNs step_ns = SecondsToNs(options_.GetDouble("track_step_s", kDefaultTrackStepS));
  const double window_s = options_.GetDouble("track_window_s", kDefaultTrackWindowS);
  const TimeNs window_ns = window_s > 0.0 ? SecondsToNs(window_s) : 0;
  const ImuIntegrator integrator(&tracked.imu.samples);
  std::vector<SmootherKeyframe> current = {{times.front(), start}};
  std::map<int, Eigen::Vector3d> landmarks;  // triangulated ones, then their solved positions
  std::set<int> triangulated;
  SmootherStatistics earlier;
  size_t next = 1;
  TimeNs window_end = times.front() + step_ns;
  while (true) {
    for (; next < times.size() && times[next] <= window_end; ++next)
      current.push_back(Predicted(integrator, current.back(), times[next]));
    for (const auto& [id, p] : TriangulateTracks(tracked, current, triangulated, {})) {
      landmarks[id] = p;
      triangulated.insert(id);
    }
    const bool last = next >= times.size();
    // Sliding: keyframes older than window_ns before the newest are held constant, and only
    // kContextS of them (the poses the window's tracks were seen from before) stay in the problem.
    size_t free_begin = 0;
    if (window_ns > 0 && !last)
      while (current[free_begin].t_ns < current.back().t_ns - window_ns) ++free_begin;
    size_t begin = free_begin;
    while (begin > 0 &&
           current[begin - 1].t_ns >= current[free_begin].t_ns - SecondsToNs(kContextS))
      --begin;
    if (begin == free_begin && free_begin > 0) --begin;  // at least the IMU link into the window
    SmootherProblemOptions stage = options;
    if (!last) {
      // A sliding solve only starts the next one and, at the end, the batch (which relinearizes
      // and converges to 1e-8): looser tolerances and no relinearization round here.
      stage.compute_covariance = false;
      stage.function_tolerance = stage.parameter_tolerance = kSlidingTolerance;
      stage.relinearize_rounds = 0;
    }
    stage.constant_keyframes = static_cast<int>(free_begin - begin);
    const Dataset slice =
        free_begin > 0 ? SlidingWindowSlice(tracked, current, begin, free_begin) : Dataset{};
    const std::vector<SmootherKeyframe> problem_keyframes(current.begin() + begin, current.end());
    const auto t_solve = std::chrono::steady_clock::now();
    SmootherResult result = SolveSmoother(free_begin > 0 ? slice : tracked, problem_keyframes,
                                          landmarks, std::nullopt, stage);
    if (last) {
      *timing = fmt::format(
          "sliding window: {} solves in {:.1f} s; batch over {} keyframes and {} tracks: {:.1f} s "
          "({} iterations)",
          sliding_solves, sliding_s, problem_keyframes.size(), result.landmarks_W.size(),
          seconds_since(t_solve), result.statistics.iterations);
    } else {
      sliding_s += seconds_since(t_solve);
      ++sliding_solves;
    }
    if (!result.usable || result.keyframes.size() != problem_keyframes.size() || last) {
      AddStatistics(earlier, &result.statistics);
      if (!last && result.usable) {
        result.usable = false;
        result.message = fmt::format("the growing window stopped at {} of {} keyframes",
                                     current.size(), times.size());
      }
      return result;
    }
    AddStatistics(result.statistics, &earlier);
    std::copy(result.keyframes.begin(), result.keyframes.end(), current.begin() + begin);
    for (const auto& [id, p] : result.landmarks_W) landmarks[id] = p;
    // Tracks whose reprojection error is high already here (a wrong match the loss only
    // down-weights) leave before the batch, which then needs no second solve for them.
    const std::set<int> outliers =
        OutlierTracks(free_begin > 0 ? slice : tracked, result, outlier_rad);
    for (const int id : outliers) {
      landmarks.erase(id);
      triangulated.insert(id);  // not triangulated again
      removed->insert(id);
    }
    if (!outliers.empty()) {
      RemoveTracks(outliers, &tracked.features);
      RemoveTracks(outliers, &tracked.features1);
    }
    window_end += step_ns;
  }
}

namespace {

// The keyframe times of the tracks inside the IMU stream. With a ground truth the first keyframe
// starts at its state (the gauge of the comparison, as imu-dead-reckoning starts): frames before
// the truth's first row are left out, and *left_out says so.
std::vector<TimeNs> TrackKeyframeTimes(const Dataset& dataset, const TrackKeyframeOptions& options,
                                       std::string* left_out) {
  if (dataset.imu.samples.empty()) return {};
  TimeNs t_min = dataset.imu.samples.front().t_ns;
  const TimeNs t_max = dataset.imu.samples.back().t_ns;
  const auto& truth = dataset.ground_truth;
  if (!truth.empty() && truth.front().t_ns > t_min && truth.front().t_ns < t_max &&
      truth.front().t_ns > dataset.features.front().t_ns) {
    t_min = truth.front().t_ns;
    *left_out =
        fmt::format("the frames before the ground truth's first row ({:.3f} s) are left out; ",
                    NsToSeconds(t_min - dataset.features.front().t_ns));
  }
  return SelectTrackKeyframes(dataset.features, options, t_min, t_max);
}

// Tracks whose reprojection error stays high after the batch (a wrong match that the loss only
// down-weights) are removed from *tracked and the batch solved once more from *result; returns
// how many were removed. The second solve's time is appended to *timing.
size_t RemoveOutliersAndSolveAgain(const SmootherProblemOptions& options, double outlier_rad,
                                   Dataset* tracked, SmootherResult* result, std::string* timing) {
  const auto t_start = std::chrono::steady_clock::now();
  const std::set<int> outliers = OutlierTracks(*tracked, *result, outlier_rad);
  if (outliers.empty()) return 0;
  RemoveTracks(outliers, &tracked->features);
  RemoveTracks(outliers, &tracked->features1);
  std::map<int, Eigen::Vector3d> kept = result->landmarks_W;
  for (int id : outliers) kept.erase(id);
  // From the batch's solution, relinearized there: no second round.
  SmootherProblemOptions again_options = options;
  again_options.relinearize_rounds = 0;
  SmootherResult again =
      SolveSmoother(*tracked, result->keyframes, kept, std::nullopt, again_options);
  if (again.usable) {
    AddStatistics(result->statistics, &again.statistics);
    *result = std::move(again);
  }
  *timing += fmt::format(
      "; the batch again without them: {:.1f} s",
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count());
  return outliers.size();
}

// A requested covariance that no keyframe got: the information matrix is rank deficient.
void NoteMissingCovariance(const SmootherResult& result, const SmootherProblemOptions& options,
                           Estimate* estimate) {
  if (!options.compute_covariance ||
      std::any_of(result.pose_covariances.begin(), result.pose_covariances.end(),
                  [](const auto& c) { return c.has_value(); }))
    return;
  estimate->events.push_back(fmt::format(
      "no covariance: the information matrix is rank deficient (smallest relative pivot {:.3g}){}",
      result.statistics.covariance_min_relative_pivot,
      options.hold_gauge ? "" : "; the gauge prior was removed (gauge_prior=0)"));
}

}  // namespace

SmootherProblemOptions SmootherEstimator::TrackProblemOptions(const Dataset& dataset) const {
  SmootherProblemOptions problem_options = ProblemOptionsFor(dataset);
  problem_options.landmarks = LandmarkMode::kTracks;
  problem_options.hold_gauge = options_.GetBool("gauge_prior", true);
  problem_options.function_tolerance = kTrackFunctionTolerance;
  problem_options.parameter_tolerance = kTrackFunctionTolerance;
  if (!options_.Has("bearing_sigma_deg"))
    problem_options.bearing_sigma_rad =
        problem_options.pixel_sigma_px / dataset.cameras.front().model.fu();
  return problem_options;
}

Estimate SmootherEstimator::RunFromTracks(const Dataset& dataset) {
  SmootherProblemOptions problem_options = TrackProblemOptions(dataset);
  const CameraSensor& cam0 = dataset.cameras.front();
  std::vector<std::string> names = PoseQuantityNames(true);
  names.insert(names.end(), {"bgx", "bgy", "bgz", "bax", "bay", "baz"});
  std::vector<std::string> units;
  for (const auto& name : names) units.push_back(StandardUnit(name));
  Estimate estimate;
  estimate.quantities = QuantityTable(names, units);

  TrackKeyframeOptions keyframe_options;
  keyframe_options.focal_px = cam0.model.fu();
  keyframe_options.min_parallax_px = options_.GetDouble("keyframe_parallax_px", 10.0);
  keyframe_options.max_interval_s = options_.GetDouble("keyframe_max_interval_s", 0.5);
  std::string left_out;
  const std::vector<TimeNs> times = TrackKeyframeTimes(dataset, keyframe_options, &left_out);
  if (times.size() < 2) {
    estimate.CountFailure("fewer than 2 keyframes with feature tracks inside the IMU stream");
    last_result_ = SmootherResult{};
    return estimate;
  }
  // Zero-velocity updates where the images stand still (kStationaryPx between consecutive frames).
  for (const TimeNs t : StationaryFrames(dataset.features, kStationaryPx, cam0.model.fu()))
    if (std::binary_search(times.begin(), times.end(), t))
      problem_options.zero_velocity_times.push_back(t);
  Dataset tracked = dataset;
  tracked.features = FeaturesAtTimes(dataset.features, times);
  tracked.features1 = FeaturesAtTimes(dataset.features1, times);
  std::string start_how;
  const ImuKeyframeState start = StartState(dataset, times.front(), &start_how);
  estimate.events.push_back(fmt::format(
      "feature tracks: {} keyframes of {} frames (parallax {:g} px, at most {:g} s apart), {} at "
      "rest (zero-velocity prior); {}{}; "
      "gauge: the first keyframe's position and yaw are held there by a prior (4 DoF, "
      "unobservable with unknown landmarks)",
      times.size(), cam0.frames.size(), keyframe_options.min_parallax_px,
      keyframe_options.max_interval_s, problem_options.zero_velocity_times.size(), left_out,
      start_how));

  std::string timing;
  std::set<int> removed_sliding;
  last_result_ =
      SolveTracksGrowing(&tracked, times, start, problem_options, &timing, &removed_sliding);
  const double outlier_px = options_.GetDouble("track_outlier_px", kDefaultTrackOutlierPx);
  if (last_result_.usable) {
    const size_t after_batch = RemoveOutliersAndSolveAgain(
        problem_options, outlier_px / cam0.model.fu(), &tracked, &last_result_, &timing);
    const size_t removed = removed_sliding.size() + after_batch;
    if (removed > 0)
      estimate.events.push_back(fmt::format(
          "removed {} of {} tracks whose reprojection error stayed above {:g} px after a solve ({} "
          "after a sliding-window solve, {} after the batch)",
          removed, last_result_.landmarks_W.size() + removed, outlier_px, removed_sliding.size(),
          after_batch));
  }
  if (!timing.empty()) estimate.events.push_back(timing);
  RefitImuNoise(dataset, problem_options, &last_result_, &estimate);
  const SmootherResult& result = last_result_;
  if (CountUnusableSolve(result, static_cast<int>(times.size()), &estimate)) return estimate;
  estimate.parameters["tracks"] = {static_cast<double>(result.landmarks_W.size()), std::nullopt,
                                   ""};
  if (problem_options.compute_covariance) estimate.covariance_names = PoseQuantityNames(false);
  NoteMissingCovariance(result, problem_options, &estimate);
  AppendKeyframeStates(result, &estimate);
  NoteUnconverged(result, problem_options.max_iterations, &estimate);
  return estimate;
}

}  // namespace mavloc
