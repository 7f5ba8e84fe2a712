#include "solver/board/pnp_initial_state.h"

#include <Eigen/QR>
#include <cmath>

namespace mavloc {

std::optional<PnpInitialState> InitialStateFromPoses(const std::vector<StampedPose>& T_W_B,
                                                     double fit_s) {
  if (T_W_B.empty()) return std::nullopt;
  PnpInitialState out;
  const StampedPose& last = T_W_B.back();
  out.t_ns = last.t_ns;
  out.T_W_B = last.T_W_B;
  std::vector<const StampedPose*> used;
  for (const StampedPose& pose : T_W_B) {
    if (NsToSeconds(last.t_ns - pose.t_ns) <= fit_s) used.push_back(&pose);
  }
  out.num_poses_fitted = static_cast<int>(used.size());
  if (used.size() < 2) return out;
  const int degree = used.size() >= 3 ? 2 : 1;
  Eigen::MatrixXd A(used.size(), degree + 1);
  Eigen::MatrixXd b(used.size(), 3);
  for (size_t i = 0; i < used.size(); ++i) {
    const double t = NsToSeconds(used[i]->t_ns - last.t_ns);
    for (int k = 0; k <= degree; ++k) A(i, k) = std::pow(t, k);
    b.row(i) = used[i]->T_W_B.p.transpose();
  }
  const Eigen::MatrixXd coefficients = A.colPivHouseholderQr().solve(b);
  out.v_W = coefficients.row(1).transpose();
  return out;
}

}  // namespace mavloc
