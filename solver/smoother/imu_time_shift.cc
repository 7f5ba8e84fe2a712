#include "solver/smoother/imu_time_shift.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "core/rotation.h"

namespace mavloc {

namespace {

constexpr int kNodes = 10;

}  // namespace

void IntegrateImuTimeShift(const std::vector<ImuSample>& samples, TimeNs t_ns,
                           const ImuBiases& biases, double tau_s, Eigen::Quaterniond* dq,
                           Eigen::Vector3d* dp) {
  const ImuIntegrator integrator(&samples);
  const TimeNs t_other = t_ns + SecondsToNs(tau_s);
  const double tau = NsToSeconds(t_other - t_ns);
  const Eigen::Vector3d g = GravityW();
  // The integrator adds g_W as a constant vector to the acceleration: starting from the identity,
  // v = dv + g s and p = dp + g s^2 / 2 over a duration s, whatever the rotation.
  if (tau >= 0.0) {
    const NavState x = integrator.Integrate(
        {t_ns, Eigen::Quaterniond::Identity(), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()},
        t_other, biases);
    *dq = x.q_W_B.normalized();
    *dp = x.p_W - 0.5 * g * tau * tau;
    return;
  }
  // Backwards: preintegrate [t_k + tau, t_k] (dR', dv', dp' over s = -tau), then
  // dR(tau) = dR'^T, dv(tau) = -dR'^T dv', dp(tau) = tau dv(tau) - dR'^T dp'.
  const double s = -tau;
  const NavState x = integrator.Integrate(
      {t_other, Eigen::Quaterniond::Identity(), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()},
      t_ns, biases);
  const Eigen::Quaterniond q_back = x.q_W_B.normalized();
  const Eigen::Vector3d dv_back = x.v_W - g * s;
  const Eigen::Vector3d dp_back = x.p_W - 0.5 * g * s * s;
  *dq = q_back.conjugate();
  const Eigen::Vector3d dv = -(q_back.conjugate() * dv_back);
  *dp = tau * dv - q_back.conjugate() * dp_back;
}

ImuTimeShift FitImuTimeShift(const std::vector<ImuSample>& samples, TimeNs t_ns,
                             const ImuBiases& biases, double max_shift_s, double* max_error) {
  ImuTimeShift shift;
  if (max_error) *max_error = 0.0;
  if (!(max_shift_s > 0.0) || samples.size() < 2) return shift;
  const TimeNs first = samples.front().t_ns, last = samples.back().t_ns;
  std::vector<double> u;
  std::vector<Eigen::Vector3d> phi, dp;
  for (int j = 0; j < kNodes; ++j) {
    const TimeNs offset_ns = SecondsToNs(max_shift_s * std::cos(M_PI * (j + 0.5) / kNodes));
    if (t_ns + offset_ns < first || t_ns + offset_ns > last) continue;
    const double tau = NsToSeconds(offset_ns);
    Eigen::Quaterniond dq;
    Eigen::Vector3d d;
    IntegrateImuTimeShift(samples, t_ns, biases, tau, &dq, &d);
    u.push_back(tau / max_shift_s);
    phi.push_back(LogQuaternion(dq));
    dp.push_back(d);
  }
  constexpr int K = ImuTimeShift::kDegree;
  if (static_cast<int>(u.size()) < K) return shift;  // at the very ends of the stream
  Eigen::MatrixXd A(u.size(), K), b(u.size(), 6);
  for (size_t i = 0; i < u.size(); ++i) {
    double power = u[i];
    for (int n = 0; n < K; ++n) {
      A(i, n) = power;
      power *= u[i];
    }
    b.row(i) << phi[i].transpose(), dp[i].transpose();
  }
  const Eigen::MatrixXd x = A.colPivHouseholderQr().solve(b);  // K x 6
  shift.max_shift_s = max_shift_s;
  shift.phi = x.leftCols<3>().transpose();
  shift.dp = x.rightCols<3>().transpose();
  if (max_error) *max_error = (A * x - b).cwiseAbs().maxCoeff();
  return shift;
}

}  // namespace mavloc
