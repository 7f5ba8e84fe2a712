#include "evaluation/truth_checks.h"

#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <limits>

#include "core/errors.h"

namespace mavloc {

namespace {

struct Span {
  TimeNs begin = std::numeric_limits<TimeNs>::max();
  TimeNs end = std::numeric_limits<TimeNs>::min();
  bool empty() const { return begin > end; }
  void Add(TimeNs t_ns) {
    begin = std::min(begin, t_ns);
    end = std::max(end, t_ns);
  }
};

Span SensorSpan(const Dataset& d) {
  Span span;
  for (const auto& s : d.imu.samples) span.Add(s.t_ns);
  for (const auto& camera : d.cameras)
    for (const auto& f : camera.frames) span.Add(f.t_ns);
  for (const auto& f : d.features) span.Add(f.t_ns);
  for (const auto& l : d.laser) span.Add(l.t_ns);
  for (const auto& t : d.tags) span.Add(t.t_ns);
  for (const auto& t : d.tags1) span.Add(t.t_ns);
  return span;
}

}  // namespace

std::string GroundTruthSource(const Dataset& dataset) {
  if (dataset.root.empty()) return "ground truth";
  return (std::filesystem::path(dataset.root) / "mav0" / "state_groundtruth_estimate0" / "data.csv")
      .string();
}

void RequireUsableGroundTruth(const Dataset& dataset) {
  const auto& truth = dataset.ground_truth;
  if (truth.empty()) return;
  const std::string source = GroundTruthSource(dataset);
  if (truth.size() < 2)
    throw InputError(source, 0, "",
                     "holds 1 row: an evaluation needs a ground truth over time (at least 2 rows)");
  const Span data = SensorSpan(dataset);
  if (data.empty()) return;
  const TimeNs truth_begin = truth.front().t_ns;
  const TimeNs truth_end = truth.back().t_ns;
  if (truth_end < data.begin || truth_begin > data.end)
    throw InputError(source, 0, "",
                     fmt::format("covers {:.3f} s to {:.3f} s but the sensor data cover {:.3f} s "
                                 "to {:.3f} s: no overlap, so no estimate can be judged",
                                 NsToSeconds(truth_begin), NsToSeconds(truth_end),
                                 NsToSeconds(data.begin), NsToSeconds(data.end)));
}

}  // namespace mavloc
