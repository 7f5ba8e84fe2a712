#include "evaluation/crlb/pixel_jacobian.h"

#include "core/rotation.h"

namespace mavloc {

bool PixelJacobian(const CameraSensor& camera, const Pose& T_W_B, const Eigen::Vector3d& p_W,
                   double sigma_px, bool with_tilt, Eigen::Matrix<double, 2, 8>* J) {
  const Eigen::Matrix3d R_W_B = T_W_B.q.toRotationMatrix();
  const Eigen::Matrix3d R_B_C = camera.T_B_C.q.toRotationMatrix();
  const Eigen::Vector3d p_B = R_W_B.transpose() * (p_W - T_W_B.p);
  const Eigen::Vector3d p_C = R_B_C.transpose() * (p_B - camera.T_B_C.p);
  if (p_C.z() <= 0.01) return false;
  Eigen::Matrix<double, 2, 3, Eigen::RowMajor> J_uv_pC;
  camera.model.ProjectWithJacobian(p_C, &J_uv_pC);
  const Eigen::Matrix<double, 2, 3> J_pW =
      J_uv_pC * R_B_C.transpose() * R_W_B.transpose() / sigma_px;
  J->setZero();
  J->leftCols<3>() = -J_pW;
  J->middleCols<3>(3) = J_uv_pC * R_B_C.transpose() * Skew(p_B) / sigma_px;
  if (with_tilt) J->rightCols<2>() = (-J_pW * Skew(p_W)).leftCols<2>();
  return true;
}

}  // namespace mavloc
