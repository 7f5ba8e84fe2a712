// The world frame W of a dataset whose map is given in a board frame M (MapFrame::kBoard,
// DESIGN.md "A map may be given in its own frame M"). W is z-up with gravity (0, 0, -9.81) as
// everywhere; on a board log only the gravity direction in M is known (estimated), so mavloc fixes
// the remaining 4 DoF of T_W_M by convention, the same for every estimator:
//   - origin of W = origin of M (p_W_M = 0);
//   - z_W = up_M, the unit vector opposite to gravity, expressed in M;
//   - x_W = the board's x axis projected onto the horizontal plane (the board's y axis when x_M is
//     within 25 deg of the vertical), normalised; y_W = z_W x x_W.
// So T_W_M depends only on the estimated gravity direction, and two estimators that agree on it
// report poses T_W_B in the same W. Every estimator on a board log reports T_W_B in this W and
// its gravity estimate as the quantities board_roll, board_pitch (core/board_frame.cc).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "core/pose.h"

namespace mavloc {

// R_W_M from the up direction in M (any non-zero length).
Eigen::Matrix3d BoardToWorldRotation(const Eigen::Vector3d& up_M);
// T_W_M = (R_W_M, 0).
Pose BoardToWorld(const Eigen::Vector3d& up_M);
// Re-expresses any R_W_M in the convention above (a rotation about z_W of the given one): the yaw
// of a tilt-only parametrization is gauge.
Eigen::Matrix3d CanonicalBoardToWorldRotation(const Eigen::Matrix3d& R_W_M);
// The up direction in M implied by R_W_M: R_W_M^T e_z.
Eigen::Vector3d UpInBoard(const Eigen::Matrix3d& R_W_M);

// The board's attitude to gravity as two angles, for reports: roll and pitch of R_W_M in the
// Euler convention of core/rotation.h (R_W_M = Rz(yaw) Ry(pitch) Rx(roll)); yaw is gauge and
// dropped. Quantity names: "board_roll", "board_pitch" (radians inside, degrees in reports).
struct BoardTilt {
  double roll_rad = 0.0;
  double pitch_rad = 0.0;
};
BoardTilt BoardTiltFromUp(const Eigen::Vector3d& up_M);

}  // namespace mavloc
