#include "core/imu_gaps.h"

#include <fmt/format.h>

#include <algorithm>

namespace mavloc {
namespace {

template <typename Row>
std::vector<Row> Within(const std::vector<Row>& rows, TimeNs from_ns, TimeNs to_ns) {
  std::vector<Row> kept;
  for (const Row& row : rows)
    if (row.t_ns >= from_ns && row.t_ns <= to_ns) kept.push_back(row);
  return kept;
}

QuantityTable Within(const QuantityTable& table, TimeNs from_ns, TimeNs to_ns) {
  QuantityTable kept = table;
  kept.t_ns.clear();
  kept.rows.clear();
  for (size_t i = 0; i < table.t_ns.size(); ++i)
    if (table.t_ns[i] >= from_ns && table.t_ns[i] <= to_ns) {
      kept.t_ns.push_back(table.t_ns[i]);
      kept.rows.push_back(table.rows[i]);
    }
  return kept;
}

}  // namespace

std::vector<ImuGap> FindImuGaps(const std::vector<ImuSample>& samples, double median_intervals,
                                double min_seconds) {
  std::vector<ImuGap> gaps;
  if (samples.size() < 3) return gaps;
  std::vector<TimeNs> intervals;
  intervals.reserve(samples.size() - 1);
  for (size_t i = 1; i < samples.size(); ++i)
    intervals.push_back(samples[i].t_ns - samples[i - 1].t_ns);
  std::vector<TimeNs> sorted = intervals;
  std::nth_element(sorted.begin(), sorted.begin() + static_cast<long>(sorted.size() / 2),
                   sorted.end());
  const double median_ns = static_cast<double>(sorted[sorted.size() / 2]);
  if (median_ns <= 0.0) return gaps;
  const double threshold_ns = std::max(median_intervals * median_ns, min_seconds * 1e9);
  for (size_t i = 0; i < intervals.size(); ++i)
    if (static_cast<double>(intervals[i]) > threshold_ns)
      gaps.push_back({samples[i].t_ns, samples[i + 1].t_ns});
  return gaps;
}

std::string DescribeImuGaps(const std::vector<ImuGap>& gaps, TimeNs t0_ns) {
  if (gaps.empty()) return "no gaps";
  const auto longest = std::max_element(gaps.begin(), gaps.end(), [](const auto& a, const auto& b) {
    return a.length_s() < b.length_s();
  });
  std::string text = fmt::format(
      "{} gap{} longer than {:g} median intervals and {:g} s (longest {:.3f} s from t = {:.3f} s",
      gaps.size(), gaps.size() == 1 ? "" : "s", kImuGapMedianIntervals, kImuGapMinSeconds,
      longest->length_s(), NsToSeconds(longest->from_ns - t0_ns));
  if (gaps.size() > 1)
    text += fmt::format("; first {:.3f} s from t = {:.3f} s", gaps.front().length_s(),
                        NsToSeconds(gaps.front().from_ns - t0_ns));
  return text + ")";
}

Dataset SliceDataset(const Dataset& dataset, TimeNs from_ns, TimeNs to_ns) {
  Dataset slice = dataset;
  slice.imu.samples = Within(dataset.imu.samples, from_ns, to_ns);
  for (auto& camera : slice.cameras) camera.frames = Within(camera.frames, from_ns, to_ns);
  slice.ground_truth = Within(dataset.ground_truth, from_ns, to_ns);
  slice.features = Within(dataset.features, from_ns, to_ns);
  slice.features1 = Within(dataset.features1, from_ns, to_ns);
  slice.laser = Within(dataset.laser, from_ns, to_ns);
  slice.tags = Within(dataset.tags, from_ns, to_ns);
  slice.tags1 = Within(dataset.tags1, from_ns, to_ns);
  slice.truth_quantities = Within(dataset.truth_quantities, from_ns, to_ns);
  return slice;
}

}  // namespace mavloc
