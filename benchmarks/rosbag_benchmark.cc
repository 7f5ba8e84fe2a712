// ROS1 bag reading throughput (MB/s of bag file) through rosbag_storage on robot_localization's
// test1.bag (../shared/data/ros_bags, 1.47 MB, bz2 chunks, 11865 IMU messages), and the streaming
// bzip2 decompression plus odometry read of TagSLAM's test_11 reference.bag.bz2 (2.7 MB -> 38.9 MB,
// 4500 nav_msgs/Odometry). The data folder is found next to the source tree, or through the
// MAVLOC_SHARED_DATA environment variable.
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <filesystem>

#include "datasets/io/rosbag/rosbag_reader.h"

namespace mavloc {
namespace {

std::string SharedData(const std::string& relative) {
  const char* env = std::getenv("MAVLOC_SHARED_DATA");
  const std::filesystem::path data =
      env != nullptr ? std::filesystem::path(env)
                     : std::filesystem::path(__FILE__).parent_path() / "../../shared/data";
  return (data / relative).string();
}

void BM_RosbagImu(benchmark::State& state) {
  const std::string path = SharedData("ros_bags/test1.bag");
  if (!std::filesystem::exists(path)) {
    state.SkipWithError(("missing " + path).c_str());
    return;
  }
  const auto bytes = static_cast<int64_t>(std::filesystem::file_size(path));
  size_t samples = 0;
  for (auto _ : state) {
    const std::vector<ImuSample> imu = ReadRosbagImu(path, "/imu/data");
    samples = imu.size();
    benchmark::DoNotOptimize(imu.data());
  }
  state.SetBytesProcessed(state.iterations() * bytes);
  state.counters["imu_samples"] = static_cast<double>(samples);
}
BENCHMARK(BM_RosbagImu)->Unit(benchmark::kMillisecond);

// Bytes counted: the decompressed bag (what a plain .bag of the same content would be).
void BM_RosbagWholeFileBzip2Odometry(benchmark::State& state) {
  const std::string path = SharedData("tagslam/test_11/reference.bag.bz2");
  if (!std::filesystem::exists(path)) {
    state.SkipWithError(("missing " + path).c_str());
    return;
  }
  constexpr int64_t kDecompressedBytes = 38888792;
  size_t states = 0;
  for (auto _ : state) {
    LogTopicSpec spec;
    spec.path = path;
    spec.topic = "/tagslam/odom/body_rig";
    const LogTrajectory trajectory = ReadRosbagTrajectory(spec);
    states = trajectory.states.size();
    benchmark::DoNotOptimize(trajectory.states.data());
  }
  state.SetBytesProcessed(state.iterations() * kDecompressedBytes);
  state.counters["states"] = static_cast<double>(states);
}
BENCHMARK(BM_RosbagWholeFileBzip2Odometry)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace mavloc
