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

namespace {

// The quantities a trajectory carries (x y z, roll pitch yaw, vx vy vz, in PoseQuantityValues'
// order) and its poses for the ATE when it carries both position and attitude.
ComparisonReference ReferenceFromStates(ComparisonReference::Kind kind, const std::string& name,
                                        const std::vector<GroundTruthState>& states,
                                        bool has_position, bool has_attitude, bool has_velocity) {
  ComparisonReference reference;
  reference.kind = kind;
  reference.name = name;
  const std::vector<std::string> all = PoseQuantityNames(has_velocity);
  std::vector<size_t> kept;
  for (size_t i = 0; i < all.size(); ++i) {
    const bool position = i < 3, attitude = i >= 3 && i < 6;
    if ((position && !has_position) || (attitude && !has_attitude)) continue;
    kept.push_back(i);
  }
  std::vector<std::string> names;
  for (size_t i : kept) names.push_back(all[i]);
  reference.quantities = MakeQuantityTable(names);
  for (const auto& s : states) {
    const auto values =
        PoseQuantityValues(s.T_W_B, has_velocity ? std::optional(s.v_W) : std::nullopt);
    std::vector<double> row;
    for (size_t i : kept) row.push_back(values[i]);
    reference.quantities.Append(s.t_ns, row);
    if (has_position && has_attitude) reference.poses.push_back({s.t_ns, s.T_W_B});
  }
  return reference;
}

}  // namespace

ComparisonReference ReferenceFromTrajectory(const std::string& path,
                                            const std::vector<GroundTruthState>& states) {
  bool with_velocity = false;
  for (const auto& s : states) with_velocity = with_velocity || !s.v_W.isZero();
  return ReferenceFromStates(ComparisonReference::Kind::kTrajectoryFile, path, states, true, true,
                             with_velocity);
}

ComparisonReference ReferenceFromLogTrajectory(const std::string& spec,
                                               const LogTrajectory& trajectory) {
  return ReferenceFromStates(ComparisonReference::Kind::kLogTopic, spec, trajectory.states,
                             trajectory.has_position, trajectory.has_attitude,
                             trajectory.has_velocity);
}

}  // namespace mavloc
