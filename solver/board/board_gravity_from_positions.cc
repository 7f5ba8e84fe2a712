#include "solver/board/board_gravity_from_positions.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "core/imu.h"
#include "core/rotation.h"
#include "solver/imu/imu_integrator.h"

namespace mavloc {

namespace {

constexpr double kStepS = 0.001;

double Median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

// Chordal L2 mean of rotations (projection of their sum onto SO(3)).
Eigen::Matrix3d ChordalMean(const std::vector<Eigen::Matrix3d>& R, const std::vector<bool>& use) {
  Eigen::Matrix3d sum = Eigen::Matrix3d::Zero();
  for (size_t i = 0; i < R.size(); ++i)
    if (use[i]) sum += R[i];
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(sum, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d D = Eigen::Matrix3d::Identity();
  D(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0 ? -1.0 : 1.0;
  return svd.matrixU() * D * svd.matrixV().transpose();
}

}  // namespace

std::optional<Eigen::Vector3d> EstimateUpInBoardFromPositions(const std::vector<StampedPose>& T_M_B,
                                                              const ImuSensor& imu, TimeNs t_begin,
                                                              TimeNs t_end, std::string* why) {
  auto fail = [&](const std::string& reason) -> std::optional<Eigen::Vector3d> {
    if (why) *why = reason;
    return std::nullopt;
  };
  if (imu.samples.size() < 4) return fail("fewer than 4 IMU samples");
  const TimeNs lo = std::max(t_begin, imu.samples.front().t_ns);
  const TimeNs hi = std::min(t_end, imu.samples.back().t_ns);
  std::vector<StampedPose> poses;
  for (const StampedPose& pose : T_M_B) {
    if (pose.t_ns < lo || pose.t_ns > hi) continue;
    if (!pose.T_W_B.p.allFinite() || !pose.T_W_B.q.coeffs().allFinite()) continue;
    poses.push_back(pose);
  }
  std::sort(poses.begin(), poses.end(),
            [](const StampedPose& a, const StampedPose& b) { return a.t_ns < b.t_ns; });
  poses.erase(
      std::unique(poses.begin(), poses.end(),
                  [](const StampedPose& a, const StampedPose& b) { return a.t_ns == b.t_ns; }),
      poses.end());
  const size_t n = poses.size();
  if (n < 5) return fail("fewer than 5 poses in the window");
  const TimeNs t0 = poses.front().t_ns;
  if (NsToSeconds(poses.back().t_ns - t0) < 0.5) return fail("the poses span less than 0.5 s");

  // Gyro-propagated dR(tau_k) = R_B0_Bk and the double integral of dR a_m, both from t0, in B0.
  const ImuIntegrator signal(&imu.samples);
  const ImuBiases zero;
  std::vector<Eigen::Matrix3d> dR(n);
  std::vector<Eigen::Vector3d> P_B0(n);  // integral_0^tau integral_0^s dR a_m
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
  Eigen::Vector3d V = Eigen::Vector3d::Zero(), P = Eigen::Vector3d::Zero();
  dR[0] = Eigen::Matrix3d::Identity();
  P_B0[0] = Eigen::Vector3d::Zero();
  for (size_t k = 0; k + 1 < n; ++k) {
    const double length = NsToSeconds(poses[k + 1].t_ns - poses[k].t_ns);
    const int steps = std::max(1, static_cast<int>(std::ceil(length / kStepS)));
    const double h = length / steps;
    for (int s = 0; s < steps; ++s) {
      Eigen::Vector3d w_mid, f_mid;
      signal.SignalAt(poses[k].t_ns, (s + 0.5) * h, zero, &w_mid, &f_mid);
      const Eigen::Vector3d a_mid = (q * ExpQuaternion(0.5 * h * w_mid)) * f_mid;
      P += V * h + 0.5 * a_mid * h * h;
      V += a_mid * h;
      q = (q * ExpQuaternion(h * w_mid)).normalized();
    }
    dR[k + 1] = q.toRotationMatrix();
    P_B0[k + 1] = P;
  }

  // R_0 = R_M_B(t0): every PnP attitude carried back to t0, robustly averaged.
  std::vector<Eigen::Matrix3d> R0_candidates(n);
  for (size_t k = 0; k < n; ++k) R0_candidates[k] = poses[k].T_W_B.R() * dR[k].transpose();
  std::vector<bool> use(n, true);
  Eigen::Matrix3d R0 = ChordalMean(R0_candidates, use);
  for (int pass = 0; pass < 2; ++pass) {
    std::vector<double> deviation(n);
    for (size_t k = 0; k < n; ++k) deviation[k] = LogSO3(R0.transpose() * R0_candidates[k]).norm();
    const double limit = std::max(3.0 * Median(deviation), 2.0 * kDeg);
    for (size_t k = 0; k < n; ++k) use[k] = deviation[k] <= limit;
    R0 = ChordalMean(R0_candidates, use);
  }

  // Linear least squares for x = (p_0, v_0, g_M); positions with large residuals dropped.
  Eigen::Matrix<double, 9, 1> x = Eigen::Matrix<double, 9, 1>::Zero();
  for (int pass = 0; pass < 3; ++pass) {
    const int used = static_cast<int>(std::count(use.begin(), use.end(), true));
    if (used < 5) return fail("fewer than 5 consistent poses in the window");
    Eigen::MatrixXd A(3 * used, 9);
    Eigen::VectorXd b(3 * used);
    int row = 0;
    for (size_t k = 0; k < n; ++k) {
      if (!use[k]) continue;
      const double tau = NsToSeconds(poses[k].t_ns - t0);
      A.block<3, 9>(row, 0) << Eigen::Matrix3d::Identity(), tau * Eigen::Matrix3d::Identity(),
          0.5 * tau * tau * Eigen::Matrix3d::Identity();
      b.segment<3>(row) = poses[k].T_W_B.p - R0 * P_B0[k];
      row += 3;
    }
    x = A.colPivHouseholderQr().solve(b);
    if (pass == 2) break;
    std::vector<double> residual(n), used_residuals;
    for (size_t k = 0; k < n; ++k) {
      const double tau = NsToSeconds(poses[k].t_ns - t0);
      residual[k] = (poses[k].T_W_B.p - R0 * P_B0[k] - x.segment<3>(0) - tau * x.segment<3>(3) -
                     0.5 * tau * tau * x.segment<3>(6))
                        .norm();
      if (use[k]) used_residuals.push_back(residual[k]);
    }
    // 1.4826 MAD of a 3-D residual norm, floored at 1 mm.
    const double sigma = std::max(1.4826 * Median(used_residuals), 1e-3);
    for (size_t k = 0; k < n; ++k) use[k] = use[k] && residual[k] <= 3.0 * sigma;
  }
  const Eigen::Vector3d g_M = x.segment<3>(6);
  const double magnitude = g_M.norm();
  if (!(std::abs(magnitude - kGravityMagnitude) < 0.15 * kGravityMagnitude)) {
    return fail("implausible gravity magnitude " + std::to_string(magnitude) +
                " m/s^2 from the poses and the accelerometer");
  }
  return Eigen::Vector3d(-g_M / magnitude);
}

}  // namespace mavloc
