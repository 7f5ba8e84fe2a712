// The error statistics and the APE/RPE building blocks of the one trajectory-error engine
// (trajectory_evaluation.h), as evo computes them (Sturm et al., IROS 2012; Zhang & Scaramuzza,
// IROS 2018): the pose relations of a relative transform E, the RPE pair selection, and the RPE
// over the selected pairs E = (T_gt,i^-1 T_gt,j)^-1 (T_est,i^-1 T_est,j).
#pragma once

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
std::optional<RpeDeltaResult> ComputeRpeEvo(const std::vector<PosePair>& pairs,
                                            const RpeDelta& delta);

}  // namespace mavloc
