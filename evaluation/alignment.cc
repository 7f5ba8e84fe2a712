#include "evaluation/alignment.h"

#include <Eigen/SVD>
#include <cmath>
#include <limits>

#include "core/rotation.h"

namespace mavloc {

std::optional<AlignmentMode> ParseAlignmentMode(const std::string& name) {
  if (name == "none") return AlignmentMode::kNone;
  if (name == "se3") return AlignmentMode::kSe3;
  if (name == "sim3") return AlignmentMode::kSim3;
  if (name == "posyaw") return AlignmentMode::kPosYaw;
  return std::nullopt;
}

std::string AlignmentModeName(AlignmentMode mode) {
  switch (mode) {
    case AlignmentMode::kNone:
      return "none";
    case AlignmentMode::kSe3:
      return "se3";
    case AlignmentMode::kSim3:
      return "sim3";
    case AlignmentMode::kPosYaw:
      return "posyaw";
  }
  return "none";
}

std::optional<Similarity> AlignPoints(const std::vector<Eigen::Vector3d>& p_est,
                                      const std::vector<Eigen::Vector3d>& p_gt,
                                      AlignmentMode mode) {
  if (mode == AlignmentMode::kNone) return Similarity{};
  const size_t n = p_est.size();
  if (n != p_gt.size() || n == 0) return std::nullopt;
  if (n < (mode == AlignmentMode::kPosYaw ? 2u : 3u)) return std::nullopt;
  Eigen::Vector3d mu_e = Eigen::Vector3d::Zero(), mu_g = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < n; ++i) {
    mu_e += p_est[i];
    mu_g += p_gt[i];
  }
  mu_e /= n;
  mu_g /= n;
  Eigen::Matrix3d sigma = Eigen::Matrix3d::Zero();  // (1/n) sum (g - mu_g)(e - mu_e)^T
  double var_e = 0.0;
  for (size_t i = 0; i < n; ++i) {
    sigma += (p_gt[i] - mu_g) * (p_est[i] - mu_e).transpose();
    var_e += (p_est[i] - mu_e).squaredNorm();
  }
  sigma /= n;
  var_e /= n;
  if (var_e < 1e-18) return std::nullopt;  // all estimated points coincide

  Similarity S;
  if (mode == AlignmentMode::kPosYaw) {
    // Maximise sum (g - mu_g) . Rz(theta) (e - mu_e): theta = atan2(S_xy - S_yx, S_xx + S_yy)
    // with S = sigma (only the horizontal components enter).
    const double theta = std::atan2(sigma(1, 0) - sigma(0, 1), sigma(0, 0) + sigma(1, 1));
    S.R = Rz(theta);
  } else {
    // Umeyama (1991), eq. 38-42.
    Eigen::JacobiSVD<Eigen::Matrix3d> svd(sigma, Eigen::ComputeFullU | Eigen::ComputeFullV);
    // evo: "Degenerate covariance rank, Umeyama alignment is not possible".
    const double eps = std::numeric_limits<double>::epsilon();
    if ((svd.singularValues().array() > eps).count() < 2) return std::nullopt;
    Eigen::Matrix3d D = Eigen::Matrix3d::Identity();
    if (svd.matrixU().determinant() * svd.matrixV().determinant() < 0) D(2, 2) = -1.0;
    S.R = svd.matrixU() * D * svd.matrixV().transpose();
    if (mode == AlignmentMode::kSim3) {
      S.scale = (svd.singularValues().asDiagonal() * D).trace() / var_e;
    }
  }
  S.t = mu_g - S.scale * S.R * mu_e;
  return S;
}

std::optional<Similarity> AlignFirstPose(const Pose& T_W_B_est0, const Pose& T_W_B_gt0,
                                         AlignmentMode mode) {
  Similarity S;
  switch (mode) {
    case AlignmentMode::kNone:
      return S;
    case AlignmentMode::kSim3:
      return std::nullopt;
    case AlignmentMode::kSe3:
      S.R = T_W_B_gt0.R() * T_W_B_est0.R().transpose();
      break;
    case AlignmentMode::kPosYaw: {
      // rpg get_best_yaw(C) with C = R_est0 R_gt0^T: theta = atan2(C01 - C10, C00 + C11).
      const Eigen::Matrix3d C = T_W_B_est0.R() * T_W_B_gt0.R().transpose();
      S.R = Rz(std::atan2(C(0, 1) - C(1, 0), C(0, 0) + C(1, 1)));
      break;
    }
  }
  S.t = T_W_B_gt0.p - S.R * T_W_B_est0.p;
  return S;
}

Similarity AlignOrigin(const Pose& T_W_B_est0, const Pose& T_W_B_gt0) {
  const Pose T = T_W_B_gt0 * T_W_B_est0.Inverse();
  Similarity S;
  S.R = T.R();
  S.t = T.p;
  return S;
}

Pose ApplySimilarity(const Similarity& S, const Pose& T_W_B) {
  return ApplySimilarity(S, Eigen::Quaterniond(S.R), T_W_B);
}

Pose ApplySimilarity(const Similarity& S, const Eigen::Quaterniond& q_S, const Pose& T_W_B) {
  return Pose(q_S * T_W_B.q, S.Apply(T_W_B.p));
}

}  // namespace mavloc
