// Throughput of `mavloc imu-noise`'s streaming path, in IMU samples per second on one core
// (x 60 for samples per minute): the IMU CSV reader (ForEachImuCsvSample: block reads,
// std::from_chars), the Allan deviation accumulator alone (six series, the default --max-tau of
// 1000 s at 200 Hz), and both passes of ComputeImuAllanDeviationStreaming over a CSV, which is what
// the command does apart from writing the report. The CSV (200 Hz, white noise and bias random
// walks, EuRoC imu0 columns, 17 significant digits as EuRoC writes them) is generated once into the
// system temp folder. The whole process, with its peak memory, is measured with /usr/bin/time -v:
// docs/commands/imu-noise.md, "Speed and memory".
#include <benchmark/benchmark.h>
#include <fmt/format.h>

#include <cstdio>
#include <filesystem>
#include <string>

#include "core/random.h"
#include "datasets/io/euroc_io.h"
#include "evaluation/imu_noise/allan_streaming.h"

namespace mavloc {
namespace {

constexpr size_t kCsvSamples = 1000000;  // 5000 s at 200 Hz, 145 MB

// A static 200 Hz IMU log of kCsvSamples rows, written once.
const std::string& ImuCsv() {
  static const std::string path = [] {
    const std::string file =
        (std::filesystem::temp_directory_path() / "mavloc_imu_noise_benchmark_1M.csv").string();
    if (std::filesystem::exists(file)) return file;
    const std::string partial = file + ".partial";
    std::FILE* out = std::fopen(partial.c_str(), "w");
    std::fputs(
        "#timestamp [ns],w_RS_S_x [rad s^-1],w_RS_S_y [rad s^-1],w_RS_S_z [rad s^-1],"
        "a_RS_S_x [m s^-2],a_RS_S_y [m s^-2],a_RS_S_z [m s^-2]\n",
        out);
    Rng rng(1);
    Eigen::Vector3d bias_g = Eigen::Vector3d::Zero(), bias_a = Eigen::Vector3d::Zero();
    for (size_t i = 0; i < kCsvSamples; ++i) {
      bias_g += rng.Gaussian3(1.3e-6);
      bias_a += rng.Gaussian3(2.1e-4);
      const Eigen::Vector3d w = bias_g + rng.Gaussian3(2.4e-3);
      const Eigen::Vector3d a = Eigen::Vector3d(0, 0, 9.81) + bias_a + rng.Gaussian3(2.8e-2);
      const std::string row = fmt::format("{},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g}\n",
                                          1403715273262142976 + static_cast<int64_t>(i) * 5000000,
                                          w.x(), w.y(), w.z(), a.x(), a.y(), a.z());
      std::fputs(row.c_str(), out);
    }
    std::fclose(out);
    std::filesystem::rename(partial, file);
    return file;
  }();
  return path;
}

void BM_ImuCsvRead(benchmark::State& state) {
  const std::string& path = ImuCsv();
  size_t samples = 0;
  for (auto _ : state) {
    samples = 0;
    double sum = 0.0;
    ForEachImuCsvSample(path, [&](const ImuSample& s) {
      sum += s.accel_m_s2.z();
      ++samples;
    });
    benchmark::DoNotOptimize(sum);
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(samples));
  state.SetBytesProcessed(state.iterations() *
                          static_cast<int64_t>(std::filesystem::file_size(path)));
}
BENCHMARK(BM_ImuCsvRead)->Unit(benchmark::kMillisecond);

void BM_StreamingAllanAccumulate(benchmark::State& state) {
  // Six series of state.range(0) samples at 200 Hz, tau up to 1000 s (the default --max-tau).
  const size_t n = static_cast<size_t>(state.range(0));
  Rng rng(2);
  std::vector<double> values(6 * 4096);
  for (double& v : values) v = rng.Gaussian();
  AllanOptions options;
  options.max_tau_s = kImuNoiseDefaultMaxTau_s;
  size_t bytes = 0;
  for (auto _ : state) {
    StreamingAllanDeviation allan(std::vector<double>(6, 0.0), n, 0.005, options);
    for (size_t k = 0; k < n; ++k) allan.Add(&values[6 * (k % 4096)]);
    bytes = allan.history_bytes();
    benchmark::DoNotOptimize(allan.Finish());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(n));
  state.counters["history_MB"] = static_cast<double>(bytes) / 1e6;
}
BENCHMARK(BM_StreamingAllanAccumulate)->Arg(1000000)->Unit(benchmark::kMillisecond);

void BM_ImuNoiseTwoPassesFromCsv(benchmark::State& state) {
  const std::string& path = ImuCsv();
  AllanOptions options;
  options.max_tau_s = kImuNoiseDefaultMaxTau_s;
  size_t samples = 0;
  for (auto _ : state) {
    const ImuAllanDeviation curves = ComputeImuAllanDeviationStreaming(
        [&](const std::function<void(const ImuSample&)>& visit) {
          ForEachImuCsvSample(path, visit);
        },
        options);
    samples = curves.sampling.samples;
    benchmark::DoNotOptimize(curves.gyro[0].points.data());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(samples));
}
BENCHMARK(BM_ImuNoiseTwoPassesFromCsv)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace mavloc
