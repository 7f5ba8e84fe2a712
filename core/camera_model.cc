#include "core/camera_model.h"

#include <Eigen/Dense>

namespace mavloc {

std::optional<DistortionModel> ParseDistortionModel(const std::string& name) {
  if (name == "none" || name.empty()) return DistortionModel::kNone;
  if (name == "radial-tangential" || name == "radtan" || name == "plumb_bob")
    return DistortionModel::kRadialTangential;
  if (name == "equidistant" || name == "equi" || name == "fisheye")
    return DistortionModel::kEquidistant;
  return std::nullopt;
}

std::string DistortionModelName(DistortionModel model) {
  switch (model) {
    case DistortionModel::kNone:
      return "none";
    case DistortionModel::kRadialTangential:
      return "radial-tangential";
    case DistortionModel::kEquidistant:
      return "equidistant";
  }
  return "none";
}

void DistortNormalizedWithJacobian(DistortionModel model, const double* k, double x, double y,
                                   double* x_d, double* y_d, Eigen::Matrix2d* J_xd_xy) {
  DistortNormalized(model, k, x, y, x_d, y_d);
  Eigen::Matrix2d& J = *J_xd_xy;
  J.setIdentity();
  switch (model) {
    case DistortionModel::kNone:
      return;
    case DistortionModel::kRadialTangential: {
      // x_d = x radial + 2 p1 x y + p2 (r^2 + 2 x^2), y_d = y radial + p1 (r^2 + 2 y^2) + 2 p2 x y.
      const double r2 = x * x + y * y;
      const double radial = 1.0 + k[0] * r2 + k[1] * r2 * r2;
      const double dradial_dr2 = k[0] + 2.0 * k[1] * r2;
      const double dradial_dx = 2.0 * x * dradial_dr2, dradial_dy = 2.0 * y * dradial_dr2;
      J(0, 0) = radial + x * dradial_dx + 2.0 * k[2] * y + 6.0 * k[3] * x;
      J(0, 1) = x * dradial_dy + 2.0 * k[2] * x + 2.0 * k[3] * y;
      J(1, 0) = y * dradial_dx + 2.0 * k[2] * x + 2.0 * k[3] * y;
      J(1, 1) = radial + y * dradial_dy + 6.0 * k[2] * y + 2.0 * k[3] * x;
      return;
    }
    case DistortionModel::kEquidistant: {
      // (x_d, y_d) = s(r) (x, y), s = theta_d(theta(r)) / r: J = s I + (s'(r) / r) (x, y)(x, y)^T.
      const double r2 = x * x + y * y;
      if (r2 < 1e-16) return;  // s -> 1, s' -> 0 (DistortNormalized's branch)
      const double r = std::sqrt(r2);
      const double theta = std::atan(r);
      const double t2 = theta * theta;
      const double theta_d = theta * (1.0 + t2 * (k[0] + t2 * (k[1] + t2 * (k[2] + t2 * k[3]))));
      const double dtheta_d_dtheta =
          1.0 + t2 * (3.0 * k[0] + t2 * (5.0 * k[1] + t2 * (7.0 * k[2] + t2 * 9.0 * k[3])));
      const double dtheta_dr = 1.0 / (1.0 + r2);
      const double s = theta_d / r;
      const double ds_dr = (dtheta_d_dtheta * dtheta_dr - s) / r;
      const Eigen::Vector2d xy(x, y);
      J = s * Eigen::Matrix2d::Identity() + (ds_dr / r) * xy * xy.transpose();
      return;
    }
  }
}

CameraModel::CameraModel(int width_px, int height_px, const Eigen::Vector4d& intrinsics,
                         DistortionModel model, const std::array<double, 4>& coefficients)
    : width_(width_px),
      height_(height_px),
      intrinsics_(intrinsics),
      model_(model),
      coefficients_(coefficients) {}

Eigen::Matrix3d CameraModel::K() const {
  Eigen::Matrix3d K = Eigen::Matrix3d::Identity();
  K(0, 0) = fu();
  K(1, 1) = fv();
  K(0, 2) = cu();
  K(1, 2) = cv();
  return K;
}

Eigen::Vector2d CameraModel::Distort(const Eigen::Vector2d& xy) const {
  Eigen::Vector2d d;
  DistortNormalized(model_, coefficients_.data(), xy.x(), xy.y(), &d.x(), &d.y());
  return d;
}

std::optional<Eigen::Vector2d> CameraModel::Undistort(const Eigen::Vector2d& xy_d) const {
  if (model_ == DistortionModel::kNone) return xy_d;
  // Gauss-Newton on Distort(xy) = xy_d with a central-difference Jacobian, started at xy_d.
  Eigen::Vector2d xy = xy_d;
  for (int iteration = 0; iteration < 50; ++iteration) {
    const Eigen::Vector2d residual = Distort(xy) - xy_d;
    if (residual.norm() < 1e-14) return xy;
    Eigen::Matrix2d J;
    const double h = 1e-7 * std::max(1.0, xy.norm());
    for (int k = 0; k < 2; ++k) {
      Eigen::Vector2d step = Eigen::Vector2d::Zero();
      step[k] = h;
      J.col(k) = (Distort(xy + step) - Distort(xy - step)) / (2.0 * h);
    }
    if (std::abs(J.determinant()) < 1e-12) return std::nullopt;
    xy -= J.inverse() * residual;
    if (!xy.allFinite()) return std::nullopt;
  }
  if ((Distort(xy) - xy_d).norm() < 1e-10) return xy;
  return std::nullopt;
}

Eigen::Vector2d CameraModel::ProjectWithJacobian(
    const Eigen::Vector3d& p_C, Eigen::Matrix<double, 2, 3, Eigen::RowMajor>* J_uv_pC) const {
  const double inv_z = 1.0 / p_C.z();
  const double x = p_C.x() / p_C.z(), y = p_C.y() / p_C.z();
  double xd = x, yd = y;
  Eigen::Matrix2d J_xd_xy;
  DistortNormalizedWithJacobian(model_, coefficients_.data(), x, y, &xd, &yd, &J_xd_xy);
  // d(x, y) / d p_C = [[1/z, 0, -x/z], [0, 1/z, -y/z]]; pixels scale by (fu, fv).
  Eigen::Matrix<double, 2, 3> J_xy_pC;
  J_xy_pC << inv_z, 0.0, -x * inv_z, 0.0, inv_z, -y * inv_z;
  *J_uv_pC = Eigen::Vector2d(fu(), fv()).asDiagonal() * J_xd_xy * J_xy_pC;
  return {fu() * xd + cu(), fv() * yd + cv()};
}

Eigen::Vector2d CameraModel::NormalizedToPixel(const Eigen::Vector2d& xy) const {
  const Eigen::Vector2d d = Distort(xy);
  return {fu() * d.x() + cu(), fv() * d.y() + cv()};
}

std::optional<Eigen::Vector2d> CameraModel::PixelToNormalized(const Eigen::Vector2d& uv) const {
  return Undistort({(uv.x() - cu()) / fu(), (uv.y() - cv()) / fv()});
}

std::optional<Eigen::Vector2d> CameraModel::Project(const Eigen::Vector3d& p_C,
                                                    double min_depth_m) const {
  if (!(p_C.z() > min_depth_m)) return std::nullopt;
  return NormalizedToPixel(p_C.head<2>() / p_C.z());
}

std::optional<Eigen::Vector3d> CameraModel::Unproject(const Eigen::Vector2d& uv) const {
  const auto xy = PixelToNormalized(uv);
  if (!xy) return std::nullopt;
  return Eigen::Vector3d(xy->x(), xy->y(), 1.0).normalized();
}

bool CameraModel::IsInside(const Eigen::Vector2d& uv, double border_px) const {
  return uv.x() >= border_px && uv.y() >= border_px && uv.x() <= width_ - 1 - border_px &&
         uv.y() <= height_ - 1 - border_px;
}

}  // namespace mavloc
