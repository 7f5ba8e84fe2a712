// The gravity direction in a board frame M from the PnP poses T_M_B of a window and the IMU, by
// fitting the positions themselves rather than differentiated velocities. For the initialisation
// of the papers' tag estimators on board logs (board_world.h).
//
// Model (DESIGN.md IMU model, a_m = R_M_B^T (a_M - g_M) + b_a + n_a, biases taken as zero): over
// the window, with tau = t - t_0,
//   p_M(t_k) = p_0 + v_0 tau_k + 1/2 g_M tau_k^2 + P(tau_k),
//   P(tau) = integral_0^tau integral_0^s R_M_B(u) a_m(u) du ds,
// linear in (p_0, v_0, g_M): 9 unknowns, 3 equations per pose, solved by least squares over every
// pose of the window. R_M_B(u) = R_0 dR(u), dR from the gyroscope (cubic-Lagrange signal of
// solver/imu/imu_integrator.h, midpoint rule on ~1 ms steps) and R_0 the chordal mean of the PnP
// attitudes carried back by dR, so the PnP attitude noise averages over the window too.
// Poses whose attitude (> 3 median deviations, at least 2 deg) or position residual (> 3 robust
// sigmas) disagree are dropped and the fit repeated (the flips of planar PnP).
//
// Why not differentiate: v from finite differences of PnP positions at the two window ends carries
// the position noise divided by a fraction of a second; on a 30 Hz board with 1 px corners (16 mm
// PnP noise) the tilt error was 4.3 deg that way and ~0.4 deg with this fit, most of it the
// accelerometer bias (|b_a| / 9.81 rad, 0.3 deg for 0.05 m/s^2).
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "core/dataset.h"
#include "core/pose.h"

namespace mavloc {

// Up (unit, opposite to gravity) in M from poses T_M_B (StampedPose::T_W_B holds T_M_B) within
// [t_begin, t_end] and the IMU. nullopt (reason in *why, may be null) with fewer than 5 poses,
// a window shorter than 0.5 s or outside the IMU stream, or |g_M| not within 15 % of 9.81.
std::optional<Eigen::Vector3d> EstimateUpInBoardFromPositions(const std::vector<StampedPose>& T_M_B,
                                                              const ImuSensor& imu, TimeNs t_begin,
                                                              TimeNs t_end, std::string* why);

}  // namespace mavloc
