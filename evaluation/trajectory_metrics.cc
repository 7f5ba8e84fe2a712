#include "evaluation/trajectory_metrics.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/rotation.h"

namespace mavloc {

ErrorStatistics ComputeStatistics(const std::vector<double>& errors) {
  // evo's PE.get_statistic: rmse = sqrt(mean(e^2)), sse = sum(e^2), numpy mean/median/std
  // (population, two-pass)/min/max.
  ErrorStatistics s;
  s.count = errors.size();
  if (errors.empty()) return s;
  double sum = 0.0, sum_sq = 0.0;
  s.min = errors.front();
  s.max = errors.front();
  for (double e : errors) {
    sum += e;
    sum_sq += e * e;
    s.min = std::min(s.min, e);
    s.max = std::max(s.max, e);
  }
  const double n = static_cast<double>(errors.size());
  s.mean = sum / n;
  s.sse = sum_sq;
  s.rmse = std::sqrt(sum_sq / n);
  double sum_dev_sq = 0.0;
  for (double e : errors) sum_dev_sq += (e - s.mean) * (e - s.mean);
  s.std = std::sqrt(sum_dev_sq / n);
  std::vector<double> sorted = errors;
  const size_t m = sorted.size() / 2;
  std::nth_element(sorted.begin(), sorted.begin() + m, sorted.end());
  s.median = sorted[m];
  if (sorted.size() % 2 == 0) {
    s.median = 0.5 * (*std::max_element(sorted.begin(), sorted.begin() + m) + s.median);
  }
  return s;
}

std::optional<PoseRelation> ParsePoseRelation(const std::string& name) {
  if (name == "trans_part" || name == "translation") return PoseRelation::kTranslation;
  if (name == "angle_deg" || name == "rotation") return PoseRelation::kRotationAngleDeg;
  if (name == "rot_part") return PoseRelation::kRotationPart;
  if (name == "full") return PoseRelation::kFull;
  return std::nullopt;
}

std::string PoseRelationName(PoseRelation relation) {
  switch (relation) {
    case PoseRelation::kTranslation:
      return "trans_part";
    case PoseRelation::kRotationAngleDeg:
      return "angle_deg";
    case PoseRelation::kRotationPart:
      return "rot_part";
    case PoseRelation::kFull:
      return "full";
  }
  return "trans_part";
}

std::optional<DeltaUnit> ParseDeltaUnit(const std::string& name) {
  if (name == "f" || name == "frames") return DeltaUnit::kFrames;
  if (name == "m" || name == "metres" || name == "meters") return DeltaUnit::kMetres;
  if (name == "s" || name == "seconds") return DeltaUnit::kSeconds;
  return std::nullopt;
}

std::string DeltaUnitName(DeltaUnit unit) {
  switch (unit) {
    case DeltaUnit::kFrames:
      return "frames";
    case DeltaUnit::kMetres:
      return "m";
    case DeltaUnit::kSeconds:
      return "s";
  }
  return "frames";
}

PoseErrorValues PoseErrors(const Eigen::Matrix3d& R_E, const Eigen::Vector3d& t_E) {
  PoseErrorValues e;
  e.translation_m = t_E.norm();
  // Rotation angle from the trace, clamped (evo: norm of scipy's rotvec; equal for a rotation).
  const double c = std::clamp(0.5 * (R_E.trace() - 1.0), -1.0, 1.0);
  // acos loses precision near 0: use atan2 of |vee(R - R^T)| / 2 = sin(angle) and cos(angle).
  const Eigen::Vector3d s(R_E(2, 1) - R_E(1, 2), R_E(0, 2) - R_E(2, 0), R_E(1, 0) - R_E(0, 1));
  e.rotation_deg = std::atan2(0.5 * s.norm(), c) * 180.0 / M_PI;
  const double rot_part_sq = (R_E - Eigen::Matrix3d::Identity()).squaredNorm();
  e.rotation_part = std::sqrt(rot_part_sq);
  e.full = std::sqrt(rot_part_sq + t_E.squaredNorm());  // the bottom row of E - I_4 is zero
  return e;
}

std::vector<std::pair<size_t, size_t>> SelectRpePairs(const std::vector<Eigen::Vector3d>& positions,
                                                      const std::vector<double>& t_s,
                                                      const RpeDelta& delta) {
  std::vector<std::pair<size_t, size_t>> pairs;
  if (delta.unit == DeltaUnit::kFrames) {
    const long d = std::lround(delta.delta);
    const size_t n = positions.size();
    if (d <= 0) return pairs;
    const size_t step = static_cast<size_t>(d);
    if (delta.all_pairs) {
      // filter_pairs_by_index, all_pairs: (i, i + d) for i + d < n.
      for (size_t i = 0; i + step < n; ++i) pairs.emplace_back(i, i + step);
    } else {
      // ids = 0, d, 2d, ... < n; consecutive ids.
      for (size_t i = 0; i + step < n; i += step) pairs.emplace_back(i, i + step);
    }
    return pairs;
  }
  // Metres (path length) or seconds (time): increments and their running sum (numpy.cumsum).
  const size_t n = delta.unit == DeltaUnit::kMetres ? positions.size() : t_s.size();
  if (n < 2 || !(delta.delta > 0)) return pairs;
  std::vector<double> increment(n, 0.0), s(n, 0.0);
  for (size_t i = 1; i < n; ++i) {
    increment[i] = delta.unit == DeltaUnit::kMetres ? (positions[i] - positions[i - 1]).norm()
                                                    : t_s[i] - t_s[i - 1];
    s[i] = s[i - 1] + increment[i];
  }
  if (delta.all_pairs) {
    // filter_pairs_by_path, all_pairs: for each i < n - 1 the j > i minimising
    // |s_j - s_i - delta| (first on ties, numpy.argmin), kept when within tol = rel_tol * delta.
    // s is non-decreasing, so |s_j - s_i - delta| is minimised around the first j with
    // s_j - s_i >= delta: a forward-moving pointer finds it in linear time overall.
    const double tol = delta.rel_delta_tol * delta.delta;
    std::vector<size_t> plateau_start(n, 0);
    for (size_t j = 1; j < n; ++j) plateau_start[j] = s[j] == s[j - 1] ? plateau_start[j - 1] : j;
    size_t k = 1;
    for (size_t i = 0; i + 1 < n; ++i) {
      k = std::max(k, i + 1);
      while (k < n && s[k] - s[i] < delta.delta) ++k;
      // Candidates: k - 1 (last below, if > i) and k (first at or above); among equal values of
      // s the first index wins, as numpy.argmin does.
      size_t best = n;
      double best_err = std::numeric_limits<double>::infinity();
      auto consider = [&](size_t j) {
        if (j <= i || j >= n) return;
        // The first index with the same abscissa value (plateaus: the trajectory stood still).
        const size_t first = std::max(plateau_start[j], i + 1);
        const double err = std::abs(s[first] - s[i] - delta.delta);
        if (err < best_err || (err == best_err && first < best)) {
          best_err = err;
          best = first;
        }
      };
      if (k > i + 1) consider(k - 1);
      consider(k);
      if (best < n && best_err <= tol) pairs.emplace_back(i, best);
    }
  } else {
    // filter_pairs_by_path, consecutive: the path is accumulated from pose 0 and an index is kept
    // each time it reaches delta (then the count restarts at that index); pairs of successive kept
    // indices. Note that pose 0 is not kept unless delta <= 0.
    std::vector<size_t> ids;
    double current = 0.0;
    for (size_t i = 0; i < n; ++i) {
      current += increment[i];
      if (current >= delta.delta) {
        ids.push_back(i);
        current = 0.0;
      }
    }
    for (size_t k = 0; k + 1 < ids.size(); ++k) pairs.emplace_back(ids[k], ids[k + 1]);
  }
  return pairs;
}

std::optional<RpeDeltaResult> ComputeRpeEvo(const std::vector<PosePair>& pairs,
                                            const RpeDelta& delta) {
  std::vector<Eigen::Vector3d> positions;
  std::vector<double> t_s;
  if (delta.unit == DeltaUnit::kMetres) {
    positions.reserve(pairs.size());
    for (const auto& pair : pairs)
      positions.push_back(delta.pairs_from_reference ? pair.T_W_B_gt.p : pair.T_W_B_est.p);
  } else if (delta.unit == DeltaUnit::kSeconds) {
    t_s.reserve(pairs.size());
    for (const auto& pair : pairs) t_s.push_back(NsToSeconds(pair.t_ns - pairs.front().t_ns));
  } else {
    positions.resize(pairs.size());  // only the count is used
  }
  const auto ids = SelectRpePairs(positions, t_s, delta);
  if (ids.empty()) return std::nullopt;
  RpeDeltaResult result;
  result.delta = delta;
  result.t_ns.reserve(ids.size());
  result.errors.reserve(ids.size());
  std::vector<double> translation, rotation, rotation_part, full;
  translation.reserve(ids.size());
  rotation.reserve(ids.size());
  rotation_part.reserve(ids.size());
  full.reserve(ids.size());
  for (const auto& [i, j] : ids) {
    // E = (Q_i^-1 Q_j)^-1 (P_i^-1 P_j), Q truth, P estimate (evo RPE.rpe_base).
    const Eigen::Matrix3d Rq_i = pairs[i].T_W_B_gt.R(), Rq_j = pairs[j].T_W_B_gt.R();
    const Eigen::Matrix3d Rp_i = pairs[i].T_W_B_est.R(), Rp_j = pairs[j].T_W_B_est.R();
    const Eigen::Matrix3d Rq = Rq_i.transpose() * Rq_j;
    const Eigen::Vector3d tq = Rq_i.transpose() * (pairs[j].T_W_B_gt.p - pairs[i].T_W_B_gt.p);
    const Eigen::Matrix3d Rp = Rp_i.transpose() * Rp_j;
    const Eigen::Vector3d tp = Rp_i.transpose() * (pairs[j].T_W_B_est.p - pairs[i].T_W_B_est.p);
    const PoseErrorValues e = PoseErrors(Rq.transpose() * Rp, Rq.transpose() * (tp - tq));
    result.t_ns.push_back(pairs[i].t_ns);
    result.errors.push_back(e);
    translation.push_back(e.translation_m);
    rotation.push_back(e.rotation_deg);
    rotation_part.push_back(e.rotation_part);
    full.push_back(e.full);
  }
  result.translation_m = ComputeStatistics(translation);
  result.rotation_deg = ComputeStatistics(rotation);
  result.rotation_part = ComputeStatistics(rotation_part);
  result.full = ComputeStatistics(full);
  return result;
}

}  // namespace mavloc
