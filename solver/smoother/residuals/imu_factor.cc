#include "solver/smoother/residuals/imu_factor.h"

#include <ceres/manifold.h>
#include <ceres/rotation.h>

#include <cmath>

#include "core/rotation.h"

namespace mavloc {

namespace {
// (Named as well: the library is compiled as unity batches, which merge the anonymous namespaces.)
namespace imu_factor {

using RowMajor9x3 = Eigen::Matrix<double, 9, 3, Eigen::RowMajor>;
using RowMajor9x4 = Eigen::Matrix<double, 9, 4, Eigen::RowMajor>;

// Below this angle t (rad) Jr and Jr^-1 use their Taylor series up to t^4: the closed forms of
// eq. 8-9 lose about eps/t^2 (relative) to cancellation near 0, the series' truncation error is
// below t^6/40320 < 3e-17 here.
constexpr double kSmallAngle = 1e-2;

// Jr(phi) = I - (1 - cos t)/t^2 [phi]x + (t - sin t)/t^3 [phi]x^2 (Forster eq. 8), t = |phi|.
Eigen::Matrix3d RightJacobian(const Eigen::Vector3d& phi) {
  const double t2 = phi.squaredNorm();
  double a, b;
  if (t2 < kSmallAngle * kSmallAngle) {
    a = 0.5 - t2 * (1.0 / 24.0 - t2 / 720.0);
    b = 1.0 / 6.0 - t2 * (1.0 / 120.0 - t2 / 5040.0);
  } else {
    const double t = std::sqrt(t2);
    const double s = std::sin(0.5 * t);
    a = 2.0 * s * s / t2;  // (1 - cos t)/t^2 without the cancellation
    b = (t - std::sin(t)) / (t2 * t);
  }
  const Eigen::Matrix3d W = Skew(phi);
  return Eigen::Matrix3d::Identity() - a * W + b * (W * W);
}

// Jr^-1(phi) = I + 1/2 [phi]x + (1/t^2 - (1 + cos t)/(2 t sin t)) [phi]x^2 (Forster eq. 9), with
// (1 + cos t)/sin t = cot(t/2), finite up to t = pi (Log returns angles in [0, pi]).
Eigen::Matrix3d RightJacobianInverse(const Eigen::Vector3d& phi) {
  const double t2 = phi.squaredNorm();
  double c;
  if (t2 < kSmallAngle * kSmallAngle) {
    c = 1.0 / 12.0 + t2 * (1.0 / 720.0 + t2 / 30240.0);
  } else {
    const double t = std::sqrt(t2);
    const double half = 0.5 * t;
    c = 1.0 / t2 - std::cos(half) / (2.0 * t * std::sin(half));
  }
  const Eigen::Matrix3d W = Skew(phi);
  return Eigen::Matrix3d::Identity() + 0.5 * W + c * (W * W);
}

// J_tangent (9 x 3) of a ceres::EigenQuaternionManifold block at q (x, y, z, w) into the ambient
// 9 x 4 Jacobian J_tangent (P^T P)^-1 P^T: the PlusJacobian's columns are orthogonal with norm
// |q|, so (P^T P)^-1 = I / |q|^2 and J_ambient P = J_tangent.
void QuaternionAmbient(const double* q, const Eigen::Matrix<double, 9, 3>& J_tangent, double* out) {
  static const ceres::EigenQuaternionManifold manifold;
  Eigen::Matrix<double, 4, 3, Eigen::RowMajor> P;
  manifold.PlusJacobian(q, P.data());
  const double inv_norm2 = 1.0 / Eigen::Map<const Eigen::Vector4d>(q).squaredNorm();
  Eigen::Map<RowMajor9x4>{out} = J_tangent * (inv_norm2 * P.transpose());
}

}  // namespace imu_factor
}  // namespace

using imu_factor::QuaternionAmbient;
using imu_factor::RightJacobian;
using imu_factor::RightJacobianInverse;
using imu_factor::RowMajor9x3;

ImuFactor::ImuFactor(const ImuPreintegration& preintegration,
                     const Eigen::Matrix<double, 9, 9>& sqrt_information)
    : ImuFactorTerms(preintegration, sqrt_information) {
  const auto S_v = sqrt_information_.middleCols<3>(3);
  const auto S_p = sqrt_information_.rightCols<3>();
  S_J_bg_vp_ = -(S_v * J_v_bg_ + S_p * J_p_bg_);
  S_J_ba_ = -(S_v * J_v_ba_ + S_p * J_p_ba_);
}

bool ImuFactor::Evaluate(double const* const* parameters, double* residuals,
                         double** jacobians) const {
  // The residual, with the operations of ImuFactorAutoDiff in the same order.
  const Eigen::Map<const Eigen::Quaterniond> q_i(parameters[0]);
  const Eigen::Map<const Eigen::Vector3d> p_i(parameters[1]), v_i(parameters[2]);
  const Eigen::Map<const Eigen::Vector3d> b_g(parameters[3]), b_a(parameters[4]);
  const Eigen::Map<const Eigen::Quaterniond> q_j(parameters[5]);
  const Eigen::Map<const Eigen::Vector3d> p_j(parameters[6]), v_j(parameters[7]);
  const Eigen::Vector3d db_g = b_g - b_g0_;
  const Eigen::Vector3d db_a = b_a - b_a0_;

  const Eigen::Vector3d dphi = J_R_bg_ * db_g;
  double correction_wxyz[4];
  ceres::AngleAxisToQuaternion(dphi.data(), correction_wxyz);
  const Eigen::Quaterniond correction(correction_wxyz[0], correction_wxyz[1], correction_wxyz[2],
                                      correction_wxyz[3]);
  const Eigen::Quaterniond delta_q = delta_q_ * correction;
  const Eigen::Quaterniond error_q = delta_q.conjugate() * q_i.conjugate() * q_j;
  const double error_wxyz[4] = {error_q.w(), error_q.x(), error_q.y(), error_q.z()};
  Eigen::Vector3d r_R;
  ceres::QuaternionToAngleAxis(error_wxyz, r_R.data());

  const Eigen::Vector3d g_W = GravityW();
  const double dt = dt_s_;
  const Eigen::Quaterniond q_i_inv = q_i.conjugate();
  const Eigen::Vector3d w_v = v_j - v_i - g_W * dt;
  const Eigen::Vector3d w_p = p_j - p_i - v_i * dt - 0.5 * g_W * dt * dt;
  Eigen::Matrix<double, 9, 1> r;
  r.head<3>() = r_R;
  r.segment<3>(3) = q_i_inv * w_v - (delta_v_ + J_v_bg_ * db_g + J_v_ba_ * db_a);
  r.segment<3>(6) = q_i_inv * w_p - (delta_p_ + J_p_bg_ * db_g + J_p_ba_ * db_a);
  Eigen::Map<Eigen::Matrix<double, 9, 1>>{residuals} = sqrt_information_ * r;
  if (!jacobians) return true;

  const auto S_R = sqrt_information_.leftCols<3>();
  const auto S_v = sqrt_information_.middleCols<3>(3);
  const auto S_p = sqrt_information_.rightCols<3>();
  const Eigen::Matrix3d R_i_T = q_i_inv.toRotationMatrix();
  // Whitened d r / d (R_i^T x) through the velocity and position rows.
  const Eigen::Matrix<double, 9, 3> S_v_RiT = S_v * R_i_T;
  const Eigen::Matrix<double, 9, 3> S_p_RiT = S_p * R_i_T;

  const bool rotation_needed = jacobians[0] || jacobians[3] || jacobians[5];
  Eigen::Matrix3d Jr_inv;
  if (rotation_needed) Jr_inv = RightJacobianInverse(r_R);

  // S d r_R / d delta_j = 2 S_R Jr^-1(r_R) R_j^T; d r_R / d delta_i is its opposite.
  Eigen::Matrix<double, 9, 3> S_dR_dj;
  if (jacobians[0] || jacobians[5]) {
    const Eigen::Matrix3d R_j_T = q_j.conjugate().toRotationMatrix();
    S_dR_dj = S_R * (2.0 * Jr_inv * R_j_T);
  }
  if (jacobians[0]) {
    const Eigen::Matrix<double, 9, 3> J_tangent =
        2.0 * (S_v_RiT * Skew(w_v) + S_p_RiT * Skew(w_p)) - S_dR_dj;
    QuaternionAmbient(parameters[0], J_tangent, jacobians[0]);
  }
  if (jacobians[1]) Eigen::Map<RowMajor9x3>{jacobians[1]} = -S_p_RiT;
  if (jacobians[2]) Eigen::Map<RowMajor9x3>{jacobians[2]} = -(S_v_RiT + dt * S_p_RiT);
  if (jacobians[3]) {
    // Exp(r_R)^T: the rotation of the conjugate error quaternion.
    const Eigen::Matrix3d E_T = error_q.conjugate().toRotationMatrix();
    const Eigen::Matrix3d dR_dbg = -Jr_inv * E_T * RightJacobian(dphi) * J_R_bg_;
    Eigen::Map<RowMajor9x3>{jacobians[3]} = S_R * dR_dbg + S_J_bg_vp_;
  }
  if (jacobians[4]) Eigen::Map<RowMajor9x3>{jacobians[4]} = S_J_ba_;
  if (jacobians[5]) QuaternionAmbient(parameters[5], S_dR_dj, jacobians[5]);
  if (jacobians[6]) Eigen::Map<RowMajor9x3>{jacobians[6]} = S_p_RiT;
  if (jacobians[7]) Eigen::Map<RowMajor9x3>{jacobians[7]} = S_v_RiT;
  return true;
}

}  // namespace mavloc
