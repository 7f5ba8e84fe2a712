#include "evaluation/association.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/rotation.h"

namespace mavloc {

namespace {

// For stamp t in sorted stamps: index i of the last stamp <= t (or -1), for bracketing.
long Bracket(const std::vector<TimeNs>& stamps, TimeNs t) {
  const auto it = std::upper_bound(stamps.begin(), stamps.end(), t);
  return static_cast<long>(it - stamps.begin()) - 1;
}

struct Interpolant {
  long i = -1;     // lower node
  long j = -1;     // upper node (== i for an exact or nearest match)
  double a = 0.0;  // weight of node j
};

std::optional<Interpolant> Locate(const std::vector<TimeNs>& stamps, TimeNs t, double max_dt_s,
                                  AssociationMode mode) {
  if (stamps.empty()) return std::nullopt;
  const TimeNs max_dt_ns = SecondsToNs(max_dt_s);
  const long i = Bracket(stamps, t);
  const long n = static_cast<long>(stamps.size());
  if (mode == AssociationMode::kNearest) {
    long best = -1;
    TimeNs best_dt = std::numeric_limits<TimeNs>::max();
    for (long k : {i, i + 1}) {
      if (k < 0 || k >= n) continue;
      const TimeNs dt = std::llabs(stamps[k] - t);
      if (dt < best_dt) {
        best_dt = dt;
        best = k;
      }
    }
    if (best < 0 || best_dt > max_dt_ns) return std::nullopt;
    return Interpolant{best, best, 0.0};
  }
  if (i < 0) return std::nullopt;  // before the first stamp
  if (stamps[i] == t) return Interpolant{i, i, 0.0};
  if (i + 1 >= n) return std::nullopt;  // after the last stamp
  const TimeNs gap_low = t - stamps[i], gap_high = stamps[i + 1] - t;
  if (std::min(gap_low, gap_high) > max_dt_ns) return std::nullopt;
  return Interpolant{i, i + 1,
                     static_cast<double>(gap_low) / static_cast<double>(stamps[i + 1] - stamps[i])};
}

}  // namespace

std::vector<PosePair> AssociatePoses(const std::vector<StampedPose>& estimate,
                                     const std::vector<StampedPose>& ground_truth, double max_dt_s,
                                     AssociationMode mode) {
  std::vector<TimeNs> stamps;
  stamps.reserve(ground_truth.size());
  for (const auto& pose : ground_truth) stamps.push_back(pose.t_ns);
  std::vector<PosePair> pairs;
  for (const auto& est : estimate) {
    const auto at = Locate(stamps, est.t_ns, max_dt_s, mode);
    if (!at) continue;
    const Pose& a = ground_truth[at->i].T_W_B;
    const Pose& b = ground_truth[at->j].T_W_B;
    Pose gt;
    gt.p = (1.0 - at->a) * a.p + at->a * b.p;
    gt.q = a.q.slerp(at->a, b.q).normalized();
    pairs.push_back({est.t_ns, est.T_W_B, gt});
  }
  return pairs;
}

namespace {

// Index of the nearest stamp of sorted `stamps` to t (first one on a tie), starting the search at
// *cursor, which only moves forward (t non-decreasing across calls): numpy.argmin(|stamps - t|).
size_t NearestForward(const std::vector<TimeNs>& stamps, TimeNs t, size_t* cursor) {
  size_t k = *cursor;
  // First index with stamps[k] >= t.
  while (k < stamps.size() && stamps[k] < t) ++k;
  *cursor = k == 0 ? 0 : k - 1;  // the next query (>= t) can still need k - 1
  if (k == stamps.size()) {
    // All stamps below t: the last one, or the first of a run of equal last stamps.
    size_t j = stamps.size() - 1;
    while (j > 0 && stamps[j - 1] == stamps[j]) --j;
    return j;
  }
  if (k == 0) return 0;
  // Candidates: k - 1 (below, the first of its equal run) and k (at or above).
  size_t below = k - 1;
  while (below > 0 && stamps[below - 1] == stamps[below]) --below;
  return t - stamps[below] <= stamps[k] - t ? below : k;
}

}  // namespace

PairedPoses AssociatePairs(const std::vector<StampedPose>& estimate,
                           const std::vector<StampedPose>& truth,
                           const AssociationOptions& options) {
  const bool interpolate = options.mode == AssociationMode::kInterpolate;
  const TimeNs offset_ns = SecondsToNs(options.time_offset_s);
  PairedPoses pairs(estimate, truth, offset_ns, interpolate);
  if (estimate.empty() || truth.empty()) return pairs;
  const TimeNs max_dt_ns = SecondsToNs(options.max_dt_s);
  std::vector<TimeNs> est_t(estimate.size()), gt_t(truth.size());
  for (size_t i = 0; i < estimate.size(); ++i) est_t[i] = estimate[i].t_ns + offset_ns;
  for (size_t i = 0; i < truth.size(); ++i) gt_t[i] = truth[i].t_ns;
  pairs.Reserve(std::min(estimate.size(), truth.size()));

  if (!interpolate) {
    // evo: snd_longer = len(est) > len(ref); the shorter one is walked.
    const bool walk_truth = estimate.size() > truth.size();
    const auto& walked = walk_truth ? gt_t : est_t;
    const auto& searched = walk_truth ? est_t : gt_t;
    size_t cursor = 0;
    for (size_t w = 0; w < walked.size(); ++w) {
      const size_t s = NearestForward(searched, walked[w], &cursor);
      const TimeNs dt = walked[w] > searched[s] ? walked[w] - searched[s] : searched[s] - walked[w];
      if (dt > max_dt_ns) continue;
      pairs.Add(walk_truth ? s : w, walk_truth ? w : s);
    }
    return pairs;
  }

  // Interpolation: bracket each estimate stamp with a forward-moving index; the pair keeps the
  // lower node (the truth sample itself on an exact stamp).
  size_t k = 0;  // first truth stamp >= t
  for (size_t ie = 0; ie < est_t.size(); ++ie) {
    const TimeNs t = est_t[ie];
    while (k < gt_t.size() && gt_t[k] < t) ++k;
    if (k == gt_t.size()) break;  // after the last truth stamp
    if (gt_t[k] == t) {
      pairs.Add(ie, k);
      continue;
    }
    if (k == 0) continue;  // before the first truth stamp
    const TimeNs gap_low = t - gt_t[k - 1], gap_high = gt_t[k] - t;
    if (std::min(gap_low, gap_high) > max_dt_ns) continue;
    pairs.Add(ie, k - 1);
  }
  return pairs;
}

AssociationResult AssociateTrajectories(const std::vector<StampedPose>& estimate,
                                        const std::vector<StampedPose>& truth,
                                        const AssociationOptions& options) {
  AssociationResult out;
  const PairedPoses pairs = AssociatePairs(estimate, truth, options);
  const bool make_pairs = options.make_pairs || options.mode != AssociationMode::kNearest;
  const bool make_indices = options.make_indices || !make_pairs;
  if (make_pairs) {
    out.pairs.reserve(pairs.size());
    for (const PosePair& pair : pairs) out.pairs.push_back(pair);
  }
  if (make_indices) {
    out.estimate_index.reserve(pairs.size());
    out.truth_index.reserve(pairs.size());
    for (size_t i = 0; i < pairs.size(); ++i) {
      out.estimate_index.push_back(pairs.estimate_index(i));
      out.truth_index.push_back(pairs.truth_index(i));
    }
  }
  return out;
}

QuantityTable TruthQuantitiesAt(const QuantityTable& truth, const std::vector<TimeNs>& t_ns,
                                double max_dt_s, AssociationMode mode) {
  QuantityTable out(truth.names, truth.units);
  for (const TimeNs t : t_ns) {
    const auto at = Locate(truth.t_ns, t, max_dt_s, mode);
    if (!at) continue;
    std::vector<double> row(truth.names.size());
    for (size_t k = 0; k < truth.names.size(); ++k) {
      const double va = truth.rows[at->i][k], vb = truth.rows[at->j][k];
      if (IsAngleUnit(truth.units[k])) {
        row[k] = WrapAngle(va + at->a * WrapAngle(vb - va));  // along the shorter arc
      } else {
        row[k] = (1.0 - at->a) * va + at->a * vb;
      }
    }
    out.Append(t, row);
  }
  return out;
}

QuantityTable GroundTruthQuantities(const Dataset& dataset) {
  // Velocity and biases are reported only when the ground truth carries them (a TUM file has no
  // velocity: all zero).
  bool has_velocity = false, has_biases = false;
  for (const auto& s : dataset.ground_truth) {
    has_velocity |= !s.v_W.isZero(0.0);
    has_biases |= !s.b_g.isZero(0.0) || !s.b_a.isZero(0.0);
  }
  std::vector<std::string> names = PoseQuantityNames(has_velocity);
  if (has_biases) names.insert(names.end(), {"bgx", "bgy", "bgz", "bax", "bay", "baz"});
  QuantityTable table = MakeQuantityTable(names);
  for (const auto& s : dataset.ground_truth) {
    std::vector<double> row =
        PoseQuantityValues(s.T_W_B, has_velocity ? std::optional(s.v_W) : std::nullopt);
    if (has_biases)
      row.insert(row.end(), {s.b_g.x(), s.b_g.y(), s.b_g.z(), s.b_a.x(), s.b_a.y(), s.b_a.z()});
    table.Append(s.t_ns, row);
  }
  return table;
}

std::vector<StampedPose> GroundTruthPoses(const Dataset& dataset) {
  std::vector<StampedPose> poses;
  poses.reserve(dataset.ground_truth.size());
  for (const auto& s : dataset.ground_truth) poses.push_back({s.t_ns, s.T_W_B});
  return poses;
}

}  // namespace mavloc
