// Wall-clock rates (UseRealTime: libapriltag's worker threads do not count in the main thread's CPU
// time). AprilTag paper pipeline speed: rendering a 752x480 arena frame, detecting its tags with
// libapriltag (frames per second, the paper's "image processing" cost of Fig. 4), detecting a
// Kalibr aprilgrid, and the tag-ekf estimator's real-time factor (seconds of data per second of
// computation) on tag-arena-dynamic.
#include <benchmark/benchmark.h>

#include <chrono>

#include "core/aprilgrid.h"
#include "core/rotation.h"
#include "datasets/rendering/aprilgrid_renderer.h"
#include "datasets/rendering/tag_renderer.h"
#include "datasets/scenarios/tag_arena.h"
#include "frontends/apriltag/detect_tags.h"
#include "solver/estimators/tag_ekf_estimator.h"

namespace mavloc {
namespace {

// The hover of tag-arena-hover, slightly tilted.
Pose HoverCamera() {
  const Pose T_W_B(Eigen::Matrix3d(Rz(0.3) * Rx(0.03)), Eigen::Vector3d(0.35, 0.35, 1.0));
  return T_W_B * TagArenaCamera(10.0).T_B_C;
}

void BM_RenderArenaFrame(benchmark::State& state) {
  const CameraSensor camera = TagArenaCamera(10.0);
  TagRenderOptions options;
  options.supersampling = static_cast<int>(state.range(0));
  const TagRenderer renderer(camera.model, TagArenaTags(), options);
  uint64_t seed = 1;
  for (auto _ : state) benchmark::DoNotOptimize(renderer.Render({HoverCamera()}, seed++));
  state.counters["fps"] =
      benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_RenderArenaFrame)->Arg(4)->Arg(2)->UseRealTime()->Unit(benchmark::kMillisecond);

// Args: decimate, threads, refine_edges.
void BM_DetectTags752x480(benchmark::State& state) {
  const CameraSensor camera = TagArenaCamera(10.0);
  const TagRenderer renderer(camera.model, TagArenaTags());
  const cv::Mat image = renderer.Render({HoverCamera()}, 1);
  TagDetectorOptions options;
  options.decimate = static_cast<double>(state.range(0));
  options.threads = static_cast<int>(state.range(1));
  options.refine_edges = state.range(2) != 0;
  TagDetector detector(options);
  size_t found = 0;
  for (auto _ : state) found = detector.Detect(image).size();
  state.counters["tags"] = static_cast<double>(found);
  state.counters["fps"] =
      benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_DetectTags752x480)
    ->Args({1, 1, 1})
    ->Args({1, 1, 0})
    ->Args({2, 1, 1})
    ->Args({1, 2, 1})
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);

// The default of `mavloc detect-tags --dataset`: rectify (remap to a distortion-free canvas of
// about 1.2 x 1.2 the raw size), detect, map the corners back. Args: decimate.
void BM_DetectTagsRectified752x480(benchmark::State& state) {
  const CameraSensor camera = TagArenaCamera(10.0);
  const TagRenderer renderer(camera.model, TagArenaTags());
  const cv::Mat image = renderer.Render({HoverCamera()}, 1);
  TagDetectorOptions options;
  options.decimate = static_cast<double>(state.range(0));
  RectifiedTagDetector detector(options, camera.model);
  size_t found = 0;
  for (auto _ : state) found = detector.Detect(image).size();
  state.counters["tags"] = static_cast<double>(found);
  state.counters["fps"] =
      benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_DetectTagsRectified752x480)
    ->Arg(1)
    ->Arg(2)
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);

// A Kalibr aprilgrid (6 x 6 tags of 0.088 m, spacing 0.3, as EuRoC's) 1.2 m in front of the EuRoC
// cam0 model, tilted 0.3 rad, rendered at 752x480 with 2 grey levels of noise. Args: separate the
// junctions, refine the X-junction corners (both on = the detector of --family aprilgrid).
void BM_DetectAprilgrid752x480(benchmark::State& state) {
  const CameraSensor camera = TagArenaCamera(10.0);
  const AprilgridTarget target{6, 6, 0.088, 0.3};
  const double half = 0.5 * (target.tag_cols * target.PitchM() - target.tag_spacing * 0.088);
  const Eigen::Matrix3d R_C_M = Rx(0.3) * Rx(M_PI);
  const Pose T_C_M(R_C_M, Eigen::Vector3d(0, 0, 1.2) - R_C_M * Eigen::Vector3d(half, half, 0));
  const cv::Mat image = RenderAprilgrid(camera.model, target, T_C_M, TagRenderOptions{}, 1);
  TagDetectorOptions options;
  options.family = "aprilgrid";
  options.aprilgrid.separate_junctions = state.range(0) != 0;
  options.aprilgrid.refine_corners = state.range(1) != 0;
  TagDetector detector(options);
  size_t found = 0;
  for (auto _ : state) found = detector.Detect(image).size();
  state.counters["tags"] = static_cast<double>(found);
  state.counters["fps"] =
      benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_DetectAprilgrid752x480)
    ->Args({1, 1})
    ->Args({1, 0})
    ->Args({0, 0})
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);

// tag-ekf on 40 s of tag-arena-dynamic (projected tags0): real-time factor = data s / compute s.
void BM_TagEkfRealTimeFactor(benchmark::State& state) {
  ScenarioOptions scenario;
  scenario.duration_s = 40.0;
  const Dataset dataset = GenerateTagArenaDynamic(scenario);
  const double data_s =
      NsToSeconds(dataset.imu.samples.back().t_ns - dataset.imu.samples.front().t_ns);
  double compute_s = 0.0;
  for (auto _ : state) {
    const auto start = std::chrono::steady_clock::now();
    TagEkfEstimator estimator{EstimatorOptions{}};
    benchmark::DoNotOptimize(estimator.Run(dataset));
    compute_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  state.counters["real_time_factor"] = data_s * state.iterations() / compute_s;
  state.counters["tag_rows"] = static_cast<double>(dataset.tags.size());
}
BENCHMARK(BM_TagEkfRealTimeFactor)->UseRealTime()->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace mavloc
