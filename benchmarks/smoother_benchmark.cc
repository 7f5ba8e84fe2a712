// Solve time of the batch smoother on tag-arena-dynamic (IMU 100 Hz, cam0 10 Hz, 21 floor tags)
// for 10, 30, 100 and 300 s of flight, seeded by tag-pnp; at 30 and 100 s also with the IMU and
// map-point factors differentiated automatically (autodiff:1, the reference of their analytic
// Jacobians). The seed and the simulation are
// computed outside the timed loop; the timing covers keyframe initialization, preintegration,
// problem assembly and the Ceres solve. Counters: keyframes, ms per keyframe (should stay flat as
// the length grows: the problem is block-banded), real-time factor (flight time / solve time,
// target >= 50 on 2 cores), Ceres iterations and the time split. The Ceres summary of each length
// is printed once to stderr.
//
// Covariances (BM_SmootherCovarianceFigureEight): mav-figure-eight (IMU 200 Hz, cam0 20 Hz, known
// landmarks) for 60, 300 and 600 s, seeded by the built-in landmark PnP, solved with pose
// covariances by each SmootherCovarianceMethod (0: kStructured, the default; 1: kCeres, i.e.
// ceres::Covariance), and for 1800 s by kStructured only (one batch of 36,000 keyframes, 2.2 GiB
// peak; kCeres would take about half an hour). Counters: keyframes, solve_s (Ceres' solve, all
// relinearization rounds), cov_s (the covariance step), cov_per_solve (their ratio; target <= 1.2
// at 600 s for kStructured), ms of covariance per keyframe (flat when linear) and, for kStructured,
// the smallest relative pivot. kCeres at 600 s takes minutes: --benchmark_filter='Covariance.*/0'
// runs kStructured only.
#include <benchmark/benchmark.h>

#include <cstdio>
#include <map>
#include <memory>

#include "datasets/scenarios/scenario.h"
#include "solver/estimator.h"
#include "solver/estimators/smoother_estimator.h"
#include "solver/smoother/smoother_initialization.h"
#include "solver/smoother/smoother_problem.h"

namespace mavloc {
namespace {

struct Case {
  Dataset dataset;
  std::vector<StampedPose> seed;
};

const Case& GetCase(int duration_s) {
  static std::map<int, std::unique_ptr<Case>> cache;
  auto& entry = cache[duration_s];
  if (!entry) {
    entry = std::make_unique<Case>();
    ScenarioOptions options;
    options.seed = 1;
    options.duration_s = duration_s;
    entry->dataset = FindScenario("tag-arena-dynamic")->generate(options);
    const EstimatorEntry* seed = FindEstimator("tag-pnp");
    if (seed) entry->seed = SeedPoses(seed->create(EstimatorOptions())->Run(entry->dataset));
  }
  return *entry;
}

void BM_SmootherTagArenaDynamic(benchmark::State& state) {
  const int duration_s = static_cast<int>(state.range(0));
  if (!FindScenario("tag-arena-dynamic") || !FindEstimator("tag-pnp")) {
    state.SkipWithError("tag-arena-dynamic or tag-pnp not available");
    return;
  }
  const Case& c = GetCase(duration_s);
  EstimatorOptions options;
  options.Set("threads", "2");
  options.Set("autodiff_jacobians", state.range(1) != 0 ? "1" : "0");
  SmootherEstimator smoother(options);
  for (auto _ : state) {
    Estimate estimate = smoother.RunFromSeedPoses(c.dataset, c.seed);
    benchmark::DoNotOptimize(estimate);
  }
  const SmootherResult& r = smoother.last_result();
  const SmootherStatistics& s = r.statistics;
  const double seconds_per_run = s.solve_s + s.preintegration_s;
  state.counters["keyframes"] = s.num_keyframes;
  state.counters["visual_res"] = s.num_visual_residuals;
  state.counters["iterations"] = s.iterations;
  state.counters["ceres_s"] = s.solve_s;
  state.counters["ms_per_kf"] = 1e3 * s.solve_s / std::max(1, s.num_keyframes);
  state.counters["linear_s"] = s.linear_solver_s;
  state.counters["jacobian_s"] = s.jacobian_evaluation_s;
  state.counters["preint_s"] = s.preintegration_s;
  state.counters["x_realtime"] = duration_s / std::max(seconds_per_run, 1e-9);
  std::fprintf(stderr, "--- tag-arena-dynamic %d s: %s (linear solver %s)\n", duration_s,
               s.ceres_brief_report.c_str(), s.linear_solver.c_str());
}

BENCHMARK(BM_SmootherTagArenaDynamic)
    ->ArgNames({"s", "autodiff"})
    ->Args({10, 0})
    ->Args({30, 0})
    ->Args({100, 0})
    ->Args({300, 0})
    ->Args({30, 1})
    ->Args({100, 1})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1);

struct CovarianceCase {
  Dataset dataset;
  std::vector<SmootherKeyframe> initial;
};

const CovarianceCase& GetCovarianceCase(int duration_s) {
  static std::map<int, std::unique_ptr<CovarianceCase>> cache;
  auto& entry = cache[duration_s];
  if (!entry) {
    entry = std::make_unique<CovarianceCase>();
    ScenarioOptions options;
    options.seed = 1;
    options.duration_s = duration_s;
    entry->dataset = FindScenario("mav-figure-eight")->generate(options);
    const std::vector<StampedPose> seed = LandmarkPnpSeed(entry->dataset);
    entry->initial =
        InitializeFromSeed(entry->dataset, SmootherKeyframeTimes(entry->dataset), seed).keyframes;
  }
  return *entry;
}

void BM_SmootherCovarianceFigureEight(benchmark::State& state) {
  const int duration_s = static_cast<int>(state.range(0));
  const auto method = state.range(1) == 0 ? SmootherCovarianceMethod::kStructured
                                          : SmootherCovarianceMethod::kCeres;
  if (!FindScenario("mav-figure-eight")) {
    state.SkipWithError("mav-figure-eight not available");
    return;
  }
  const CovarianceCase& c = GetCovarianceCase(duration_s);
  EstimatorOptions estimator_options;
  estimator_options.Set("threads", "2");
  SmootherProblemOptions options =
      SmootherEstimator(estimator_options).ProblemOptionsFor(c.dataset);
  options.compute_covariance = true;
  options.covariance_method = method;
  SmootherResult result;
  for (auto _ : state) {
    result = SolveSmoother(c.dataset, c.initial, {}, std::nullopt, options);
    benchmark::DoNotOptimize(result);
  }
  const SmootherStatistics& s = result.statistics;
  int with_covariance = 0;
  for (const auto& C : result.pose_covariances) with_covariance += C.has_value() ? 1 : 0;
  state.counters["keyframes"] = s.num_keyframes;
  state.counters["with_cov"] = with_covariance;
  state.counters["solve_s"] = s.solve_s;
  state.counters["cov_s"] = s.covariance_s;
  state.counters["cov_per_solve"] = s.covariance_s / std::max(s.solve_s, 1e-9);
  state.counters["cov_ms_per_kf"] = 1e3 * s.covariance_s / std::max(1, s.num_keyframes);
  if (method == SmootherCovarianceMethod::kStructured)
    state.counters["min_pivot"] = s.covariance_min_relative_pivot;
  std::fprintf(stderr, "--- mav-figure-eight %d s, %s covariance: %s\n", duration_s,
               method == SmootherCovarianceMethod::kCeres ? "ceres" : "structured",
               s.ceres_brief_report.c_str());
}

BENCHMARK(BM_SmootherCovarianceFigureEight)
    ->ArgsProduct({{60, 300, 600}, {0, 1}})
    ->Args({1800, 0})
    ->ArgNames({"s", "ceres"})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1);

}  // namespace
}  // namespace mavloc
