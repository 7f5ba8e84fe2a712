// Gaps in an IMU stream: intervals between consecutive samples far longer than the stream's usual
// interval. Integrating across such a gap (a dropout of the logger, a pause of the driver) is
// integrating no data: dead reckoning and preintegration then drift without bound. Estimators that
// integrate the IMU refuse a stream with gaps unless asked to restart after each gap
// (solver/imu_gap_guard.h).
#pragma once

#include <string>
#include <vector>

#include "core/dataset.h"
#include "core/imu.h"
#include "core/time.h"

namespace mavloc {

// An interval is a gap when it is longer than this many median intervals and than
// kImuGapMinSeconds. Real loggers drop samples now and then: the PX4 logs of ../shared/data pause
// for 65 ms (sample.ulg) and 161 ms (sample_log_small.ulg, at its start), which the integrators
// bridge with little error; EuRoC and the ROS bags have no dropout. A gap is a pause of the stream
// that no integrator bridges.
constexpr double kImuGapMedianIntervals = 10.0;
constexpr double kImuGapMinSeconds = 0.2;

struct ImuGap {
  TimeNs from_ns = 0;  // stamp of the last sample before the gap
  TimeNs to_ns = 0;    // stamp of the first sample after it
  double length_s() const { return NsToSeconds(to_ns - from_ns); }
};

// The gaps of a time-ordered stream, in time order; none for fewer than three samples.
std::vector<ImuGap> FindImuGaps(const std::vector<ImuSample>& samples,
                                double median_intervals = kImuGapMedianIntervals,
                                double min_seconds = kImuGapMinSeconds);

// One line for a report or an error: "2 gaps (longest 50.0 s from t = 12.345 s); ...".
// Times are seconds since `t0_ns` (the dataset's first IMU sample).
std::string DescribeImuGaps(const std::vector<ImuGap>& gaps, TimeNs t0_ns);

// The part of a dataset with stamps in [from_ns, to_ns]: every stream (IMU, camera frames, ground
// truth, features, laser, tags, truth quantities) cut to it; sensors, map and scenario kept.
Dataset SliceDataset(const Dataset& dataset, TimeNs from_ns, TimeNs to_ns);

}  // namespace mavloc
