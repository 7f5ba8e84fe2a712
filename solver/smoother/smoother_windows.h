// The smoother solved in overlapping windows of keyframes, for logs too long for one batch solve in
// memory (DESIGN.md "Estimators"). Each window is a SolveSmoother problem over its keyframes and
// the measurements between them; its first keyframe carries the marginal prior the previous window
// left (solver/smoother/smoother_marginalization.h: the keyframes before it and their residuals
// eliminated at that window's solution), as a fixed-lag smoother does (GTSAM's
// BatchFixedLagSmoother; Basalt's square-root marginalization). Window i covers keyframes
// [a_i, b_i]; the next starts at a_{i+1}, the first keyframe within overlap_s of b_i's time, so
// keyframes [a_i, a_{i+1}) are taken from window i with at least overlap_s of later measurements
// behind them, and the overlap is solved again by window i+1 (from window i's solution).
//
// What a window cannot hand on is refused: estimated landmarks, a laser plane, calibration blocks
// (extrinsics, time offset, board tilt) are shared by all keyframes and would need a prior of
// their own. The result's pose covariances are each window's (a keyframe's covariance without the
// measurements beyond its window: slightly larger than the batch's).
#pragma once

#include <vector>

#include "core/dataset.h"
#include "solver/smoother/smoother_problem.h"

namespace mavloc {

struct SmootherWindowOptions {
  double window_s = 60.0;  // length of a window (keyframe times)
  double overlap_s = 5.0;  // the later measurements every kept keyframe has behind it
};

// Empty when a smoother over `dataset` with `options` can be solved in windows, else why not.
std::string WindowsUnsupportedReason(const Dataset& dataset, const SmootherProblemOptions& options);

// The measurements of `dataset` a smoother over keyframes in [t0_ns, t1_ns] uses: IMU samples from
// the last one at or before t0 to the first at or after t1, visual measurements within 1 ms of the
// interval; sensors, map and scenario information as they are; no ground truth.
Dataset SliceForWindow(const Dataset& dataset, TimeNs t0_ns, TimeNs t1_ns);

// Solves `initial` (time order) in windows. Fails (usable = false, message naming the window) when
// a window fails or cannot hand on its prior.
SmootherResult SolveSmootherInWindows(const Dataset& dataset,
                                      const std::vector<SmootherKeyframe>& initial,
                                      const SmootherProblemOptions& options,
                                      const SmootherWindowOptions& windows);

}  // namespace mavloc
