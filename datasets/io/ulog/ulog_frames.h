// PX4's frames to mavloc's (PX4: docs.px4.io/main/en/ros/external_position_estimation.html and
// "Coordinate Frames": body FRD, earth NED, quaternions Hamilton (w, x, y, z) rotating FRD into
// NED; mavloc: DESIGN.md, W z up, B = IMU, Eigen Hamilton q_W_B).
//   B = FLU:  R_FLU_FRD = diag(1, -1, -1)              (a 180 deg turn about x)
//   W = ENU:  R_ENU_NED = [0 1 0; 1 0 0; 0 0 -1]       (a 180 deg turn about (1, 1, 0) / sqrt 2)
//   A PX4 "FRD" earth frame (x along the initial heading, z down) becomes a z-up FLU world frame
//   by diag(1, -1, -1).
// So q_W_B = R_ENU_NED * q_NED_FRD * R_FRD_FLU; a position or velocity in NED becomes (y, x, -z).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace mavloc::ulog {

inline Eigen::Matrix3d R_FLU_FRD() { return Eigen::Vector3d(1.0, -1.0, -1.0).asDiagonal(); }

inline Eigen::Matrix3d R_ENU_NED() {
  Eigen::Matrix3d R;
  R << 0.0, 1.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, -1.0;
  return R;
}

inline Eigen::Vector3d FrdToFlu(const Eigen::Vector3d& v_frd) { return R_FLU_FRD() * v_frd; }
inline Eigen::Vector3d NedToEnu(const Eigen::Vector3d& v_ned) { return R_ENU_NED() * v_ned; }

// q_W_B for a z-up world W = R_W_Wpx4 * Wpx4 and body B = FLU, from PX4's q (FRD into its
// earth frame Wpx4, NED or FRD-world). R_FRD_FLU = R_FLU_FRD^T = R_FLU_FRD.
inline Eigen::Quaterniond ToMavlocQuaternion(const Eigen::Matrix3d& R_W_Wpx4,
                                             const Eigen::Quaterniond& q_Wpx4_FRD) {
  const Eigen::Matrix3d R_W_B = R_W_Wpx4 * q_Wpx4_FRD.normalized().toRotationMatrix() * R_FLU_FRD();
  return Eigen::Quaterniond(R_W_B).normalized();
}

}  // namespace mavloc::ulog
