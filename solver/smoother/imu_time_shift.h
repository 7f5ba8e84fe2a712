// The motion of the body over a short time shift tau around a keyframe time t_k, from the IMU, as
// a smooth function of tau that a Ceres residual can differentiate (the camera-IMU time offset
// t_d of the smoother: an image stamped t_k was exposed at t_k + t_d).
//
// With the keyframe state (R_k, p_k, v_k) and the biases held at the linearization point:
//   R_W_B(t_k + tau) = R_k Exp(phi(tau)),
//   p_W_B(t_k + tau) = p_k + v_k tau + 1/2 g_W tau^2 + R_k dp(tau),
// where Exp(phi(tau)) = R_k^T R(t_k + tau) and dp(tau) = R_k^T (p - p_k - v_k tau - g tau^2 / 2)
// are the strapdown solution of the IMU alone from t_k (solver/imu/imu_integrator.h: RK4 on the
// cubic Lagrange interpolant of the samples, integrated forward for tau > 0 and from t_k + tau up
// to t_k, then inverted, for tau < 0). phi and dp are sampled at 10 Chebyshev nodes of
// [-max_shift, max_shift] and represented by least-squares polynomials tau^1 .. tau^5 (zero at
// tau = 0 by construction).
//
// Accuracy (what the residual assumes about the pose at t_k + t_d):
// - the polynomial fit: the remainder of a degree-5 fit of a motion with bounded 6th derivative,
//   below 1e-10 m and rad on the aprilgrid-calibration motion for max_shift = 30 ms
//   (FitImuTimeShift reports the largest residual at the nodes);
// - the integrator: O(dt^4) per sample interval on noiseless data (< 1e-9 over 30 ms);
// - the biases: held at the linearization values; an error db_g, db_a there moves the pose by
//   |db_g| |t_d| rad and |db_a| t_d^2 / 2 m (2e-3 rad/s x 20 ms = 4e-5 rad at worst for EuRoC's
//   turn-on gyro bias before relinearization);
// - IMU noise: integrated over |t_d| only (ADIS16448: 1.7e-4 rad/s/sqrt(Hz) x sqrt(0.02 s) = 2e-5
//   rad for 20 ms).
// By contrast, the first-order model R_k Exp(w_m t_d), p_k + v_k t_d misses 1/2 a t_d^2 (1 mm at
// 5 m/s^2 and 20 ms, a pixel at 0.5 m) and 1/2 w' t_d^2: too coarse for the noiseless check.
// Beyond [-max_shift, max_shift] the polynomial extrapolates; the smoother bounds t_d to it.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "core/imu.h"
#include "core/time.h"
#include "solver/imu/imu_integrator.h"

namespace mavloc {

struct ImuTimeShift {
  static constexpr int kDegree = 5;
  double max_shift_s = 0.0;
  // Coefficients of u^1 .. u^kDegree with u = tau / max_shift_s (columns), per component (rows).
  Eigen::Matrix<double, 3, kDegree> phi = Eigen::Matrix<double, 3, kDegree>::Zero();
  Eigen::Matrix<double, 3, kDegree> dp = Eigen::Matrix<double, 3, kDegree>::Zero();

  // phi(tau) (rad, rotation vector in B at t_k) and dp(tau) (m, in B at t_k).
  template <typename T>
  void Evaluate(const T& tau, T* phi_out, T* dp_out) const {
    for (int r = 0; r < 3; ++r) phi_out[r] = dp_out[r] = T(0.0);
    if (max_shift_s <= 0.0) return;
    const T u = tau / max_shift_s;
    T power = u;
    for (int n = 0; n < kDegree; ++n) {
      for (int r = 0; r < 3; ++r) {
        phi_out[r] += phi(r, n) * power;
        dp_out[r] += dp(r, n) * power;
      }
      power = power * u;
    }
  }

  // The same with the derivatives d phi / d tau and d dp / d tau (analytic Jacobians).
  void EvaluateWithDerivative(double tau, Eigen::Vector3d* phi_out, Eigen::Vector3d* dphi_dtau,
                              Eigen::Vector3d* dp_out, Eigen::Vector3d* ddp_dtau) const {
    phi_out->setZero();
    dphi_dtau->setZero();
    dp_out->setZero();
    ddp_dtau->setZero();
    if (max_shift_s <= 0.0) return;
    const double u = tau / max_shift_s;
    double power = 1.0;  // u^n
    for (int n = 0; n < kDegree; ++n) {
      // Term n is c_n u^(n+1); its derivative in tau is (n+1) c_n u^n / max_shift_s.
      const double derivative = (n + 1) * power / max_shift_s;
      *dphi_dtau += phi.col(n) * derivative;
      *ddp_dtau += dp.col(n) * derivative;
      power *= u;
      *phi_out += phi.col(n) * power;
      *dp_out += dp.col(n) * power;
    }
  }
};

// The fit around t_ns (inside the IMU stream); nodes outside the stream are left out. max_error,
// when given, receives the largest fit residual at the nodes (max over rad and m).
ImuTimeShift FitImuTimeShift(const std::vector<ImuSample>& samples, TimeNs t_ns,
                             const ImuBiases& biases, double max_shift_s,
                             double* max_error = nullptr);

// The same motion by direct integration (the fit's reference; tests): R_k^T R(t_k + tau) and dp.
void IntegrateImuTimeShift(const std::vector<ImuSample>& samples, TimeNs t_ns,
                           const ImuBiases& biases, double tau_s, Eigen::Quaterniond* dq,
                           Eigen::Vector3d* dp);

}  // namespace mavloc
