// Bearing of a feature track whose landmark is parameterised by its inverse depth rho along the
// bearing b_a of its first observation, in the camera Ca of its anchor keyframe (Civera, Davison,
// Montiel, T-RO 2008, "Inverse Depth Parametrization for Monocular SLAM"; anchored as in MSCKF and
// OpenVINS): p_W = R_W_Ca b_a / rho + p_W_Ca. In the observing camera Co, multiplied by rho > 0
// (which leaves the direction unchanged),
//   h = R_Co_W (R_W_Ca b_a + rho (p_W_Ca - p_W_Co)),   r = E (h / |h| - b) / sigma_rad,
// with b the measured unit bearing and E (2 x 3) an orthonormal basis of the plane perpendicular
// to b (feature_bearing_factor.h). h stays finite as rho -> 0: a far point is a direction, and its
// residual then constrains the rotation alone, so far and near points are equally well
// conditioned (an XYZ landmark at depth d has a Jacobian that vanishes as 1/d along the ray).
//
// AnchoredBearingFactor: the observing keyframe differs from the anchor. Parameter blocks:
//   q_W_Ba (4, x y z w), p_W_Ba (3), q_W_Bo (4), p_W_Bo (3), rho (1).
//   Its Jacobians are analytic (the feature-track smoother's most numerous residual). With
//   J_h = E (I - u u^T) / (|h| sigma), u = h / |h|, R_Co_W = R_B_Co^T R_W_Bo^T, rotations perturbed
//   as R' = Exp(2 delta) R (quaternion_ambient.h), v_a = R_W_Ba (R_B_Ca b_a + rho p_B_Ca) and
//   p_W_Co - p_W_Bo = R_W_Bo p_B_Co:
//     dr/d delta_a = -2 J_h R_Co_W [v_a]x,               dr/dp_W_Ba = rho J_h R_Co_W,
//     dr/d delta_o =  2 J_h R_Co_W ([h_W]x + rho [R_W_Bo p_B_Co]x),
//     dr/dp_W_Bo = -rho J_h R_Co_W,                      dr/drho = J_h R_Co_W (p_W_Ca - p_W_Co).
//   AnchoredBearingFactorAutoDiff is the same residual differentiated automatically, the reference
//   the analytic Jacobians are checked against.
// AnchorStereoBearingFactor: the other camera of the anchor keyframe (stereo): the relative pose
//   is the extrinsics' T_Co_Ca, h = R_Co_Ca b_a + rho p_Co_Ca. Parameter block: rho (1).
// InverseDepthPriorFactor: a weak prior rho ~ N(rho_mean, sigma^2) that keeps a track seen
//   without parallax (a hover, a far point) from being a free direction of the normal equations.
#pragma once

#include <ceres/autodiff_cost_function.h>
#include <ceres/sized_cost_function.h>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "core/pose.h"
#include "solver/smoother/residuals/feature_bearing_factor.h"

namespace mavloc {

template <typename T>
bool WhitenedBearingResidual(const Eigen::Matrix<T, 3, 1>& h, const Eigen::Vector3d& bearing,
                             const Eigen::Matrix<double, 2, 3>& basis, double inv_sigma,
                             T* residuals) {
  const T norm = h.norm();
  if (!(norm > T(1e-12))) return false;
  const Eigen::Matrix<T, 2, 1> r = basis.cast<T>() * (h / norm - bearing.cast<T>());
  residuals[0] = r[0] * T(inv_sigma);
  residuals[1] = r[1] * T(inv_sigma);
  return true;
}

class AnchoredBearingFactorAutoDiff {
 public:
  AnchoredBearingFactorAutoDiff(const Pose& T_B_Ca, const Eigen::Vector3d& b_anchor_Ca,
                                const Pose& T_B_Co, const Eigen::Vector2d& xy_normalized,
                                double sigma_rad)
      : T_B_Ca_(T_B_Ca),
        T_B_Co_(T_B_Co),
        b_anchor_Ca_(b_anchor_Ca.normalized()),
        bearing_(Eigen::Vector3d(xy_normalized.x(), xy_normalized.y(), 1.0).normalized()),
        basis_(BearingTangentBasis(bearing_)),
        inv_sigma_(1.0 / sigma_rad) {}

  template <typename T>
  bool operator()(const T* qa_ptr, const T* pa_ptr, const T* qo_ptr, const T* po_ptr,
                  const T* rho_ptr, T* residuals) const {
    using Vec3 = Eigen::Matrix<T, 3, 1>;
    const Eigen::Map<const Eigen::Quaternion<T>> q_W_Ba(qa_ptr), q_W_Bo(qo_ptr);
    const Eigen::Map<const Vec3> p_W_Ba(pa_ptr), p_W_Bo(po_ptr);
    const T rho = rho_ptr[0];
    const Eigen::Quaternion<T> q_B_Ca = T_B_Ca_.q.cast<T>(), q_B_Co = T_B_Co_.q.cast<T>();
    // Camera centres in W and the anchor bearing in W.
    const Vec3 p_W_Ca = q_W_Ba * T_B_Ca_.p.cast<T>() + p_W_Ba;
    const Vec3 p_W_Co = q_W_Bo * T_B_Co_.p.cast<T>() + p_W_Bo;
    const Vec3 b_W = q_W_Ba * (q_B_Ca * b_anchor_Ca_.cast<T>());
    const Vec3 h_W = b_W + rho * (p_W_Ca - p_W_Co);
    const Vec3 h_Co = q_B_Co.conjugate() * (q_W_Bo.conjugate() * h_W);
    return WhitenedBearingResidual(h_Co, bearing_, basis_, inv_sigma_, residuals);
  }

  static ceres::CostFunction* Create(const Pose& T_B_Ca, const Eigen::Vector3d& b_anchor_Ca,
                                     const Pose& T_B_Co, const Eigen::Vector2d& xy_normalized,
                                     double sigma_rad) {
    return new ceres::AutoDiffCostFunction<AnchoredBearingFactorAutoDiff, 2, 4, 3, 4, 3, 1>(
        new AnchoredBearingFactorAutoDiff(T_B_Ca, b_anchor_Ca, T_B_Co, xy_normalized, sigma_rad));
  }

 private:
  Pose T_B_Ca_, T_B_Co_;
  Eigen::Vector3d b_anchor_Ca_;
  Eigen::Vector3d bearing_;
  Eigen::Matrix<double, 2, 3> basis_;
  double inv_sigma_;
};

class AnchoredBearingFactor : public ceres::SizedCostFunction<2, 4, 3, 4, 3, 1> {
 public:
  AnchoredBearingFactor(const Pose& T_B_Ca, const Eigen::Vector3d& b_anchor_Ca, const Pose& T_B_Co,
                        const Eigen::Vector2d& xy_normalized, double sigma_rad);

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

  static ceres::CostFunction* Create(const Pose& T_B_Ca, const Eigen::Vector3d& b_anchor_Ca,
                                     const Pose& T_B_Co, const Eigen::Vector2d& xy_normalized,
                                     double sigma_rad) {
    return new AnchoredBearingFactor(T_B_Ca, b_anchor_Ca, T_B_Co, xy_normalized, sigma_rad);
  }

 private:
  Eigen::Matrix3d R_B_Ca_, R_B_Co_;
  Eigen::Vector3d p_B_Ca_, p_B_Co_;
  Eigen::Vector3d b_anchor_B_;  // R_B_Ca b_a
  Eigen::Vector3d bearing_;
  Eigen::Matrix<double, 2, 3> basis_;
  double inv_sigma_;
};

class AnchorStereoBearingFactor {
 public:
  AnchorStereoBearingFactor(const Pose& T_B_Ca, const Eigen::Vector3d& b_anchor_Ca,
                            const Pose& T_B_Co, const Eigen::Vector2d& xy_normalized,
                            double sigma_rad)
      : bearing_(Eigen::Vector3d(xy_normalized.x(), xy_normalized.y(), 1.0).normalized()),
        basis_(BearingTangentBasis(bearing_)),
        inv_sigma_(1.0 / sigma_rad) {
    const Pose T_Co_Ca = T_B_Co.Inverse() * T_B_Ca;
    b_Co_ = T_Co_Ca.q * b_anchor_Ca.normalized();
    p_Co_Ca_ = T_Co_Ca.p;
  }

  template <typename T>
  bool operator()(const T* rho_ptr, T* residuals) const {
    const Eigen::Matrix<T, 3, 1> h = b_Co_.cast<T>() + rho_ptr[0] * p_Co_Ca_.cast<T>();
    return WhitenedBearingResidual(h, bearing_, basis_, inv_sigma_, residuals);
  }

  static ceres::CostFunction* Create(const Pose& T_B_Ca, const Eigen::Vector3d& b_anchor_Ca,
                                     const Pose& T_B_Co, const Eigen::Vector2d& xy_normalized,
                                     double sigma_rad) {
    return new ceres::AutoDiffCostFunction<AnchorStereoBearingFactor, 2, 1>(
        new AnchorStereoBearingFactor(T_B_Ca, b_anchor_Ca, T_B_Co, xy_normalized, sigma_rad));
  }

 private:
  Eigen::Vector3d b_Co_;     // the anchor bearing rotated into Co
  Eigen::Vector3d p_Co_Ca_;  // the anchor camera's centre in Co
  Eigen::Vector3d bearing_;
  Eigen::Matrix<double, 2, 3> basis_;
  double inv_sigma_;
};

class InverseDepthPriorFactor {
 public:
  InverseDepthPriorFactor(double rho_mean, double sigma) : mean_(rho_mean), inv_sigma_(1 / sigma) {}
  template <typename T>
  bool operator()(const T* rho, T* residual) const {
    residual[0] = (rho[0] - T(mean_)) * T(inv_sigma_);
    return true;
  }
  static ceres::CostFunction* Create(double rho_mean, double sigma) {
    return new ceres::AutoDiffCostFunction<InverseDepthPriorFactor, 1, 1>(
        new InverseDepthPriorFactor(rho_mean, sigma));
  }

 private:
  double mean_, inv_sigma_;
};

}  // namespace mavloc
