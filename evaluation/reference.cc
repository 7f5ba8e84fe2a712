#include "evaluation/reference.h"

namespace mavloc {

std::string ComparisonReference::Describe() const {
  return (kind == Kind::kEstimator ? "estimator '" : "trajectory file '") + name + "'";
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

}  // namespace mavloc
