#include "solver/smoother/smoother_windows.h"

#include <fmt/format.h>

#include <algorithm>

namespace mavloc {

namespace {

constexpr TimeNs kVisualToleranceNs = 1'000'000;  // the smoother attaches within 1 ms

// The observations within the tolerance of [t0, t1] of a time-ordered stream (the readers and
// the simulators give them in time order): two binary searches, not a pass over the whole log
// per window.
template <typename Observation>
std::vector<Observation> Within(const std::vector<Observation>& all, TimeNs t0_ns, TimeNs t1_ns) {
  const auto first = std::partition_point(all.begin(), all.end(), [&](const Observation& o) {
    return o.t_ns < t0_ns - kVisualToleranceNs;
  });
  const auto last = std::partition_point(
      first, all.end(), [&](const Observation& o) { return o.t_ns <= t1_ns + kVisualToleranceNs; });
  return std::vector<Observation>(first, last);
}

// The last keyframe index b >= a with t_b - t_a <= window; the first index c > a with
// t_c >= t_b - overlap (a + 1 at least: every window moves on).
int WindowEnd(const std::vector<SmootherKeyframe>& kf, int a, TimeNs window_ns) {
  int b = a;
  while (b + 1 < static_cast<int>(kf.size()) && kf[b + 1].t_ns - kf[a].t_ns <= window_ns) ++b;
  return b;
}

int NextWindowStart(const std::vector<SmootherKeyframe>& kf, int a, int b, TimeNs overlap_ns) {
  int c = b;
  while (c - 1 > a && kf[c - 1].t_ns >= kf[b].t_ns - overlap_ns) --c;
  return c;
}

}  // namespace

std::string WindowsUnsupportedReason(const Dataset& dataset,
                                     const SmootherProblemOptions& options) {
  if (options.landmarks != LandmarkMode::kKnown && !dataset.features.empty())
    return "the landmarks are estimated";
  if (options.laser_beam && !dataset.laser.empty())
    return "the laser plane is shared by every keyframe";
  if (options.estimate_extrinsics || options.estimate_time_offset || options.initial_q_W_M)
    return "calibration blocks are estimated";
  if (options.fit_imu_noise) return "fit_imu_noise needs every IMU residual in one problem";
  return "";
}

Dataset SliceForWindow(const Dataset& dataset, TimeNs t0_ns, TimeNs t1_ns) {
  Dataset slice;
  slice.name = dataset.name;
  slice.root = dataset.root;
  slice.scenario = dataset.scenario;
  slice.cameras = dataset.cameras;
  slice.map = dataset.map;
  slice.scenario_info = dataset.scenario_info;
  const auto& samples = dataset.imu.samples;
  auto first = std::upper_bound(samples.begin(), samples.end(), t0_ns,
                                [](TimeNs t, const ImuSample& s) { return t < s.t_ns; });
  if (first != samples.begin()) --first;
  auto last = std::lower_bound(samples.begin(), samples.end(), t1_ns,
                               [](const ImuSample& s, TimeNs t) { return s.t_ns < t; });
  if (last != samples.end()) ++last;
  slice.imu = dataset.imu;
  slice.imu.samples.assign(first, last);
  for (CameraSensor& camera : slice.cameras) camera.frames = Within(camera.frames, t0_ns, t1_ns);
  slice.features = Within(dataset.features, t0_ns, t1_ns);
  slice.features1 = Within(dataset.features1, t0_ns, t1_ns);
  slice.laser = Within(dataset.laser, t0_ns, t1_ns);
  slice.tags = Within(dataset.tags, t0_ns, t1_ns);
  slice.tags1 = Within(dataset.tags1, t0_ns, t1_ns);
  return slice;
}

SmootherResult SolveSmootherInWindows(const Dataset& dataset,
                                      const std::vector<SmootherKeyframe>& initial,
                                      const SmootherProblemOptions& options,
                                      const SmootherWindowOptions& windows) {
  SmootherResult result;
  const int n = static_cast<int>(initial.size());
  result.statistics.num_keyframes = n;
  result.statistics.windows = 0;
  if (const std::string why = WindowsUnsupportedReason(dataset, options); !why.empty()) {
    result.message = "cannot solve in windows: " + why;
    return result;
  }
  const TimeNs window_ns = SecondsToNs(windows.window_s);
  const TimeNs overlap_ns = SecondsToNs(windows.overlap_s);
  if (!(windows.overlap_s > 0.0) || !(windows.window_s > 2.0 * windows.overlap_s)) {
    result.message = "windows must be longer than twice their overlap, and the overlap positive";
    return result;
  }
  std::vector<SmootherKeyframe> seeds = initial;
  std::optional<KeyframeMarginalPrior> prior;
  for (int a = 0; a < n;) {
    int b = WindowEnd(seeds, a, window_ns);
    // A remainder shorter than a window's overlap goes into this window.
    if (b + 1 < n && seeds[n - 1].t_ns - seeds[b].t_ns <= overlap_ns) b = n - 1;
    const bool last = b == n - 1;
    const int next = last ? n : NextWindowStart(seeds, a, b, overlap_ns);
    SmootherProblemOptions o = options;
    o.first_keyframe_prior = prior;
    o.marginalize_before_keyframe = last ? 0 : next - a;
    o.count_dropped_before_ns = last ? options.count_dropped_before_ns : seeds[next].t_ns;
    const std::vector<SmootherKeyframe> window(seeds.begin() + a, seeds.begin() + b + 1);
    SmootherResult w = SolveSmoother(SliceForWindow(dataset, seeds[a].t_ns, seeds[b].t_ns), window,
                                     {}, std::nullopt, o);
    const std::string where =
        fmt::format("window {} ({:.3f}-{:.3f} s)", result.statistics.windows + 1,
                    NsToSeconds(seeds[a].t_ns), NsToSeconds(seeds[b].t_ns));
    AddStatistics(w.statistics, &result.statistics);
    if (!w.statistics.converged) {
      result.statistics.converged = false;
      result.statistics.last_relative_cost_change = std::max(
          result.statistics.last_relative_cost_change, w.statistics.last_relative_cost_change);
    }
    result.statistics.windows += 1;
    result.statistics.num_imu_factors += w.statistics.num_imu_factors;
    result.statistics.num_visual_residuals += w.statistics.num_visual_residuals;
    result.statistics.num_parameters += w.statistics.num_parameters;
    result.statistics.final_cost += w.statistics.final_cost;
    result.statistics.initial_cost += w.statistics.initial_cost;
    result.statistics.linear_solver = w.statistics.linear_solver;
    for (const auto& [reason, count] : w.dropped) result.dropped[reason] += count;
    if (!w.usable || (!last && !w.marginal_prior)) {
      result.message = where + ": " + (w.usable ? w.marginalization_failure : w.message);
      return result;
    }
    const int keep = last ? b + 1 - a : next - a;
    for (int k = 0; k < keep; ++k) {
      result.keyframes.push_back(w.keyframes[k]);
      if (options.compute_covariance)
        result.pose_covariances.push_back(
            k < static_cast<int>(w.pose_covariances.size()) ? w.pose_covariances[k] : std::nullopt);
    }
    // The overlap starts the next window from this one's solution, and the keyframes after it
    // from its last biases (the seeds' poses carry none): their preintegration is then linearized
    // near the solution and the relinearization round is rarely needed.
    for (int k = keep; k <= b - a; ++k) seeds[a + k] = w.keyframes[k];
    for (int k = b + 1; k < n; ++k) seeds[k].state.biases = w.keyframes.back().state.biases;
    result.message = w.message;
    prior = w.marginal_prior;
    a = last ? n : next;
  }
  result.usable = true;
  return result;
}

}  // namespace mavloc
