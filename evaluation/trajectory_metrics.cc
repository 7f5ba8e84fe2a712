#include "evaluation/trajectory_metrics.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/rotation.h"

namespace mavloc {

ErrorStatistics ComputeStatistics(const std::vector<double>& errors) {
  return ComputeStatistics(std::vector<double>(errors));
}

ErrorStatistics ComputeStatistics(std::vector<double>&& errors) {
  return ComputeStatisticsWithImage(std::move(errors), [](double e) { return e; }).first;
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

namespace {

// filter_pairs_by_index: all_pairs (i, i + d) for every i with i + d < n; else ids 0, d, 2d, ...
// < n and the pairs of consecutive ids.
template <typename Visit>
void ForEachFramePair(size_t n, const RpeDelta& delta, const Visit& visit) {
  const long d = std::lround(delta.delta);
  if (d <= 0) return;
  const size_t step = static_cast<size_t>(d);
  for (size_t i = 0; i + step < n; i += delta.all_pairs ? 1 : step) visit(i, i + step);
}

}  // namespace

std::vector<std::pair<size_t, size_t>> SelectRpePairs(const std::vector<Eigen::Vector3d>& positions,
                                                      const std::vector<double>& t_s,
                                                      const RpeDelta& delta) {
  std::vector<std::pair<size_t, size_t>> pairs;
  if (delta.unit == DeltaUnit::kFrames) {
    ForEachFramePair(positions.size(), delta,
                     [&pairs](size_t i, size_t j) { pairs.emplace_back(i, j); });
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

std::optional<RpeDeltaResult> ComputeRpeEvo(const PairedPoses& pairs, const RpeDelta& delta,
                                            bool keep_series) {
  std::vector<Eigen::Vector3d> positions;
  std::vector<double> t_s;
  if (delta.unit == DeltaUnit::kMetres) {
    positions.reserve(pairs.size());
    for (const auto& pair : pairs)
      positions.push_back(delta.pairs_from_reference ? pair.T_W_B_gt.p : pair.T_W_B_est.p);
  } else if (delta.unit == DeltaUnit::kSeconds) {
    t_s.reserve(pairs.size());
    const TimeNs t0_ns = pairs.t_ns(0);
    for (size_t i = 0; i < pairs.size(); ++i) t_s.push_back(NsToSeconds(pairs.t_ns(i) - t0_ns));
  }
  // Frames: the pairs (i, i + d) are visited without being listed (a list of 16-byte pairs for
  // every pose otherwise); metres and seconds: selected on the path or the stamps.
  const bool frames = delta.unit == DeltaUnit::kFrames;
  const std::vector<std::pair<size_t, size_t>> ids =
      frames ? std::vector<std::pair<size_t, size_t>>() : SelectRpePairs(positions, t_s, delta);
  positions = std::vector<Eigen::Vector3d>();  // released, not only cleared
  t_s = std::vector<double>();
  const auto for_each_pair = [&](const auto& visit) {
    if (frames) {
      ForEachFramePair(pairs.size(), delta, visit);
    } else {
      for (const auto& [i, j] : ids) visit(i, j);
    }
  };
  size_t count = 0;
  for_each_pair([&count](size_t, size_t) { ++count; });
  if (count == 0) return std::nullopt;
  // E = (Q_i^-1 Q_j)^-1 (P_i^-1 P_j), Q truth, P estimate (evo RPE.rpe_base). A pair read as the
  // end j is kept for the next start (consecutive pairs share it: ids 0, d, 2d, ...).
  size_t kept_index = pairs.size();
  PosePair kept;
  const auto read = [&](size_t k) {
    if (k != kept_index) kept = pairs[k];
    kept_index = k;
    return kept;
  };
  const auto rpe_error = [&read](const PosePair& pair_i, size_t j) {
    const PosePair pair_j = read(j);
    const Eigen::Matrix3d Rq_i = pair_i.T_W_B_gt.R(), Rq_j = pair_j.T_W_B_gt.R();
    const Eigen::Matrix3d Rp_i = pair_i.T_W_B_est.R(), Rp_j = pair_j.T_W_B_est.R();
    const Eigen::Matrix3d Rq = Rq_i.transpose() * Rq_j;
    const Eigen::Vector3d tq = Rq_i.transpose() * (pair_j.T_W_B_gt.p - pair_i.T_W_B_gt.p);
    const Eigen::Matrix3d Rp = Rp_i.transpose() * Rp_j;
    const Eigen::Vector3d tp = Rp_i.transpose() * (pair_j.T_W_B_est.p - pair_i.T_W_B_est.p);
    return PoseErrors(Rq.transpose() * Rp, Rq.transpose() * (tp - tq));
  };
  RpeDeltaResult result;
  result.delta = delta;
  if (keep_series) {
    result.t_ns.reserve(count);
    result.errors.reserve(count);
    for_each_pair([&](size_t i, size_t j) {
      const PosePair pair_i = read(i);
      result.t_ns.push_back(pair_i.t_ns);
      result.errors.push_back(rpe_error(pair_i, j));
    });
  }
  // From the kept errors, or computed again in each of the two passes.
  const PoseErrorStatistics statistics = StatisticsInTwoPasses(count, [&](const auto& sink) {
    if (keep_series) {
      for (const PoseErrorValues& e : result.errors) sink(e);
    } else {
      for_each_pair([&](size_t i, size_t j) { sink(rpe_error(read(i), j)); });
    }
  });
  result.translation_m = statistics.translation_m;
  result.rotation_deg = statistics.rotation_deg;
  result.rotation_part = statistics.rotation_part;
  result.full = statistics.full;
  return result;
}

}  // namespace mavloc
