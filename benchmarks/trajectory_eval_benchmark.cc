// Trajectory evaluation at scale: a 1,000,000-pose ground truth (1 kHz, 1000 s)
// against a 500,000-pose estimate (500 Hz, stamps 0.3 ms off the truth's), SE3 and posyaw.
// - BM_AteCore: association (evo nearest, linear merge) + Umeyama alignment + ATE statistics, the
//   computation benchmarks/numpy_ate_yardstick.py does with np.searchsorted and numpy's SVD on the
//   same analytic trajectories (the yardstick);
// - BM_Rpe: evo RPE with delta 1 frame and 10 m on the associated pairs;
// - BM_EvaluateTrajectory: the whole entry point (association, alignment, APE in four relations,
//   RPE 1 frame and 10 m, rpg relative errors at the 5 default lengths, yaw drift, diagnostics);
// - BM_ReadTumTrajectory: reading the 1,000,000-pose truth back from the TUM file mavloc writes
//   (ReadTrajectory: text, format detection, stamps, numbers, quaternion checks, order), the part
//   of `mavloc eval` that np.loadtxt does in the whole-process yardstick (docs/performance.md).
// Run one with --benchmark_filter and /usr/bin/time -v for the peak memory.
#include <benchmark/benchmark.h>

#include <cmath>
#include <filesystem>

#include "core/rotation.h"
#include "datasets/io/trajectory_formats/trajectory_format.h"
#include "datasets/io/tum_io.h"
#include "evaluation/trajectory_evaluation.h"

namespace mavloc {
namespace {

constexpr size_t kTruthPoses = 1'000'000;
constexpr size_t kEstimatePoses = 500'000;

// The same analytic trajectories as numpy_ate_yardstick.py.
Pose TruthAt(double t) {
  const Eigen::Vector3d p(20.0 * std::cos(0.05 * t), 15.0 * std::sin(0.07 * t),
                          2.0 + std::sin(0.3 * t));
  EulerRpy rpy;
  rpy.yaw = 0.05 * t + 0.3 * std::sin(0.9 * t);
  rpy.pitch = 0.1 * std::sin(0.5 * t);
  rpy.roll = 0.1 * std::cos(0.4 * t);
  return Pose(RotationFromEuler(rpy), p);
}

const std::vector<StampedPose>& Truth() {
  static const std::vector<StampedPose> truth = [] {
    std::vector<StampedPose> poses(kTruthPoses);
    for (size_t k = 0; k < kTruthPoses; ++k) {
      const TimeNs t_ns = static_cast<TimeNs>(k) * 1'000'000;  // 1 kHz
      poses[k] = {t_ns, TruthAt(NsToSeconds(t_ns))};
    }
    return poses;
  }();
  return truth;
}

// Estimate: the truth in a world turned by 0.01 rad about z and shifted by (1, 2, 0.5), with a
// wobble of a centimetre and a small attitude error.
const std::vector<StampedPose>& Estimate() {
  static const std::vector<StampedPose> estimate = [] {
    std::vector<StampedPose> poses(kEstimatePoses);
    const Eigen::Matrix3d R_world = Rz(0.01);
    const Eigen::Vector3d t_world(1.0, 2.0, 0.5);
    for (size_t k = 0; k < kEstimatePoses; ++k) {
      const TimeNs t_ns = static_cast<TimeNs>(k) * 2'000'000 + 300'000;  // 500 Hz, +0.3 ms
      const double t = NsToSeconds(t_ns);
      const Pose gt = TruthAt(t);
      const Eigen::Vector3d wobble(0.01 * std::sin(3 * t), 0.01 * std::cos(2 * t),
                                   0.005 * std::sin(5 * t));
      poses[k] = {t_ns, Pose(R_world * gt.R() * Rz(0.001 * std::sin(t)),
                             R_world * (gt.p + wobble) + t_world)};
    }
    return poses;
  }();
  return estimate;
}

AlignmentMode Mode(const benchmark::State& state) {
  return state.range(0) == 0 ? AlignmentMode::kSe3 : AlignmentMode::kPosYaw;
}

void BM_AteCore(benchmark::State& state) {
  const auto& truth = Truth();
  const auto& estimate = Estimate();
  double rmse = 0.0;
  for (auto _ : state) {
    // Indices only, then the positions gathered, as the numpy yardstick does.
    const auto association =
        AssociateTrajectories(estimate, truth, {AssociationMode::kNearest, 0.01, 0.0, false});
    const size_t n = association.estimate_index.size();
    std::vector<Eigen::Vector3d> p_est(n), p_gt(n);
    for (size_t i = 0; i < n; ++i) {
      p_est[i] = estimate[association.estimate_index[i]].T_W_B.p;
      p_gt[i] = truth[association.truth_index[i]].T_W_B.p;
    }
    const auto S = AlignPoints(p_est, p_gt, Mode(state));
    std::vector<double> errors(p_est.size());
    for (size_t i = 0; i < p_est.size(); ++i) errors[i] = (S->Apply(p_est[i]) - p_gt[i]).norm();
    rmse = ComputeStatistics(errors).rmse;
    benchmark::DoNotOptimize(rmse);
  }
}
BENCHMARK(BM_AteCore)->Arg(0)->Arg(1)->ArgName("posyaw")->Unit(benchmark::kMillisecond);

void BM_Rpe(benchmark::State& state) {
  const auto association =
      AssociateTrajectories(Estimate(), Truth(), {AssociationMode::kNearest, 0.01, 0.0});
  const RpeDelta delta = state.range(0) == 0 ? RpeDelta{1, DeltaUnit::kFrames, false}
                                             : RpeDelta{10.0, DeltaUnit::kMetres, false};
  double rmse = 0.0;
  for (auto _ : state) {
    rmse = ComputeRpeEvo(association.pairs, delta)->translation_m.rmse;
    benchmark::DoNotOptimize(rmse);
  }
}
BENCHMARK(BM_Rpe)->Arg(0)->Arg(1)->ArgName("metres")->Unit(benchmark::kMillisecond);

void BM_EvaluateTrajectory(benchmark::State& state) {
  EvaluationProtocol protocol;
  protocol.alignment = Mode(state);
  protocol.rpe_deltas = {RpeDelta{1, DeltaUnit::kFrames, false},
                         RpeDelta{10.0, DeltaUnit::kMetres, false}};
  double rmse = 0.0;
  for (auto _ : state) {
    const auto r = EvaluateTrajectory(Estimate(), Truth(), protocol);
    rmse = r->ape_translation_m.rmse;
    benchmark::DoNotOptimize(rmse);
  }
}
BENCHMARK(BM_EvaluateTrajectory)->Arg(0)->Arg(1)->ArgName("posyaw")->Unit(benchmark::kMillisecond);

void BM_ReadTumTrajectory(benchmark::State& state) {
  const std::string path =
      (std::filesystem::temp_directory_path() / "mavloc_bench_truth_1M.txt").string();
  WriteTumTrajectory(Truth(), path);
  size_t poses = 0;
  for (auto _ : state) {
    poses = ReadTrajectory(path).poses.size();
    benchmark::DoNotOptimize(poses);
  }
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations()) *
                          static_cast<int64_t>(std::filesystem::file_size(path)));
  state.counters["poses"] = static_cast<double>(poses);
  std::filesystem::remove(path);
}
BENCHMARK(BM_ReadTumTrajectory)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace mavloc
