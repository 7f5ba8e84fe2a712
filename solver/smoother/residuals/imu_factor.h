// The preintegrated IMU factor between keyframes i and j (Forster et al., T-RO 2017, eq. 45):
//   r_R = Log( (dR Exp(J_R_bg db_g))^T R_i^T R_j )
//   r_v = R_i^T (v_j - v_i - g dt) - (dv + J_v_bg db_g + J_v_ba db_a)
//   r_p = R_i^T (p_j - p_i - v_i dt - 1/2 g dt^2) - (dp + J_p_bg db_g + J_p_ba db_a)
// with db = b_i - b0 (the preintegration's linearization biases, eq. 44), whitened by the
// square-root information S of the preintegrated covariance: r = S [r_R; r_v; r_p]. Parameter
// blocks: q_W_Bi (4, Eigen order x y z w), p_W_Bi, v_W_i, b_g_i, b_a_i, q_W_Bj, p_W_Bj, v_W_j.
//
// ImuFactor (used by the smoother) evaluates the residual in double and its Jacobians
// analytically (the paper's appendix, "Jacobians of the residual errors", with Jr the right
// Jacobian of SO(3), eq. 8-9; Jr and Jr^-1 by their Taylor series below 1e-2 rad, Log by atan2,
// exact at any angle). The quaternion blocks live on
// ceres::EigenQuaternionManifold, whose Plus is R' = Exp(2 delta) R (a left, world-frame
// perturbation by twice the tangent vector), so that in its tangent space
//   d r_R / d delta_i = -2 Jr^-1(r_R) R_j^T,        d r_R / d delta_j = 2 Jr^-1(r_R) R_j^T,
//   d r_v / d delta_i = 2 R_i^T [v_j - v_i - g dt]x,
//   d r_p / d delta_i = 2 R_i^T [p_j - p_i - v_i dt - 1/2 g dt^2]x,
//   d r_R / d b_g = -Jr^-1(r_R) Exp(r_R)^T Jr(J_R_bg db_g) J_R_bg,
//   d r_v / d (v_i, v_j, b_g, b_a) = (-R_i^T, R_i^T, -J_v_bg, -J_v_ba),
//   d r_p / d (p_i, v_i, p_j, b_g, b_a) = (-R_i^T, -R_i^T dt, R_i^T, -J_p_bg, -J_p_ba),
// and each quaternion block's tangent Jacobian J_t is mapped to the ambient 4 coordinates as
// J_t (P^T P)^-1 P^T with P the manifold's PlusJacobian at q (P^T P = |q|^2 I), so that Ceres'
// product J_ambient P returns J_t. ImuFactorAutoDiff is the same residual differentiated
// automatically (26 dual numbers), kept as the reference the tests check ImuFactor against.
#pragma once

#include <ceres/autodiff_cost_function.h>
#include <ceres/rotation.h>
#include <ceres/sized_cost_function.h>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "core/imu.h"
#include "solver/smoother/imu_preintegration.h"

namespace mavloc {

// The preintegrated measurement, its bias Jacobians and linearization biases, and the whitening:
// what both versions of the factor read.
struct ImuFactorTerms {
  ImuFactorTerms(const ImuPreintegration& preintegration,
                 const Eigen::Matrix<double, 9, 9>& sqrt_information)
      : delta_q_(preintegration.delta_q()),
        delta_v_(preintegration.delta_v()),
        delta_p_(preintegration.delta_p()),
        J_R_bg_(preintegration.J_R_bg()),
        J_v_bg_(preintegration.J_v_bg()),
        J_v_ba_(preintegration.J_v_ba()),
        J_p_bg_(preintegration.J_p_bg()),
        J_p_ba_(preintegration.J_p_ba()),
        b_g0_(preintegration.linearization_biases().b_g),
        b_a0_(preintegration.linearization_biases().b_a),
        dt_s_(preintegration.dt_s()),
        sqrt_information_(sqrt_information) {}

  Eigen::Quaterniond delta_q_;
  Eigen::Vector3d delta_v_, delta_p_;
  Eigen::Matrix3d J_R_bg_, J_v_bg_, J_v_ba_, J_p_bg_, J_p_ba_;
  Eigen::Vector3d b_g0_, b_a0_;
  double dt_s_;
  Eigen::Matrix<double, 9, 9> sqrt_information_;
};

class ImuFactor : public ceres::SizedCostFunction<9, 4, 3, 3, 3, 3, 4, 3, 3>,
                  private ImuFactorTerms {
 public:
  ImuFactor(const ImuPreintegration& preintegration,
            const Eigen::Matrix<double, 9, 9>& sqrt_information);

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

  static ceres::CostFunction* Create(const ImuPreintegration& preintegration,
                                     const Eigen::Matrix<double, 9, 9>& sqrt_information) {
    return new ImuFactor(preintegration, sqrt_information);
  }

 private:
  // Constant parts of the whitened Jacobians: S (0, -J_v_bg, -J_p_bg), S (0, -J_v_ba, -J_p_ba).
  Eigen::Matrix<double, 9, 3> S_J_bg_vp_, S_J_ba_;
};

class ImuFactorAutoDiff : private ImuFactorTerms {
 public:
  ImuFactorAutoDiff(const ImuPreintegration& preintegration,
                    const Eigen::Matrix<double, 9, 9>& sqrt_information)
      : ImuFactorTerms(preintegration, sqrt_information) {}

  template <typename T>
  bool operator()(const T* q_i_ptr, const T* p_i_ptr, const T* v_i_ptr, const T* b_g_ptr,
                  const T* b_a_ptr, const T* q_j_ptr, const T* p_j_ptr, const T* v_j_ptr,
                  T* residuals_ptr) const {
    using Vec3 = Eigen::Matrix<T, 3, 1>;
    const Eigen::Map<const Eigen::Quaternion<T>> q_i(q_i_ptr);
    const Eigen::Map<const Eigen::Quaternion<T>> q_j(q_j_ptr);
    const Eigen::Map<const Vec3> p_i(p_i_ptr), v_i(v_i_ptr), p_j(p_j_ptr), v_j(v_j_ptr);
    const Eigen::Map<const Vec3> b_g(b_g_ptr), b_a(b_a_ptr);
    const Vec3 db_g = b_g - b_g0_.cast<T>();
    const Vec3 db_a = b_a - b_a0_.cast<T>();

    // Bias-corrected rotation measurement dR Exp(J_R_bg db_g).
    const Vec3 dphi = J_R_bg_.cast<T>() * db_g;
    T correction_wxyz[4];
    ceres::AngleAxisToQuaternion(dphi.data(), correction_wxyz);
    const Eigen::Quaternion<T> correction(correction_wxyz[0], correction_wxyz[1],
                                          correction_wxyz[2], correction_wxyz[3]);
    const Eigen::Quaternion<T> delta_q = delta_q_.cast<T>() * correction;
    const Eigen::Quaternion<T> error_q = delta_q.conjugate() * q_i.conjugate() * q_j;
    const T error_wxyz[4] = {error_q.w(), error_q.x(), error_q.y(), error_q.z()};

    Eigen::Matrix<T, 9, 1> r;
    T r_R[3];
    ceres::QuaternionToAngleAxis(error_wxyz, r_R);
    r.template head<3>() = Eigen::Map<const Vec3>(r_R);

    const Vec3 g_W = GravityW().cast<T>();
    const T dt(dt_s_);
    const Eigen::Quaternion<T> q_i_inv = q_i.conjugate();
    r.template segment<3>(3) =
        q_i_inv * (v_j - v_i - g_W * dt) -
        (delta_v_.cast<T>() + J_v_bg_.cast<T>() * db_g + J_v_ba_.cast<T>() * db_a);
    r.template segment<3>(6) =
        q_i_inv * (p_j - p_i - v_i * dt - T(0.5) * g_W * dt * dt) -
        (delta_p_.cast<T>() + J_p_bg_.cast<T>() * db_g + J_p_ba_.cast<T>() * db_a);

    Eigen::Map<Eigen::Matrix<T, 9, 1>> residuals(residuals_ptr);
    residuals = sqrt_information_.cast<T>() * r;
    return true;
  }

  static ceres::CostFunction* Create(const ImuPreintegration& preintegration,
                                     const Eigen::Matrix<double, 9, 9>& sqrt_information) {
    return new ceres::AutoDiffCostFunction<ImuFactorAutoDiff, 9, 4, 3, 3, 3, 3, 4, 3, 3>(
        new ImuFactorAutoDiff(preintegration, sqrt_information));
  }
};

}  // namespace mavloc
