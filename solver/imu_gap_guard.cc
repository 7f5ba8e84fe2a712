#include "solver/imu_gap_guard.h"

#include <fmt/format.h>

#include <algorithm>
#include <vector>

#include "core/errors.h"
#include "core/imu_gaps.h"

namespace mavloc {
namespace {

struct Segment {
  TimeNs from_ns = 0, to_ns = 0;
};

// The gap-free stretches of the IMU stream, in time order.
std::vector<Segment> Segments(const Dataset& dataset, const std::vector<ImuGap>& gaps) {
  std::vector<Segment> segments;
  TimeNs from_ns = dataset.imu.samples.front().t_ns;
  for (const ImuGap& gap : gaps) {
    segments.push_back({from_ns, gap.from_ns});
    from_ns = gap.to_ns;
  }
  segments.push_back({from_ns, dataset.imu.samples.back().t_ns});
  return segments;
}

// cam0 frames strictly inside (from_ns, to_ns) (none without a camera).
int FramesWithin(const Dataset& dataset, TimeNs from_ns, TimeNs to_ns) {
  if (dataset.cameras.empty()) return 0;
  int count = 0;
  for (const CameraFrame& frame : dataset.cameras.front().frames)
    count += frame.t_ns > from_ns && frame.t_ns < to_ns;
  return count;
}

void Append(const Estimate& part, Estimate* joined) {
  if (joined->quantities.names.empty()) {
    joined->quantities = part.quantities;
  } else if (part.quantities.names == joined->quantities.names) {
    for (size_t i = 0; i < part.quantities.t_ns.size(); ++i)
      joined->quantities.Append(part.quantities.t_ns[i], part.quantities.rows[i]);
  }
  joined->poses.insert(joined->poses.end(), part.poses.begin(), part.poses.end());
  if (joined->covariance_names.empty()) joined->covariance_names = part.covariance_names;
  if (part.covariance_names == joined->covariance_names)
    joined->covariances.insert(joined->covariances.end(), part.covariances.begin(),
                               part.covariances.end());
  for (const auto& [reason, count] : part.failures) joined->failures[reason] += count;
  for (const auto& [reason, count] : part.rejections) joined->rejections[reason] += count;
}

}  // namespace

ImuGapGuard::ImuGapGuard(Factory create, const EstimatorOptions& options)
    : create_(std::move(create)), inner_(create_()) {
  const std::string policy = options.GetString(kImuGapsOption, "refuse");
  if (policy != "refuse" && policy != "reset")
    throw InputError(
        fmt::format("--option {}={}: expected refuse or reset", kImuGapsOption, policy));
  reset_ = policy == "reset";
}

Applicability ImuGapGuard::AppliesTo(const Dataset& dataset) const {
  const std::vector<ImuGap> gaps = FindImuGaps(dataset.imu.samples);
  if (gaps.empty()) return inner_->AppliesTo(dataset);
  const std::string described =
      dataset.imu.name + ": " + DescribeImuGaps(gaps, dataset.imu.samples.front().t_ns);
  if (!reset_)
    return Applicability::No(
        described + "; an estimator that integrates the IMU cannot bridge them (--option " +
        kImuGapsOption + "=reset restarts it after each gap)");
  std::string first_reason;
  for (const Segment& segment : Segments(dataset, gaps)) {
    const Applicability applies =
        inner_->AppliesTo(SliceDataset(dataset, segment.from_ns, segment.to_ns));
    if (applies.applies) return applies;
    if (first_reason.empty()) first_reason = applies.reason;
  }
  return Applicability::No(described + "; no segment between them can be estimated (" +
                           first_reason + ")");
}

Estimate ImuGapGuard::Run(const Dataset& dataset) {
  const std::vector<ImuGap> gaps = FindImuGaps(dataset.imu.samples);
  if (gaps.empty()) return inner_->Run(dataset);
  // Only reached with reset: AppliesTo refuses a stream with gaps otherwise.
  Estimate joined;
  TimeNs longest_ns = -1;
  for (const Segment& segment : Segments(dataset, gaps)) {
    const Dataset part = SliceDataset(dataset, segment.from_ns, segment.to_ns);
    std::unique_ptr<Estimator> fresh = create_();
    const Applicability applies = fresh->AppliesTo(part);
    if (!applies.applies) {
      joined.failures["IMU segment between gaps not estimated: " + applies.reason] +=
          std::max(1, FramesWithin(dataset, segment.from_ns - 1, segment.to_ns + 1));
      continue;
    }
    const Estimate estimate = fresh->Run(part);
    Append(estimate, &joined);
    if (segment.to_ns - segment.from_ns > longest_ns) {  // constants of the longest segment
      longest_ns = segment.to_ns - segment.from_ns;
      joined.parameters = estimate.parameters;
      joined.extrinsics = estimate.extrinsics;
      joined.T_W_M = estimate.T_W_M;
    }
  }
  // Every frame is posed or counted: those inside a gap have no IMU to carry a state to them.
  for (const ImuGap& gap : gaps)
    if (const int inside = FramesWithin(dataset, gap.from_ns, gap.to_ns); inside > 0)
      joined.failures["frame inside an IMU gap (no IMU to carry the state there)"] += inside;
  joined.parameters["imu_gap_restarts"] = {static_cast<double>(gaps.size()), std::nullopt, ""};
  return joined;
}

}  // namespace mavloc
