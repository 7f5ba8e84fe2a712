#include "solver/estimators/imu_dead_reckoning.h"

#include <algorithm>
#include <cmath>

#include "solver/imu/imu_integrator.h"

namespace mavloc {

ImuDeadReckoning::ImuDeadReckoning(const EstimatorOptions& options)
    : output_rate_hz_(options.GetDouble("rate_hz", 50.0)) {}

namespace {

// A ground truth read from a pose-only file (TUM, an 8-column EuRoC CSV) has v_W = 0 in every row
// although the body moves: starting from zero velocity would be silently wrong, so it is refused.
bool GroundTruthLacksVelocity(const std::vector<GroundTruthState>& truth) {
  bool moves = false;
  for (const auto& s : truth) {
    if (s.v_W != Eigen::Vector3d::Zero()) return false;
    moves = moves || (s.T_W_B.p - truth.front().T_W_B.p).norm() > 0.01;
  }
  return moves;
}

}  // namespace

Applicability ImuDeadReckoning::AppliesTo(const Dataset& dataset) const {
  if (dataset.imu.samples.size() < 2) return Applicability::No("needs imu0 samples");
  if (dataset.ground_truth.empty())
    return Applicability::No("needs ground truth for the initial state");
  if (GroundTruthLacksVelocity(dataset.ground_truth))
    return Applicability::No(
        "the ground truth has no velocity (a pose-only file: zero in every row while the body "
        "moves); dead reckoning starts from the true velocity");
  const TimeNs t0 = dataset.ground_truth.front().t_ns;
  if (t0 < dataset.imu.samples.front().t_ns || t0 >= dataset.imu.samples.back().t_ns)
    return Applicability::No("ground truth starts outside the IMU stream");
  return Applicability::Yes();
}

Estimate ImuDeadReckoning::Run(const Dataset& dataset) {
  Estimate estimate;
  estimate.quantities = MakeQuantityTable(PoseQuantityNames(/*with_velocity=*/true));
  const GroundTruthState& gt0 = dataset.ground_truth.front();
  NavState state;
  state.t_ns = gt0.t_ns;
  state.q_W_B = gt0.T_W_B.q;
  state.p_W = gt0.T_W_B.p;
  state.v_W = gt0.v_W;
  const ImuBiases biases{gt0.b_g, gt0.b_a};
  const ImuIntegrator integrator(&dataset.imu.samples);

  const TimeNs step_ns = SecondsToNs(1.0 / std::max(output_rate_hz_, 1e-3));
  const TimeNs t_end = dataset.imu.samples.back().t_ns;
  TimeNs next_output = state.t_ns;
  auto record = [&](const NavState& x) {
    const Pose T_W_B(x.q_W_B, x.p_W);
    estimate.quantities.Append(x.t_ns, PoseQuantityValues(T_W_B, x.v_W));
    estimate.poses.push_back({x.t_ns, T_W_B});
  };
  record(state);
  next_output += step_ns;
  while (next_output <= t_end) {
    state = integrator.Integrate(state, next_output, biases);
    record(state);
    next_output += step_ns;
  }
  return estimate;
}

}  // namespace mavloc
