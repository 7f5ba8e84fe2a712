// ULog parsing throughput (MB/s of file read) on PX4's sample.ulg (../shared/data/px4_ulog,
// 4.05 MB, 69 s of flight), parsed repeatedly: the full scan behind `SummarizeUlog` (every
// message framed, every data message counted) and the IMU import (sensor_combined decoded and
// converted to FLU). The data folder is found next to the source tree, or through the
// MAVLOC_SHARED_DATA environment variable.
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <filesystem>

#include "datasets/io/ulog/ulog_reader.h"

namespace mavloc {
namespace {

std::string SampleUlog() {
  const char* env = std::getenv("MAVLOC_SHARED_DATA");
  const std::filesystem::path data =
      env != nullptr ? std::filesystem::path(env)
                     : std::filesystem::path(__FILE__).parent_path() / "../../shared/data";
  return (data / "px4_ulog/sample.ulg").string();
}

void BM_UlogScan(benchmark::State& state) {
  const std::string path = SampleUlog();
  if (!std::filesystem::exists(path)) {
    state.SkipWithError(("missing " + path).c_str());
    return;
  }
  const auto bytes = static_cast<int64_t>(std::filesystem::file_size(path));
  for (auto _ : state) {
    const UlogInfo info = ReadUlogInfo(path);
    benchmark::DoNotOptimize(info.topics.size());
  }
  state.SetBytesProcessed(state.iterations() * bytes);
}
BENCHMARK(BM_UlogScan)->Unit(benchmark::kMillisecond);

void BM_UlogImu(benchmark::State& state) {
  const std::string path = SampleUlog();
  if (!std::filesystem::exists(path)) {
    state.SkipWithError(("missing " + path).c_str());
    return;
  }
  const auto bytes = static_cast<int64_t>(std::filesystem::file_size(path));
  size_t samples = 0;
  for (auto _ : state) {
    const std::vector<ImuSample> imu = ReadUlogImu(path, "sensor_combined");
    samples = imu.size();
    benchmark::DoNotOptimize(imu.data());
  }
  state.SetBytesProcessed(state.iterations() * bytes);
  state.counters["imu_samples"] = static_cast<double>(samples);
}
BENCHMARK(BM_UlogImu)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace mavloc
