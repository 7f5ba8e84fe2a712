// The random motion of the laser-spot paper (Martinelli & Troiani, INRIA RR-7906, 2012, 5.1.1),
// made physically sensible. The paper draws, every 0.01 s, the linear acceleration and the angular
// speed as independent Gaussians (sigma_a = 1 m/s^2, sigma_w = 10 deg/s). White draws integrate to
// an unbounded random walk that soon hits the plane or turns the camera away from it, so here:
// - the random parts are Ornstein-Uhlenbeck processes sampled at the same 100 Hz, with the paper's
//   sigmas as stationary standard deviations and a correlation time (0.5 s by default):
//   x_{k+1} = rho x_k + sqrt(1 - rho^2) sigma n_k, rho = exp(-dt / tau);
// - a mean-reverting pull is added: the height above the plane (plane frame P, z along the normal)
//   by a critically damped spring towards height_m, the lateral velocity towards the initial
//   velocity, the attitude towards the reference attitude (camera looking at the plane);
//   the lateral position is free.
// This process (constant acceleration in W and body rate in B over each 0.01 s step) has a
// discontinuous IMU signal: no integrator of the IMU samples can follow it, so a noiseless IMU
// would drift by centimetres in seconds. The trajectory is therefore the process smoothed: the
// process is sampled every smoothing_spacing_s and the samples are the control points of uniform
// quintic B-splines (C^4), for the position p_W(t) and for the attitude relative to the reference,
// R_W_B(t) = R_W_ref Exp(phi(t)), so that the IMU signal is smooth and analytic:
//   v_W = p', a_W = p'', w_B = J_r(phi) phi' (d/dt Exp(phi) = Exp(phi) [J_r(phi) phi']x).
// The curve starts exactly at the initial position and reference attitude (a constant offset and a
// constant left rotation, which leave the IMU signal unchanged) and at the initial velocity (the
// control points before the start are moved to make it so).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <memory>
#include <vector>

#include "datasets/simulation/bspline.h"
#include "datasets/simulation/trajectory.h"

namespace mavloc {

struct RandomMotionOptions {
  TimeNs start_ns = 0;
  double duration_s = 60.0;
  double step_s = 0.01;                                       // process step (100 Hz)
  double smoothing_spacing_s = 0.2;                           // B-spline control point spacing
  Eigen::Quaterniond q_W_P = Eigen::Quaterniond::Identity();  // plane frame P (z = normal)
  Eigen::Vector3d p0_P = Eigen::Vector3d(0.0, 0.0, 1.0);      // initial position in P
  Eigen::Vector3d v0_P = Eigen::Vector3d(1.0, 0.0, 0.0);      // initial (and mean lateral) velocity
  Eigen::Quaterniond q_P_B_ref = Eigen::Quaterniond::Identity();  // initial and reference attitude
  double sigma_accel_m_s2 = 1.0;
  double sigma_rate_rad_s = 10.0 * 3.14159265358979323846 / 180.0;
  double correlation_time_s = 0.5;
  double height_stiffness_1_s2 = 9.0;  // pull on the height: -k (z - z0) - c v_z
  double height_damping_1_s = 4.2;
  double velocity_reversion_1_s = 0.5;  // pull on the lateral velocity towards v0
  double attitude_reversion_1_s = 0.5;  // body rate -kappa Log(R_ref^T R)
};

class RandomMotionTrajectory : public Trajectory {
 public:
  // Draws the whole motion from motion_seed.
  RandomMotionTrajectory(const RandomMotionOptions& options, uint64_t motion_seed);

  TimeNs start_ns() const override { return start_ns_; }
  TimeNs end_ns() const override { return end_ns_; }
  // Clamped to [start_ns, end_ns].
  TrajectorySample At(TimeNs t_ns) const override;

 private:
  TimeNs start_ns_ = 0;
  TimeNs end_ns_ = 0;
  std::unique_ptr<UniformBSpline> position_;  // p_W(t), t in s from start_ns
  std::unique_ptr<UniformBSpline> rotation_;  // phi(t): R_W_B = R_W_ref Exp(phi)
  Eigen::Quaterniond q_W_ref_ = Eigen::Quaterniond::Identity();
  Eigen::Vector3d position_offset_W_ = Eigen::Vector3d::Zero();  // p_W(t) = spline + offset
};

}  // namespace mavloc
