// On-manifold IMU preintegration between two keyframes i and j (Forster, Carlone, Dellaert,
// Scaramuzza, "On-Manifold Preintegration for Real-Time Visual-Inertial Odometry", T-RO 2017).
//
// The preintegrated measurements (eq. 33, with the biases held at the linearization point b0):
//   dR_ij = R_i^T R_j,   dv_ij = R_i^T (v_j - v_i - g dt_ij),
//   dp_ij = R_i^T (p_j - p_i - v_i dt_ij - 1/2 g dt_ij^2)
// are integrals of the bias-corrected IMU signal only. They are computed here by classic RK4 on
//   d(dR)/dt = dR [w_m - b_g]x,   d(dv)/dt = dR (a_m - b_a),   d(dp)/dt = dv
// with one step per IMU sample interval and the signal interpolated as in ImuIntegrator (cubic
// Lagrange), so that noiseless data are integrated to O(dt^4) instead of Forster's O(dt) Euler
// scheme (the smoother must return the truth to 1e-6 on noiseless data).
//
// First-order bias correction (eq. 44): for a bias b = b0 + db,
//   dR(b) = dR Exp(J_R_bg db_g),   dv(b) = dv + J_v_bg db_g + J_v_ba db_a,
//   dp(b) = dp + J_p_bg db_g + J_p_ba db_a.
// The five Jacobians are the exact derivatives of the RK4 scheme (forward-mode automatic
// differentiation through the integration), i.e. what Forster's recursion (appendix, eq. 59-61)
// approximates to first order in dt.
//
// Covariance of the preintegration error eta = [dphi, dv, dp] (eq. 62-63), propagated per sample
// interval k with the continuous noise densities sigma_g, sigma_a (discrete sigma =
// sigma_c/sqrt(dt)):
//   eta_{k+1} = A_k eta_k + B_k n_k,
//   A_k = [ dR_{k,k+1}^T              0     0 ]      B_k = [ Jr_k dt   0               ]
//         [ -dR_k [a_k]x dt           I     0 ]            [ 0         dR_k dt         ]
//         [ -1/2 dR_k [a_k]x dt^2     I dt  I ]            [ 0         1/2 dR_k dt^2   ]
// with a_k, w_k the bias-corrected signal at the interval midpoint.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

#include "core/imu.h"
#include "core/time.h"
#include "solver/imu/imu_integrator.h"

namespace mavloc {

// The state of one keyframe as the IMU factor sees it.
struct ImuKeyframeState {
  Eigen::Quaterniond q_W_B = Eigen::Quaterniond::Identity();
  Eigen::Vector3d p_W = Eigen::Vector3d::Zero();
  Eigen::Vector3d v_W = Eigen::Vector3d::Zero();
  ImuBiases biases;
};

// One step of the covariance propagation (eq. 62-63).
struct PreintegrationStepMatrices {
  Eigen::Matrix<double, 9, 9> A = Eigen::Matrix<double, 9, 9>::Identity();
  Eigen::Matrix<double, 9, 6> B = Eigen::Matrix<double, 9, 6>::Zero();  // noise (n_g, n_a)
  double dt_s = 0.0;
};

class ImuPreintegration {
 public:
  // Preintegrates samples over [t_i_ns, t_j_ns] (both inside the stream, t_i < t_j) with the
  // biases fixed at `linearization_biases`. `noise` gives the densities for the covariance (zero
  // densities give a zero covariance; the factor then needs a floor, see SqrtInformation).
  ImuPreintegration(const std::vector<ImuSample>& samples, TimeNs t_i_ns, TimeNs t_j_ns,
                    const ImuBiases& linearization_biases, const ImuNoise& noise);

  TimeNs t_i_ns() const { return t_i_ns_; }
  TimeNs t_j_ns() const { return t_j_ns_; }
  double dt_s() const { return dt_s_; }
  const ImuBiases& linearization_biases() const { return biases0_; }

  // Preintegrated measurements at the linearization biases.
  const Eigen::Quaterniond& delta_q() const { return delta_q_; }
  Eigen::Matrix3d delta_R() const { return delta_q_.toRotationMatrix(); }
  const Eigen::Vector3d& delta_v() const { return delta_v_; }
  const Eigen::Vector3d& delta_p() const { return delta_p_; }

  // Bias Jacobians (eq. 44), evaluated at the linearization biases.
  const Eigen::Matrix3d& J_R_bg() const { return J_R_bg_; }
  const Eigen::Matrix3d& J_v_bg() const { return J_v_bg_; }
  const Eigen::Matrix3d& J_v_ba() const { return J_v_ba_; }
  const Eigen::Matrix3d& J_p_bg() const { return J_p_bg_; }
  const Eigen::Matrix3d& J_p_ba() const { return J_p_ba_; }

  // Covariance of [dphi, dv, dp] (rad, m/s, m).
  const Eigen::Matrix<double, 9, 9>& covariance() const { return covariance_; }
  // Upper-triangular L with L^T L = (covariance + floor^2 I)^-1; floors (per block: rotation,
  // velocity, position) keep the information finite for noiseless data.
  Eigen::Matrix<double, 9, 9> SqrtInformation(double rotation_floor_rad = 1e-9,
                                              double velocity_floor_m_s = 1e-9,
                                              double position_floor_m = 1e-9) const;

  // First-order corrected measurements for other biases (eq. 44).
  Eigen::Quaterniond CorrectedDeltaQ(const ImuBiases& biases) const;
  Eigen::Vector3d CorrectedDeltaV(const ImuBiases& biases) const;
  Eigen::Vector3d CorrectedDeltaP(const ImuBiases& biases) const;

  // The state at t_j predicted from the state at t_i (eq. 44 with the corrected measurements);
  // the biases are carried over unchanged.
  ImuKeyframeState Predict(const ImuKeyframeState& state_i) const;

  // How many propagation steps (sample intervals) the preintegration took. The step matrices
  // themselves are not kept: a smoother holds one preintegration per keyframe.
  int num_steps() const { return num_steps_; }

  // Recomputes everything with new linearization biases (when the estimate drifted far from b0).
  void Repropagate(const std::vector<ImuSample>& samples, const ImuBiases& linearization_biases);

 private:
  void Propagate(const std::vector<ImuSample>& samples);

  TimeNs t_i_ns_;
  TimeNs t_j_ns_;
  double dt_s_;
  ImuBiases biases0_;
  ImuNoise noise_;
  Eigen::Quaterniond delta_q_ = Eigen::Quaterniond::Identity();
  Eigen::Vector3d delta_v_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d delta_p_ = Eigen::Vector3d::Zero();
  Eigen::Matrix3d J_R_bg_ = Eigen::Matrix3d::Zero();
  Eigen::Matrix3d J_v_bg_ = Eigen::Matrix3d::Zero();
  Eigen::Matrix3d J_v_ba_ = Eigen::Matrix3d::Zero();
  Eigen::Matrix3d J_p_bg_ = Eigen::Matrix3d::Zero();
  Eigen::Matrix3d J_p_ba_ = Eigen::Matrix3d::Zero();
  Eigen::Matrix<double, 9, 9> covariance_ = Eigen::Matrix<double, 9, 9>::Zero();
  int num_steps_ = 0;
};

}  // namespace mavloc
