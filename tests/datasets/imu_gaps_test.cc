// IMU gaps (core/imu_gaps.h): found where the stream pauses, not in the ordinary jitter and the
// occasional dropped sample of real loggers (EuRoC, its calibration log, PX4 ULog, ROS bags).
#include "core/imu_gaps.h"

#include <gtest/gtest.h>

#include <string>

#include "datasets/io/euroc_io.h"
#include "datasets/io/log_reader.h"
#include "tests/test_support.h"

namespace mavloc {
namespace {

std::vector<ImuSample> Stream(double rate_hz, double duration_s) {
  std::vector<ImuSample> samples;
  for (int i = 0; i < static_cast<int>(rate_hz * duration_s); ++i)
    samples.push_back({static_cast<TimeNs>(i * 1e9 / rate_hz), {}, {}});
  return samples;
}

TEST(ImuGaps, FindsEachGapWithItsTimeAndLength) {
  std::vector<ImuSample> samples = Stream(200.0, 10.0);
  // Remove 2.0 s from t = 3 s, 0.3 s from t = 8 s and 60 ms (a dropout, not a gap) from t = 9 s.
  std::erase_if(samples, [](const ImuSample& s) {
    const double t = NsToSeconds(s.t_ns);
    return (t > 3.0 && t < 5.0) || (t > 8.0 && t < 8.3) || (t > 9.0 && t < 9.06);
  });
  const auto gaps = FindImuGaps(samples);
  ASSERT_EQ(gaps.size(), 2u);
  EXPECT_NEAR(NsToSeconds(gaps[0].from_ns), 3.0, 1e-9);
  EXPECT_NEAR(gaps[0].length_s(), 2.0, 0.006);
  EXPECT_NEAR(gaps[1].length_s(), 0.3, 0.006);
  // Without the 0.2 s floor the dropout counts too.
  EXPECT_EQ(FindImuGaps(samples, kImuGapMedianIntervals, 0.0).size(), 3u);
  const std::string text = DescribeImuGaps(gaps, 0);
  EXPECT_NE(text.find("2 gaps"), std::string::npos) << text;
  EXPECT_NE(text.find("longest 2.00"), std::string::npos) << text;
  EXPECT_NE(text.find("from t = 3.000 s"), std::string::npos) << text;
}

TEST(ImuGaps, DroppedSamplesAndJitterAreNoGap) {
  std::vector<ImuSample> samples = Stream(200.0, 10.0);
  // Three samples dropped in a row (20 ms) and +-1 ms of jitter.
  samples.erase(samples.begin() + 500, samples.begin() + 503);
  for (size_t i = 0; i < samples.size(); i += 2) samples[i].t_ns += 1'000'000;
  EXPECT_TRUE(FindImuGaps(samples).empty());
  EXPECT_TRUE(FindImuGaps(Stream(200.0, 0.01)).empty());  // fewer than 3 samples
}

TEST(ImuGaps, SliceKeepsEveryStreamWithinTheInterval) {
  Dataset dataset;
  dataset.imu.samples = Stream(100.0, 4.0);
  dataset.ground_truth.push_back({0, {}, {}, {}, {}});
  dataset.ground_truth.push_back({2'500'000'000, {}, {}, {}, {}});
  dataset.tags.push_back({1'000'000'000, 3, {}, 0});
  dataset.tags.push_back({3'000'000'000, 4, {}, 0});
  const Dataset slice = SliceDataset(dataset, 2'000'000'000, 4'000'000'000);
  EXPECT_EQ(slice.imu.samples.front().t_ns, 2'000'000'000);
  EXPECT_EQ(slice.imu.samples.size(), 200u);
  ASSERT_EQ(slice.ground_truth.size(), 1u);
  EXPECT_EQ(slice.ground_truth[0].t_ns, 2'500'000'000);
  ASSERT_EQ(slice.tags.size(), 1u);
  EXPECT_EQ(slice.tags[0].tag_id, 4);
}

TEST(ImuGapsOnRealLogs, NoneInTheLogsOfSharedData) {
  REQUIRE_SHARED_DATA();
  const std::string data = testing::SharedDataDir();
  EXPECT_TRUE(FindImuGaps(ReadImuCsv(data + "/euroc_v1_01_easy/mav0/imu0/data.csv")).empty());
  EXPECT_TRUE(FindImuGaps(ReadImuCsv(data + "/euroc_imu_april/imu0.csv")).empty());
  for (const char* bag : {"test1.bag", "test2.bag"}) {
    const auto samples = ReadLogImu(data + "/ros_bags/" + bag, "/imu/data");
    EXPECT_TRUE(FindImuGaps(samples).empty())
        << bag << ": " << DescribeImuGaps(FindImuGaps(samples), samples.front().t_ns);
  }
  for (const char* ulog : {"sample.ulg", "sample_log_small.ulg"}) {
    const auto samples = ReadLogImu(data + "/px4_ulog/" + ulog, "sensor_combined");
    if (samples.empty()) continue;
    EXPECT_TRUE(FindImuGaps(samples).empty())
        << ulog << ": " << DescribeImuGaps(FindImuGaps(samples), samples.front().t_ns);
  }
}

}  // namespace
}  // namespace mavloc
