#include "solver/pose/neighbour_gate.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

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

// The frames next to frame i (itself left out), up to half on each side and within half_window_s
// of it (no bound when half_window_s <= 0), split into those before and those after it.
struct Neighbourhood {
  std::vector<size_t> before, after;  // nearest first
};

Neighbourhood NeighboursOf(const std::vector<double>& times_s, size_t i, size_t half,
                           double half_window_s) {
  const auto within = [&](size_t k) {
    return half_window_s <= 0.0 || std::abs(times_s[k] - times_s[i]) <= half_window_s;
  };
  Neighbourhood out;
  for (size_t k = i; k > 0 && out.before.size() < half && within(k - 1); --k)
    out.before.push_back(k - 1);
  for (size_t k = i + 1; k < times_s.size() && out.after.size() < half && within(k); ++k)
    out.after.push_back(k);
  return out;
}

// A median needs three values to outvote one wrong neighbour; a slope fitted through neighbours on
// one side needs five (with three, one wrong neighbour tilts it).
constexpr size_t kMinNeighbours = 3;
constexpr size_t kMinOneSided = 5;

// The component-wise median of the neighbours' positions.
Eigen::Vector3d MedianPosition(const std::vector<Eigen::Vector3d>& positions_W,
                               const std::vector<size_t>& neighbours) {
  Eigen::Vector3d median_W;
  std::vector<double> axis;
  for (int a = 0; a < 3; ++a) {
    axis.clear();
    for (const size_t k : neighbours) axis.push_back(positions_W[k](a));
    median_W(a) = Median(axis);
  }
  return median_W;
}

// The slope of p(t) along one axis through the neighbours, robustly: Siegel's repeated median
// ("Robust regression using repeated medians", Biometrika 1982), the median over j of the median
// over k of the pairwise slopes, which holds while under half of the neighbours are wrong.
double RepeatedMedianSlope(const std::vector<double>& times_s,
                           const std::vector<Eigen::Vector3d>& positions_W,
                           const std::vector<size_t>& neighbours, int axis) {
  std::vector<double> per_point, pairwise;
  for (const size_t j : neighbours) {
    pairwise.clear();
    for (const size_t k : neighbours) {
      const double dt_s = times_s[k] - times_s[j];
      if (dt_s != 0.0) pairwise.push_back((positions_W[k](axis) - positions_W[j](axis)) / dt_s);
    }
    if (!pairwise.empty()) per_point.push_back(Median(pairwise));
  }
  return per_point.empty() ? 0.0 : Median(per_point);
}

// Where one-sided neighbours put frame i, per axis: the median of p_k + slope (t_i - t_k); the
// slope removes the lag of their median behind (or ahead of) a moving vehicle.
Eigen::Vector3d PredictedPosition(const std::vector<double>& times_s,
                                  const std::vector<Eigen::Vector3d>& positions_W,
                                  const std::vector<size_t>& neighbours, size_t i) {
  Eigen::Vector3d predicted_W;
  std::vector<double> values;
  for (int a = 0; a < 3; ++a) {
    const double slope = RepeatedMedianSlope(times_s, positions_W, neighbours, a);
    values.clear();
    for (const size_t k : neighbours)
      values.push_back(positions_W[k](a) + slope * (times_s[i] - times_s[k]));
    predicted_W(a) = Median(values);
  }
  return predicted_W;
}

}  // namespace

NeighbourGateOptions ParseNeighbourGateOptions(const EstimatorOptions& options) {
  NeighbourGateOptions out;
  out.gate_m = options.GetDouble("neighbour_gate_m", out.gate_m);
  out.frames = options.GetInt("neighbour_frames", out.frames);
  out.window_s = options.GetDouble("neighbour_window_s", out.window_s);
  return out;
}

std::vector<bool> NeighbourGateRefusals(const std::vector<double>& times_s,
                                        const std::vector<Eigen::Vector3d>& positions_W,
                                        const NeighbourGateOptions& options) {
  if (times_s.size() != positions_W.size())
    throw std::invalid_argument("NeighbourGateRefusals: times and positions differ in size");
  const size_t n = positions_W.size();
  std::vector<bool> refused(n, false);
  if (!options.enabled()) return refused;
  const size_t half = static_cast<size_t>(std::max(options.frames, 2) / 2);
  const double half_window_s = 0.5 * options.window_s;
  for (size_t i = 0; i < n; ++i) {
    const Neighbourhood near = NeighboursOf(times_s, i, half, half_window_s);
    const size_t side = std::min(near.before.size(), near.after.size());
    Eigen::Vector3d predicted_W;
    if (side >= kMinNeighbours) {
      // Inside a run: as many frames after as before, whose median a steady motion centres on the
      // frame (a step of wrong frames does not tilt it, as a fitted slope would).
      std::vector<size_t> neighbours(near.before.begin(),
                                     near.before.begin() + static_cast<long>(side));
      neighbours.insert(neighbours.end(), near.after.begin(),
                        near.after.begin() + static_cast<long>(side));
      predicted_W = MedianPosition(positions_W, neighbours);
    } else {
      // Next to a gap or an end of the log: what there is, with the slope.
      std::vector<size_t> neighbours = near.before;
      neighbours.insert(neighbours.end(), near.after.begin(), near.after.end());
      if (neighbours.size() < kMinOneSided) continue;  // too little to compare with
      predicted_W = PredictedPosition(times_s, positions_W, neighbours, i);
    }
    refused[i] = (positions_W[i] - predicted_W).norm() > options.gate_m;
  }
  return refused;
}

std::string NeighbourGateReason(const NeighbourGateOptions& options) {
  return fmt::format(
      "position more than {:g} m from where its neighbouring posed frames put it (up to {} "
      "within {:g} s; neighbour_gate_m)",
      options.gate_m, options.frames, options.window_s);
}

}  // namespace mavloc
