#include "core/dataset.h"

#include <algorithm>
#include <iterator>
#include <string>
#include <utility>
#include <vector>

#include "core/errors.h"
#include "core/number_text.h"

namespace mavloc {

const CameraSensor* Dataset::Camera(const std::string& camera_name) const {
  for (const auto& camera : cameras) {
    if (camera.name == camera_name) return &camera;
  }
  return nullptr;
}

namespace {

auto FirstNotBefore(const std::vector<GroundTruthState>& truth, TimeNs t_ns) {
  return std::lower_bound(truth.begin(), truth.end(), t_ns,
                          [](const GroundTruthState& s, TimeNs t) { return s.t_ns < t; });
}

}  // namespace

std::optional<double> ScenarioNumber(const Dataset& dataset, const std::string& key) {
  const auto it = dataset.scenario_info.find(key);
  if (it == dataset.scenario_info.end()) return std::nullopt;
  // The value is its first word; words after it describe it ("1 per bearing angle").
  const ParsedNumber<double> value = ParseDoubleText(FirstWord(it->second));
  if (!value.ok())
    throw InputError("scenario.yaml", 0, key,
                     DescribeNumberText(it->second, value, "a finite number"));
  return value.value;
}

namespace {

std::string Rows(size_t count) { return std::to_string(count) + (count == 1 ? " row" : " rows"); }

}  // namespace

std::string DescribeDatasetStreams(const Dataset& dataset) {
  const bool on_disk = !dataset.root.empty();
  const auto file = [&](const std::string& stream) {
    return on_disk ? "mav0/" + stream + "/data.csv" : stream;
  };
  std::vector<std::string> parts = {
      file(dataset.imu.name) + " " + Rows(dataset.imu.samples.size()),
      (on_disk ? file("state_groundtruth_estimate0") : std::string("ground truth")) + " " +
          Rows(dataset.ground_truth.size())};
  for (const CameraSensor& camera : dataset.cameras)
    if (!camera.frames.empty())
      parts.push_back(file(camera.name) + " " + Rows(camera.frames.size()));
  const std::pair<const char*, size_t> streams[] = {
      {"features0", dataset.features.size()},
      {"features1", dataset.features1.size()},
      {"laser0", dataset.laser.size()},
      {"tags0", dataset.tags.size()},
      {"tags1", dataset.tags1.size()},
      {"truth_quantities0", dataset.truth_quantities.size()}};
  for (const auto& [stream, count] : streams)
    if (count > 0) parts.push_back(file(stream) + " " + Rows(count));
  std::string text;
  for (const std::string& part : parts) text += (text.empty() ? "" : ", ") + part;
  return text;
}

const GroundTruthState& NearestTruth(const std::vector<GroundTruthState>& truth, TimeNs t_ns) {
  const auto it = FirstNotBefore(truth, t_ns);
  if (it == truth.end()) return truth.back();
  if (it != truth.begin() && (t_ns - std::prev(it)->t_ns) < (it->t_ns - t_ns))
    return *std::prev(it);
  return *it;
}

GroundTruthState InterpolatedTruth(const std::vector<GroundTruthState>& truth, TimeNs t_ns) {
  const auto it = FirstNotBefore(truth, t_ns);
  if (it == truth.begin()) return truth.front();
  if (it == truth.end()) return truth.back();
  const GroundTruthState& a = *std::prev(it);
  const GroundTruthState& b = *it;
  if (b.t_ns == t_ns || b.t_ns == a.t_ns) return b;
  const double s = static_cast<double>(t_ns - a.t_ns) / static_cast<double>(b.t_ns - a.t_ns);
  GroundTruthState out;
  out.t_ns = t_ns;
  out.T_W_B = Pose(a.T_W_B.q.slerp(s, b.T_W_B.q).normalized(), (1 - s) * a.T_W_B.p + s * b.T_W_B.p);
  out.v_W = (1 - s) * a.v_W + s * b.v_W;
  out.b_g = (1 - s) * a.b_g + s * b.b_g;
  out.b_a = (1 - s) * a.b_a + s * b.b_a;
  return out;
}

}  // namespace mavloc
