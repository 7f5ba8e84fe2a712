// Time of the smoother's Cramér–Rao bounds (evaluation/crlb/smoother_bound.h: information at the
// truth, filtering recursion and smoothing selected inversion) on tag-arena-dynamic (IMU 100 Hz,
// cam0 10 Hz) for 10, 30, 100 and 300 s of flight; the simulation is outside the timed loop.
// Counters: keyframes, ms per keyframe (flat as the flight grows: everything is linear in the
// number of keyframes), and the bound's position / attitude sigma at the middle keyframe. The same
// on a board map and on laser-only data below.
#include <benchmark/benchmark.h>

#include <cmath>
#include <map>
#include <memory>

#include "core/rotation.h"
#include "datasets/scenarios/scenario.h"
#include "evaluation/crlb/markov_information.h"
#include "evaluation/crlb/smoother_bound.h"

namespace mavloc {
namespace {

const Dataset& GetDataset(int duration_s) {
  static std::map<int, std::unique_ptr<Dataset>> cache;
  auto& entry = cache[duration_s];
  if (!entry) {
    ScenarioOptions options;
    options.seed = 1;
    options.duration_s = duration_s;
    entry = std::make_unique<Dataset>(FindScenario("tag-arena-dynamic")->generate(options));
  }
  return *entry;
}

void BM_SmootherCrlbTagArenaDynamic(benchmark::State& state) {
  if (!FindScenario("tag-arena-dynamic")) {
    state.SkipWithError("tag-arena-dynamic not available");
    return;
  }
  const Dataset& dataset = GetDataset(static_cast<int>(state.range(0)));
  SmootherCrlb bound;
  for (auto _ : state) {
    bound = ComputeSmootherCrlb(dataset);
    benchmark::DoNotOptimize(bound);
  }
  if (!bound.ok) {
    state.SkipWithError(bound.reason.c_str());
    return;
  }
  const double n = static_cast<double>(bound.keyframes.size());
  state.counters["keyframes"] = n;
  state.counters["ms_per_keyframe"] = benchmark::Counter(
      n * 1e-3, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  const CrlbKeyframe& mid = bound.keyframes[bound.keyframes.size() / 2];
  const CrlbSigmas s = SigmasOf(mid.smoothing, mid.T_W_B.q);
  state.counters["sigma_p_mm"] = 1e3 * s.position_m;
  state.counters["sigma_att_deg"] = s.attitude_rad / kDeg;
}
BENCHMARK(BM_SmootherCrlbTagArenaDynamic)
    ->Arg(10)
    ->Arg(30)
    ->Arg(100)
    ->Arg(300)
    ->Unit(benchmark::kMillisecond);

// A board map (aprilgrid-calibration, stereo, 20 Hz): the tilt to gravity as a nuisance parameter
// (the coupled solves of the smoothing bound and the augmented filtering recursion) for 10 and
// 30 s; the simulation (time_offset_ms=0, as `mavloc repro smoother` runs it) is outside the loop.
void BM_SmootherCrlbAprilgrid(benchmark::State& state) {
  const ScenarioEntry* entry = FindScenario("aprilgrid-calibration");
  if (!entry) {
    state.SkipWithError("aprilgrid-calibration not available");
    return;
  }
  ScenarioOptions options;
  options.seed = 1;
  options.duration_s = static_cast<double>(state.range(0));
  options.settings = {{"time_offset_ms", "0"}};
  const Dataset dataset = entry->generate(options);
  SmootherCrlb bound;
  for (auto _ : state) {
    bound = ComputeSmootherCrlb(dataset);
    benchmark::DoNotOptimize(bound);
  }
  if (!bound.ok) {
    state.SkipWithError(bound.reason.c_str());
    return;
  }
  state.counters["keyframes"] = static_cast<double>(bound.keyframes.size());
  state.counters["corners"] = static_cast<double>(bound.visual_residuals);
}
BENCHMARK(BM_SmootherCrlbAprilgrid)->Arg(10)->Arg(30)->Unit(benchmark::kMillisecond);

// Laser-only data (laser-plane, IMU 100 Hz, laser spot 10 Hz): the plane as a 3-parameter
// nuisance, the augmented filtering recursion and the five quantities' bounds, for 30 s and 60 s
// (the paper's run; longer runs can fail the information recursion's conditioning, see
// laser_bound.h); the simulation is outside the loop. Counters: keyframes, ms per
// keyframe, the d and alpha sigmas at the middle keyframe.
void BM_SmootherCrlbLaserPlane(benchmark::State& state) {
  const ScenarioEntry* entry = FindScenario("laser-plane");
  if (!entry) {
    state.SkipWithError("laser-plane not available");
    return;
  }
  ScenarioOptions options;
  options.seed = 1;
  options.duration_s = static_cast<double>(state.range(0));
  const Dataset dataset = entry->generate(options);
  SmootherCrlb bound;
  for (auto _ : state) {
    bound = ComputeSmootherCrlb(dataset);
    benchmark::DoNotOptimize(bound);
  }
  if (!bound.ok) {
    state.SkipWithError(bound.reason.c_str());
    return;
  }
  const double n = static_cast<double>(bound.keyframes.size());
  state.counters["keyframes"] = n;
  state.counters["ms_per_keyframe"] = benchmark::Counter(
      n * 1e-3, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  const CrlbKeyframe& mid = bound.keyframes[bound.keyframes.size() / 2];
  if (mid.laser) {
    state.counters["sigma_d_mm"] = 1e3 * std::sqrt(mid.laser->smoothing(0, 0));
    state.counters["sigma_alpha_deg"] = std::sqrt(mid.laser->smoothing(4, 4)) / kDeg;
  }
}
BENCHMARK(BM_SmootherCrlbLaserPlane)->Arg(30)->Arg(60)->Unit(benchmark::kMillisecond);

// The bounds alone on a synthetic 15-state chain of n states (no dataset).
void BM_MarkovBounds(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  MarkovInformation info;
  Eigen::MatrixXd Phi = Eigen::MatrixXd::Identity(15, 15);
  Phi.block(0, 6, 3, 3) = 0.1 * Eigen::MatrixXd::Identity(3, 3);
  for (int k = 0; k < n; ++k) {
    info.node.push_back(Eigen::MatrixXd::Identity(15, 15) * (k % 3 == 0 ? 1e2 : 0.0));
    if (k + 1 < n) info.AddTransition(Phi, 1e-4 * Eigen::MatrixXd::Identity(15, 15));
  }
  for (auto _ : state) {
    MarkovBounds bounds = ComputeMarkovBounds(info);
    benchmark::DoNotOptimize(bounds);
  }
  state.counters["states"] = n;
}
BENCHMARK(BM_MarkovBounds)->Arg(1000)->Arg(3000)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace mavloc
