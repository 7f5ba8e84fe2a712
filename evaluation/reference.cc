#include "evaluation/reference.h"

namespace mavloc {

std::string ComparisonReference::Describe() const {
  switch (kind) {
    case Kind::kEstimator:
      return "estimator '" + name + "'";
    case Kind::kTrajectoryFile:
      return "trajectory file '" + name + "'";
    case Kind::kLogTopic:
      break;
  }
  return "log topic '" + name + "'";
}

ComparisonReference ReferenceFromEstimate(const std::string& estimator_name,
                                          const Estimate& estimate) {
  ComparisonReference reference;
  reference.kind = ComparisonReference::Kind::kEstimator;
  reference.name = estimator_name;
  reference.quantities = estimate.quantities;
  reference.poses = estimate.poses;
  return reference;
}

ComparisonReference ReferenceFromTrajectory(const std::string& path,
                                            const std::vector<GroundTruthState>& states) {
  ComparisonReference reference;
  reference.kind = ComparisonReference::Kind::kTrajectoryFile;
  reference.name = path;
  bool with_velocity = false;
  for (const auto& s : states) with_velocity = with_velocity || !s.v_W.isZero();
  reference.quantities = MakeQuantityTable(PoseQuantityNames(with_velocity));
  for (const auto& s : states) {
    reference.quantities.Append(
        s.t_ns, PoseQuantityValues(s.T_W_B, with_velocity ? std::optional(s.v_W) : std::nullopt));
    reference.poses.push_back({s.t_ns, s.T_W_B});
  }
  return reference;
}

ComparisonReference ReferenceFromLogTrajectory(const std::string& spec,
                                               const LogTrajectory& trajectory) {
  ComparisonReference reference;
  reference.kind = ComparisonReference::Kind::kLogTopic;
  reference.name = spec;
  // PoseQuantityValues order: x y z roll pitch yaw [vx vy vz].
  const std::vector<std::string> all = PoseQuantityNames(trajectory.has_velocity);
  std::vector<size_t> kept;
  for (size_t i = 0; i < all.size(); ++i) {
    const bool position = i < 3, attitude = i >= 3 && i < 6;
    if ((position && !trajectory.has_position) || (attitude && !trajectory.has_attitude)) continue;
    kept.push_back(i);
  }
  std::vector<std::string> names;
  for (size_t i : kept) names.push_back(all[i]);
  reference.quantities = MakeQuantityTable(names);
  const bool full_pose = trajectory.has_position && trajectory.has_attitude;
  for (const auto& s : trajectory.states) {
    const auto values =
        PoseQuantityValues(s.T_W_B, trajectory.has_velocity ? std::optional(s.v_W) : std::nullopt);
    std::vector<double> row;
    for (size_t i : kept) row.push_back(values[i]);
    reference.quantities.Append(s.t_ns, row);
    if (full_pose) reference.poses.push_back({s.t_ns, s.T_W_B});
  }
  return reference;
}

}  // namespace mavloc
