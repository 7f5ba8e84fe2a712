#include "core/board_frame.h"

#include <cmath>

#include "core/rotation.h"

namespace mavloc {

Eigen::Matrix3d BoardToWorldRotation(const Eigen::Vector3d& up_M) {
  const Eigen::Vector3d z = up_M.normalized();
  // cos(25 deg) = 0.906: beyond that the projection of x_M is too short to define yaw well.
  const Eigen::Vector3d reference =
      std::abs(z.x()) < 0.906 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  const Eigen::Vector3d x = (reference - reference.dot(z) * z).normalized();
  const Eigen::Vector3d y = z.cross(x);
  Eigen::Matrix3d R_M_W;
  R_M_W.col(0) = x;
  R_M_W.col(1) = y;
  R_M_W.col(2) = z;
  return R_M_W.transpose();
}

Pose BoardToWorld(const Eigen::Vector3d& up_M) {
  return Pose(Eigen::Matrix3d(BoardToWorldRotation(up_M)), Eigen::Vector3d::Zero());
}

Eigen::Vector3d UpInBoard(const Eigen::Matrix3d& R_W_M) {
  return R_W_M.transpose() * Eigen::Vector3d::UnitZ();
}

Eigen::Matrix3d CanonicalBoardToWorldRotation(const Eigen::Matrix3d& R_W_M) {
  return BoardToWorldRotation(UpInBoard(R_W_M));
}

BoardTilt BoardTiltFromUp(const Eigen::Vector3d& up_M) {
  const EulerRpy rpy = EulerFromRotation(BoardToWorldRotation(up_M));
  return {rpy.roll, rpy.pitch};
}

}  // namespace mavloc
