// Rotation conventions (DESIGN.md):
// - Eigen Hamilton quaternions, q_A_B rotates B-coordinates into A: v_A = q_A_B * v_B.
// - Euler angles for reporting are roll, pitch, yaw with R = Rz(yaw) * Ry(pitch) * Rx(roll)
//   (intrinsic z-y'-x'', the aerospace convention); pitch lies in [-pi/2, pi/2].
// - SO(3) exponential/logarithm maps with the right Jacobian used by IMU preintegration
//   (Forster et al., T-RO 2017, eq. 8).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <numbers>

namespace mavloc {

// Radians per degree (x * kDeg: degrees to radians; x / kDeg: radians to degrees).
inline constexpr double kDeg = std::numbers::pi / 180.0;

// Roll, pitch, yaw in radians.
struct EulerRpy {
  double roll = 0.0;
  double pitch = 0.0;
  double yaw = 0.0;
};

// R = Rz(yaw) * Ry(pitch) * Rx(roll).
Eigen::Matrix3d RotationFromEuler(const EulerRpy& rpy);
Eigen::Quaterniond QuaternionFromEuler(const EulerRpy& rpy);
// Inverse of RotationFromEuler; at gimbal lock (|pitch| = pi/2) roll is set to 0.
EulerRpy EulerFromRotation(const Eigen::Matrix3d& R);
EulerRpy EulerFromQuaternion(const Eigen::Quaterniond& q);

Eigen::Matrix3d Rx(double angle_rad);
Eigen::Matrix3d Ry(double angle_rad);
Eigen::Matrix3d Rz(double angle_rad);

// Wraps an angle into (-pi, pi].
double WrapAngle(double angle_rad);

Eigen::Matrix3d Skew(const Eigen::Vector3d& v);
// Inverse of Skew for a skew-symmetric matrix (uses the antisymmetric part).
Eigen::Vector3d Vee(const Eigen::Matrix3d& S);

// Exp: so(3) -> SO(3) (Rodrigues), with a Taylor expansion near zero.
Eigen::Matrix3d ExpSO3(const Eigen::Vector3d& phi);
Eigen::Quaterniond ExpQuaternion(const Eigen::Vector3d& phi);
// Log: SO(3) -> so(3), angle in [0, pi].
Eigen::Vector3d LogSO3(const Eigen::Matrix3d& R);
Eigen::Vector3d LogQuaternion(const Eigen::Quaterniond& q);
// Right Jacobian Jr(phi) and its inverse (Forster et al. 2017, eq. 8 and 9).
Eigen::Matrix3d RightJacobianSO3(const Eigen::Vector3d& phi);
Eigen::Matrix3d RightJacobianInverseSO3(const Eigen::Vector3d& phi);

// Projects a nearly orthonormal matrix onto SO(3) (SVD).
Eigen::Matrix3d NearestRotation(const Eigen::Matrix3d& M);

// Quaternion coefficient orders used on disk: EuRoC writes (w, x, y, z), TUM writes (x, y, z, w).
Eigen::Quaterniond QuaternionFromWxyz(double w, double x, double y, double z);

}  // namespace mavloc
