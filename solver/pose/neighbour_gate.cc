#include "solver/pose/neighbour_gate.h"

#include <fmt/format.h>

#include <algorithm>

namespace mavloc {

namespace {

double Median(std::vector<double> values) {
  const size_t mid = values.size() / 2;
  std::nth_element(values.begin(), values.begin() + static_cast<long>(mid), values.end());
  const double upper = values[mid];
  if (values.size() % 2 == 1) return upper;
  const double lower = *std::max_element(values.begin(), values.begin() + static_cast<long>(mid));
  return 0.5 * (lower + upper);
}

}  // namespace

NeighbourGateOptions ParseNeighbourGateOptions(const EstimatorOptions& options) {
  NeighbourGateOptions out;
  out.gate_m = options.GetDouble("neighbour_gate_m", out.gate_m);
  out.frames = options.GetInt("neighbour_frames", out.frames);
  return out;
}

std::vector<bool> NeighbourGateRefusals(const std::vector<Eigen::Vector3d>& positions_W,
                                        const NeighbourGateOptions& options) {
  const size_t n = positions_W.size();
  std::vector<bool> refused(n, false);
  if (!options.enabled()) return refused;
  const size_t half = static_cast<size_t>(std::max(options.frames, 2) / 2);
  std::vector<double> axis;
  for (size_t i = 0; i < n; ++i) {
    // As many frames after as before, so that the median of a steady motion is the frame's own
    // position (a one-sided window at the ends would lag behind a moving vehicle).
    const size_t side = std::min({half, i, n - 1 - i});
    if (side == 0) continue;  // the first and the last frame: nothing on one side
    const size_t begin = i - side, end = i + side + 1;
    Eigen::Vector3d median_W;
    for (int a = 0; a < 3; ++a) {
      axis.clear();
      for (size_t k = begin; k < end; ++k)
        if (k != i) axis.push_back(positions_W[k](a));
      median_W(a) = Median(axis);
    }
    refused[i] = (positions_W[i] - median_W).norm() > options.gate_m;
  }
  return refused;
}

std::string NeighbourGateReason(const NeighbourGateOptions& options) {
  return fmt::format(
      "position more than {:g} m from the median of its {} neighbouring posed frames "
      "(neighbour_gate_m)",
      options.gate_m, options.frames);
}

}  // namespace mavloc
