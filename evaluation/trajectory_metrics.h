// The error statistics and the APE/RPE building blocks of the one trajectory-error engine
// (trajectory_evaluation.h), as evo computes them (Sturm et al., IROS 2012; Zhang & Scaramuzza,
// IROS 2018): the pose relations of a relative transform E, the RPE pair selection, and the RPE
// over the selected pairs E = (T_gt,i^-1 T_gt,j)^-1 (T_est,i^-1 T_est,j).
#pragma once

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "evaluation/alignment.h"
#include "evaluation/association.h"

namespace mavloc {

struct ErrorStatistics {
  double rmse = 0.0;
  double mean = 0.0;
  double median = 0.0;
  double std = 0.0;  // population standard deviation
  double min = 0.0;
  double max = 0.0;
  double sse = 0.0;  // sum of squared errors (evo's "sse")
  size_t count = 0;
};

// Statistics of a set of non-negative errors (all zero for an empty set, with count 0).
ErrorStatistics ComputeStatistics(const std::vector<double>& errors);
// The same, taking the values (their order is lost: the median is found in place, no copy).
ErrorStatistics ComputeStatistics(std::vector<double>&& errors);

// The statistics of the values and of their image f(e_i) (f non-decreasing, e.g. a division by a
// positive length), without storing the image: the same bits as ComputeStatistics of each series.
// The sums run over the values in their order; the image's order statistics are f of the values'
// (for a non-decreasing f the k-th smallest f(e) is f of the k-th smallest e, ties included).
// The values' order is lost.
template <typename F>
std::pair<ErrorStatistics, ErrorStatistics> ComputeStatisticsWithImage(std::vector<double>&& errors,
                                                                       F f);

// ---- evo's APE/RPE (evo/core/metrics.py), used by trajectory_evaluation.h -----------------------

// evo's PoseRelation (the point_distance relations are not offered).
enum class PoseRelation { kTranslation, kRotationAngleDeg, kRotationPart, kFull };
std::optional<PoseRelation> ParsePoseRelation(
    const std::string& name);  // evo's names: trans_part,
                               // angle_deg, rot_part, full
std::string PoseRelationName(PoseRelation relation);

// The four error values of one relative transform E (see trajectory_evaluation.h):
// ||t(E)||, |angle(R(E))| in degrees, ||R(E) - I||_F, ||E - I_4||_F.
struct PoseErrorValues {
  double translation_m = 0.0;
  double rotation_deg = 0.0;
  double rotation_part = 0.0;
  double full = 0.0;
};
// E given as a rotation matrix and translation (the rotation is used as given, so that a scaled or
// non-orthonormal input reproduces evo's matrix arithmetic).
PoseErrorValues PoseErrors(const Eigen::Matrix3d& R_E, const Eigen::Vector3d& t_E);

// The statistics of the four error series that `produce` gives: produce(sink) calls
// sink(PoseErrorValues) once per element, in the same order every time. Two passes of two series
// each (half the memory of the four series at once, for twice the error arithmetic); the same
// statistics as ComputeStatistics of each series.
struct PoseErrorStatistics {
  ErrorStatistics translation_m;
  ErrorStatistics rotation_deg;
  ErrorStatistics rotation_part;
  ErrorStatistics full;
};
template <typename Produce>
PoseErrorStatistics StatisticsInTwoPasses(size_t count, const Produce& produce);

enum class DeltaUnit { kFrames, kMetres, kSeconds };
std::optional<DeltaUnit> ParseDeltaUnit(const std::string& name);  // f|frames, m|metres, s|seconds
std::string DeltaUnitName(DeltaUnit unit);

struct RpeDelta {
  double delta = 1.0;  // frames (integer), metres or seconds
  DeltaUnit unit = DeltaUnit::kFrames;
  bool all_pairs = false;
  double rel_delta_tol = 0.1;  // evo's rel_delta_tol (all_pairs with metres or seconds)
  // evo_rpe --pairs_from_reference: select pairs on the truth's path instead of the (aligned)
  // estimate's, evo's default. Only matters for metres.
  bool pairs_from_reference = false;
};

// Index pairs (i, j), i < j, into a sequence of poses / stamps, as evo/core/filters.py selects them
// (filter_pairs_by_index, filter_pairs_by_path; rules in trajectory_evaluation.h). positions: the
// path the pairs are chosen on (evo: the aligned estimate, or the truth with
// pairs_from_reference); t_s: the pairs' stamps in seconds, used as the abscissa for seconds (evo
// has no seconds unit: mavloc's seconds are filter_pairs_by_path with time in place of path).
std::vector<std::pair<size_t, size_t>> SelectRpePairs(const std::vector<Eigen::Vector3d>& positions,
                                                      const std::vector<double>& t_s,
                                                      const RpeDelta& delta);

struct RpeDeltaResult {
  RpeDelta delta;
  ErrorStatistics translation_m;
  ErrorStatistics rotation_deg;
  ErrorStatistics rotation_part;
  ErrorStatistics full;
  // Per selected pair: stamp of the first pose and the four errors (for plots over time).
  std::vector<TimeNs> t_ns;
  std::vector<PoseErrorValues> errors;
};

// RPE of the pairs (with the estimate already scaled by alignment.scale when Sim3, as evo does).
// nullopt when the delta selects no pair.
// keep_series false leaves t_ns and errors empty (the statistics alone).
std::optional<RpeDeltaResult> ComputeRpeEvo(const PairedPoses& pairs, const RpeDelta& delta,
                                            bool keep_series = true);

// ---- template definitions -----------------------------------------------------------------------

// evo's PE.get_statistic: rmse = sqrt(mean(e^2)), sse = sum(e^2), numpy mean/median/std
// (population, two-pass)/min/max; numpy.median: the middle value, or the mean of the two middle
// values for an even count.
template <typename F>
std::pair<ErrorStatistics, ErrorStatistics> ComputeStatisticsWithImage(std::vector<double>&& errors,
                                                                       F f) {
  ErrorStatistics s, t;
  s.count = t.count = errors.size();
  if (errors.empty()) return {s, t};
  double sum = 0.0, sum_sq = 0.0, sum_f = 0.0, sum_sq_f = 0.0;
  for (double e : errors) {
    const double fe = f(e);
    sum += e;
    sum_sq += e * e;
    sum_f += fe;
    sum_sq_f += fe * fe;
  }
  const double n = static_cast<double>(errors.size());
  s.mean = sum / n;
  s.sse = sum_sq;
  s.rmse = std::sqrt(sum_sq / n);
  t.mean = sum_f / n;
  t.sse = sum_sq_f;
  t.rmse = std::sqrt(sum_sq_f / n);
  double sum_dev_sq = 0.0, sum_dev_sq_f = 0.0;
  for (double e : errors) {
    const double fe = f(e);
    sum_dev_sq += (e - s.mean) * (e - s.mean);
    sum_dev_sq_f += (fe - t.mean) * (fe - t.mean);
  }
  s.std = std::sqrt(sum_dev_sq / n);
  t.std = std::sqrt(sum_dev_sq_f / n);
  s.min = *std::min_element(errors.begin(), errors.end());
  s.max = *std::max_element(errors.begin(), errors.end());
  t.min = f(s.min);
  t.max = f(s.max);
  const size_t m = errors.size() / 2;
  std::nth_element(errors.begin(), errors.begin() + m, errors.end());
  const double upper = errors[m];
  s.median = upper;
  t.median = f(upper);
  if (errors.size() % 2 == 0) {
    const double lower = *std::max_element(errors.begin(), errors.begin() + m);
    s.median = 0.5 * (lower + upper);
    t.median = 0.5 * (f(lower) + f(upper));
  }
  return {s, t};
}

template <typename Produce>
PoseErrorStatistics StatisticsInTwoPasses(size_t count, const Produce& produce) {
  PoseErrorStatistics out;
  std::vector<double> a, b;
  a.reserve(count);
  b.reserve(count);
  produce([&a, &b](const PoseErrorValues& e) {
    a.push_back(e.translation_m);
    b.push_back(e.rotation_deg);
  });
  out.translation_m = ComputeStatistics(std::move(a));
  out.rotation_deg = ComputeStatistics(std::move(b));
  a.clear();  // the capacity serves the second pass
  b.clear();
  produce([&a, &b](const PoseErrorValues& e) {
    a.push_back(e.rotation_part);
    b.push_back(e.full);
  });
  out.rotation_part = ComputeStatistics(std::move(a));
  out.full = ComputeStatistics(std::move(b));
  return out;
}

}  // namespace mavloc
