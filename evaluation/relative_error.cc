#include "evaluation/relative_error.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>

#include "core/rotation.h"

namespace mavloc {

std::vector<double> AccumulatedDistances(const PairedPoses& pairs) {
  std::vector<double> d(pairs.size(), 0.0);
  if (pairs.empty()) return d;
  Eigen::Vector3d previous = pairs.p_gt(0);
  for (size_t i = 1; i < pairs.size(); ++i) {
    const Eigen::Vector3d p = pairs.p_gt(i);
    d[i] = d[i - 1] + (p - previous).norm();
    previous = p;
  }
  return d;
}

std::vector<double> DefaultRelativeLengths(double path_length_m,
                                           const std::vector<double>& fractions) {
  std::vector<double> lengths;
  for (double f : fractions) {
    const double truncated = std::trunc(f * path_length_m * 100.0) / 100.0;
    if (truncated > 0.0) lengths.push_back(truncated);
  }
  return lengths;
}

std::vector<long> SegmentEndIndices(const std::vector<double>& distances, double length_m,
                                    double max_length_diff_m) {
  const size_t n = distances.size();
  std::vector<long> end(n, -1);
  // The first index of each run of equal distances (rpg keeps the first index on ties).
  std::vector<size_t> run_start(n, 0);
  for (size_t j = 1; j < n; ++j)
    run_start[j] = distances[j] == distances[j - 1] ? run_start[j - 1] : j;
  size_t k = 0;  // first index with distances[k] >= distances[i] + length
  for (size_t i = 0; i < n; ++i) {
    const double target = distances[i] + length_m;
    k = std::max(k, i);
    while (k < n && distances[k] < target) ++k;
    // |distances[j] - target| over j in [i, n) is minimised at k - 1 or at k (distances do not
    // decrease); within a run of equal distances the first index >= i.
    double best_err = max_length_diff_m;  // strict '<' as rpg
    long best = -1;
    for (size_t j : {k == 0 ? n : k - 1, k}) {
      if (j < i || j >= n) continue;
      const size_t first = std::max(run_start[j], i);
      const double err = std::abs(distances[first] - target);
      if (err < best_err || (err == best_err && best >= 0 && static_cast<long>(first) < best)) {
        best_err = err;
        best = static_cast<long>(first);
      }
    }
    end[i] = best;
  }
  return end;
}

RelativeErrorAtLength ComputeRelativeError(const PairedPoses& pairs,
                                           const std::vector<double>& distances, double length_m,
                                           double max_length_diff_fraction, double scale,
                                           const Eigen::Matrix3d& R_raw_aligned,
                                           bool keep_segments) {
  RelativeErrorAtLength r;
  r.length_m = length_m;
  if (!(length_m > 0) || pairs.size() != distances.size()) return r;
  auto end = SegmentEndIndices(distances, length_m, max_length_diff_fraction * length_m);
  const size_t found =
      static_cast<size_t>(std::count_if(end.begin(), end.end(), [](long j) { return j >= 0; }));
  if (found < 2) return r;  // rpg: "Too few samples! Will not compute."
  // Without the segments, the % and per-metre series are not stored: their statistics come from
  // the metres' and degrees' (ComputeStatisticsWithImage, the same bits).
  for (auto* values : {&r.translation_m, &r.rotation_deg, &r.yaw_deg, &r.tilt_deg})
    values->reserve(found);
  if (keep_segments) {
    r.start_t_ns.reserve(found);
    r.translation_percent.reserve(found);
    r.rotation_deg_per_m.reserve(found);
  }
  for (size_t i = 0; i < pairs.size(); ++i) {
    if (end[i] < 0) continue;
    const PosePair a = pairs[i];
    const PosePair b = pairs[static_cast<size_t>(end[i])];
    // dT_est = T_c1^-1 T_c2 (translation scaled), dT_gt = T_m1^-1 T_m2, E_c = dT_gt^-1 dT_est.
    const Eigen::Matrix3d Re1 = a.T_W_B_est.R(), Re2 = b.T_W_B_est.R();
    const Eigen::Matrix3d Rg1 = a.T_W_B_gt.R(), Rg2 = b.T_W_B_gt.R();
    const Eigen::Matrix3d R_est = Re1.transpose() * Re2;
    const Eigen::Vector3d t_est = scale * (Re1.transpose() * (b.T_W_B_est.p - a.T_W_B_est.p));
    const Eigen::Matrix3d R_gt = Rg1.transpose() * Rg2;
    const Eigen::Vector3d t_gt = Rg1.transpose() * (b.T_W_B_gt.p - a.T_W_B_gt.p);
    const Eigen::Matrix3d R_c = R_gt.transpose() * R_est;
    const Eigen::Vector3d t_c = R_gt.transpose() * (t_est - t_gt);
    // E_w = Rot(T_c2) E_c Rot(T_c2)^-1, with T_c2 the raw estimate's end pose.
    const Eigen::Matrix3d Re2_raw = R_raw_aligned * Re2;
    const Eigen::Matrix3d R_w = Re2_raw * R_c * Re2_raw.transpose();
    const Eigen::Vector3d t_w = Re2_raw * t_c;
    const double tn = t_w.norm();
    // rpg compute_angle is arccos(clamp((trace - 1) / 2)); the same angle from atan2 (PoseErrors)
    // keeps its precision near 0, where arccos loses about 1e-8 rad.
    const double angle_deg = PoseErrors(R_w, t_w).rotation_deg;
    const EulerRpy ypr = EulerFromRotation(R_w);  // R = Rz(yaw) Ry(pitch) Rx(roll), rpg 'rzyx'
    if (keep_segments) {
      r.start_t_ns.push_back(a.t_ns);
      r.translation_percent.push_back(100.0 * tn / length_m);
      r.rotation_deg_per_m.push_back(angle_deg / length_m);
    }
    r.translation_m.push_back(tn);
    r.rotation_deg.push_back(angle_deg);
    r.yaw_deg.push_back(std::abs(ypr.yaw) * 180.0 / M_PI);
    r.tilt_deg.push_back(std::hypot(ypr.pitch, ypr.roll) * 180.0 / M_PI);
  }
  r.segments = r.translation_m.size();
  end = std::vector<long>();  // released before the statistics
  if (keep_segments) {
    r.translation_m_stats = ComputeStatistics(r.translation_m);
    r.translation_percent_stats = ComputeStatistics(r.translation_percent);
    r.rotation_deg_stats = ComputeStatistics(r.rotation_deg);
    r.rotation_deg_per_m_stats = ComputeStatistics(r.rotation_deg_per_m);
    r.yaw_deg_stats = ComputeStatistics(r.yaw_deg);
    r.tilt_deg_stats = ComputeStatistics(r.tilt_deg);
    return r;
  }
  std::tie(r.translation_m_stats, r.translation_percent_stats) = ComputeStatisticsWithImage(
      std::move(r.translation_m), [length_m](double tn) { return 100.0 * tn / length_m; });
  std::tie(r.rotation_deg_stats, r.rotation_deg_per_m_stats) = ComputeStatisticsWithImage(
      std::move(r.rotation_deg), [length_m](double angle) { return angle / length_m; });
  r.yaw_deg_stats = ComputeStatistics(std::move(r.yaw_deg));
  r.tilt_deg_stats = ComputeStatistics(std::move(r.tilt_deg));
  // Released (assigning {} would keep the capacity).
  for (auto* values : {&r.translation_m, &r.rotation_deg, &r.yaw_deg, &r.tilt_deg})
    *values = std::vector<double>();
  return r;
}

}  // namespace mavloc
