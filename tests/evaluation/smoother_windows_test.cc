// The smoother in windows (solver/smoother/smoother_windows.h; the marginal prior itself:
// tests/solver/smoother_marginalization_test.cc):
// - on a noisy figure-eight the windowed solution equals the batch's far inside the Cramér–Rao
//   bound, keyframe for keyframe, and the last window's keyframes (which have every later
//   measurement behind them, as in the batch) equal it closer still;
// - noiseless data give the truth through every window;
// - what a keyframe prior cannot carry is refused; the memory budget picks the windows.
#include <gtest/gtest.h>

#include <cmath>

#include "core/errors.h"
#include "solver/estimator.h"
#include "solver/estimators/smoother_estimator.h"
#include "solver/smoother/smoother_windows.h"
#include "tests/scenario_support.h"

namespace mavloc {
namespace {

// The estimator's keyframe states, as the batch or the windows gave them.
struct Solution {
  Estimate estimate;
  SmootherResult result;
};

Solution Solve(const Dataset& dataset, std::map<std::string, std::string> options) {
  SmootherEstimator smoother{EstimatorOptions(std::move(options))};
  Solution s;
  s.estimate = smoother.Run(dataset);
  s.result = smoother.last_result();
  return s;
}

TEST(SmootherWindows, EqualTheBatchFarInsideTheBoundOnANoisyFigureEight) {
  const Dataset dataset = testing::Simulate("mav-figure-eight", 1, 40.0);
  const Solution batch = Solve(dataset, {});
  const Solution windowed = Solve(dataset, {{"window_s", "12"}, {"window_overlap_s", "3"}});
  ASSERT_TRUE(batch.result.usable) << batch.result.message;
  ASSERT_TRUE(windowed.result.usable) << windowed.result.message;
  EXPECT_EQ(batch.result.statistics.windows, 1);
  EXPECT_EQ(windowed.result.statistics.windows, 4);  // 0-12, 9-21, 18-30, 27-40.5 s
  ASSERT_EQ(windowed.result.keyframes.size(), batch.result.keyframes.size());
  EXPECT_EQ(windowed.result.dropped, batch.result.dropped);
  EXPECT_EQ(windowed.estimate.events.size(), 1u);
  const TimeNs last_window_start_ns = batch.result.keyframes.front().t_ns + SecondsToNs(27.0);
  double sum_sq_diff = 0.0, sum_sq_error = 0.0, max_diff_last = 0.0;
  for (size_t k = 0; k < batch.result.keyframes.size(); ++k) {
    const SmootherKeyframe& b = batch.result.keyframes[k];
    const SmootherKeyframe& w = windowed.result.keyframes[k];
    ASSERT_EQ(b.t_ns, w.t_ns);
    const double diff = (b.state.p_W - w.state.p_W).norm();
    sum_sq_diff += diff * diff;
    const GroundTruthState truth = InterpolatedTruth(dataset.ground_truth, b.t_ns);
    sum_sq_error += (b.state.p_W - truth.T_W_B.p).squaredNorm();
    if (b.t_ns > last_window_start_ns) max_diff_last = std::max(max_diff_last, diff);
  }
  const double n = static_cast<double>(batch.result.keyframes.size());
  const double rms_diff = std::sqrt(sum_sq_diff / n), rms_error = std::sqrt(sum_sq_error / n);
  std::printf("batch: %d solves, %d iterations; windows: %d solves, %d iterations\n",
              batch.result.statistics.solves, batch.result.statistics.iterations,
              windowed.result.statistics.solves, windowed.result.statistics.iterations);
  std::printf(
      "batch position RMSE %.4f mm; windowed - batch RMS %.4f mm, last window max %.2e mm\n",
      1e3 * rms_error, 1e3 * rms_diff, 1e3 * max_diff_last);
  // The batch's error is at the bound (about 0.5-1 mm per axis); the windows leave out only
  // measurements more than 3 s later.
  EXPECT_LT(rms_diff, 0.1 * rms_error);
  EXPECT_LT(max_diff_last, 0.01 * rms_error);
}

TEST(SmootherWindows, NoiselessDataGiveTheTruthThroughEveryWindow) {
  const Dataset dataset = testing::Simulate(
      "mav-figure-eight", 2, 20.0, {{"imu_noise", "0"}, {"bias", "0"}, {"pixel_noise_px", "0"}});
  const Solution windowed = Solve(dataset, {{"window_s", "6"}, {"window_overlap_s", "2"}});
  ASSERT_TRUE(windowed.result.usable) << windowed.result.message;
  EXPECT_GE(windowed.result.statistics.windows, 4);
  double max_error_m = 0.0;
  for (const SmootherKeyframe& kf : windowed.result.keyframes)
    max_error_m =
        std::max(max_error_m,
                 (kf.state.p_W - InterpolatedTruth(dataset.ground_truth, kf.t_ns).T_W_B.p).norm());
  EXPECT_LT(max_error_m, 1e-6);
}

TEST(SmootherWindows, RefuseWhatAKeyframePriorCannotCarry) {
  Dataset data;
  data.features.push_back({});
  data.laser.push_back({});
  SmootherProblemOptions options;
  EXPECT_EQ(WindowsUnsupportedReason(data, options), "");
  options.landmarks = LandmarkMode::kUnknown;
  EXPECT_NE(WindowsUnsupportedReason(data, options).find("landmarks"), std::string::npos);
  // The landmark mode does not matter without features (tags only).
  EXPECT_EQ(WindowsUnsupportedReason(Dataset{}, options), "");
  options = SmootherProblemOptions{};
  options.estimate_extrinsics = true;
  EXPECT_NE(WindowsUnsupportedReason(data, options).find("calibration"), std::string::npos);
  options = SmootherProblemOptions{};
  options.fit_imu_noise = true;
  EXPECT_NE(WindowsUnsupportedReason(data, options).find("fit_imu_noise"), std::string::npos);
  options = SmootherProblemOptions{};
  options.laser_beam = LaserBeam{};
  EXPECT_NE(WindowsUnsupportedReason(data, options).find("plane"), std::string::npos);

  // Asked for explicitly on a problem with estimated landmarks: an input error naming window_s.
  const Dataset three_point = testing::Simulate("three-point-hover", 1, 20.0);
  try {
    Solve(three_point, {{"window_s", "2"}, {"window_overlap_s", "0.5"}});
    ADD_FAILURE() << "window_s on estimated landmarks was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("window_s"), std::string::npos) << e.what();
  }
}

TEST(SmootherWindows, TheMemoryBudgetChoosesWindowsAndSaysSo) {
  const Dataset dataset = testing::Simulate("mav-figure-eight", 3, 70.0);
  const Solution batch = Solve(dataset, {});
  EXPECT_EQ(batch.result.statistics.windows, 1);
  EXPECT_TRUE(batch.estimate.events.empty());
  // 70 s of figure-eight is about 120 MiB as one batch: a budget of 40 MiB windows it.
  const Solution budgeted = Solve(dataset, {{"memory_budget_mib", "40"}});
  ASSERT_TRUE(budgeted.result.usable) << budgeted.result.message;
  EXPECT_GE(budgeted.result.statistics.windows, 2);
  ASSERT_EQ(budgeted.estimate.events.size(), 1u);
  EXPECT_NE(budgeted.estimate.events[0].find("memory_budget_mib=40"), std::string::npos)
      << budgeted.estimate.events[0];
}

}  // namespace
}  // namespace mavloc
