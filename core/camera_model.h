// Pinhole camera with the two distortion models EuRoC and Kalibr name:
// - "radial-tangential" (Kalibr "radtan", OpenCV plumb bob k1, k2, p1, p2):
//     x_d = x (1 + k1 r^2 + k2 r^4) + 2 p1 x y + p2 (r^2 + 2 x^2)
//     y_d = y (1 + k1 r^2 + k2 r^4) + p1 (r^2 + 2 y^2) + 2 p2 x y,   r^2 = x^2 + y^2
// - "equidistant" (Kalibr "equi", OpenCV fisheye k1..k4):
//     theta = atan(r), theta_d = theta (1 + k1 theta^2 + k2 theta^4 + k3 theta^6 + k4 theta^8)
//     (x_d, y_d) = theta_d / r * (x, y)
// Pixels: u = fu x_d + cu, v = fv y_d + cv. Camera frame C: z forward, x right, y down.
// Normalized image coordinates are (x, y) = (X/Z, Y/Z) of a point in C, before distortion.
// The distortion functions are templated so that Ceres can differentiate them automatically.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cmath>
#include <optional>
#include <string>

namespace mavloc {

enum class DistortionModel { kNone, kRadialTangential, kEquidistant };

// Parses "none", "radial-tangential"/"radtan"/"plumb_bob", "equidistant"/"equi"/"fisheye".
std::optional<DistortionModel> ParseDistortionModel(const std::string& name);
// Kalibr/EuRoC names: "none", "radial-tangential", "equidistant".
std::string DistortionModelName(DistortionModel model);

template <typename T>
void DistortNormalized(DistortionModel model, const double* k, const T& x, const T& y, T* x_d,
                       T* y_d) {
  switch (model) {
    case DistortionModel::kNone:
      *x_d = x;
      *y_d = y;
      return;
    case DistortionModel::kRadialTangential: {
      const T r2 = x * x + y * y;
      const T radial = T(1.0) + k[0] * r2 + k[1] * r2 * r2;
      *x_d = x * radial + T(2.0 * k[2]) * x * y + k[3] * (r2 + T(2.0) * x * x);
      *y_d = y * radial + k[2] * (r2 + T(2.0) * y * y) + T(2.0 * k[3]) * x * y;
      return;
    }
    case DistortionModel::kEquidistant: {
      using std::atan;
      using std::sqrt;
      const T r2 = x * x + y * y;
      if (r2 < T(1e-16)) {  // theta_d / r -> 1 as r -> 0
        *x_d = x;
        *y_d = y;
        return;
      }
      const T r = sqrt(r2);
      const T theta = atan(r);
      const T t2 = theta * theta;
      const T theta_d = theta * (T(1.0) + t2 * (k[0] + t2 * (k[1] + t2 * (k[2] + t2 * k[3]))));
      const T scale = theta_d / r;
      *x_d = x * scale;
      *y_d = y * scale;
      return;
    }
  }
}

// The distortion and its 2 x 2 Jacobian d(x_d, y_d) / d(x, y), differentiated by hand from the
// formulas above (the values are DistortNormalized's, to the bit).
void DistortNormalizedWithJacobian(DistortionModel model, const double* k, double x, double y,
                                   double* x_d, double* y_d, Eigen::Matrix2d* J_xd_xy);

class CameraModel {
 public:
  CameraModel() = default;
  // intrinsics = (fu, fv, cu, cv) in pixels; distortion coefficients as named above (unused
  // entries zero).
  CameraModel(int width_px, int height_px, const Eigen::Vector4d& intrinsics,
              DistortionModel model = DistortionModel::kNone,
              const std::array<double, 4>& coefficients = {0, 0, 0, 0});

  int width() const { return width_; }
  int height() const { return height_; }
  const Eigen::Vector4d& intrinsics() const { return intrinsics_; }
  double fu() const { return intrinsics_[0]; }
  double fv() const { return intrinsics_[1]; }
  double cu() const { return intrinsics_[2]; }
  double cv() const { return intrinsics_[3]; }
  DistortionModel distortion_model() const { return model_; }
  const std::array<double, 4>& distortion() const { return coefficients_; }
  // The 3x3 matrix K and OpenCV's distortion vector (k1 k2 p1 p2, or fisheye k1..k4).
  Eigen::Matrix3d K() const;

  Eigen::Vector2d Distort(const Eigen::Vector2d& xy) const;
  // Inverse of Distort by Gauss-Newton; nullopt where it does not converge.
  std::optional<Eigen::Vector2d> Undistort(const Eigen::Vector2d& xy_distorted) const;

  // Normalized (undistorted) coordinates -> pixel.
  Eigen::Vector2d NormalizedToPixel(const Eigen::Vector2d& xy) const;
  // Pixel -> normalized (undistorted) coordinates; nullopt where undistortion fails.
  std::optional<Eigen::Vector2d> PixelToNormalized(const Eigen::Vector2d& uv) const;

  // Projects a point in C; nullopt when it is not in front of the camera (z <= min_depth_m).
  std::optional<Eigen::Vector2d> Project(const Eigen::Vector3d& p_C,
                                         double min_depth_m = 1e-6) const;
  // Unit bearing in C of a pixel.
  std::optional<Eigen::Vector3d> Unproject(const Eigen::Vector2d& uv) const;

  bool IsInside(const Eigen::Vector2d& uv, double border_px = 0.0) const;

  // Pixel projection of a point in C (no visibility check, z != 0) and its Jacobian
  // d uv / d p_C, analytic; the same pixel as ProjectT<double>, to the bit.
  Eigen::Vector2d ProjectWithJacobian(const Eigen::Vector3d& p_C,
                                      Eigen::Matrix<double, 2, 3, Eigen::RowMajor>* J_uv_pC) const;

  // Templated pixel projection of a point in C (no visibility check), for automatic
  // differentiation.
  template <typename T>
  void ProjectT(const T* p_C, T* uv) const {
    const T x = p_C[0] / p_C[2];
    const T y = p_C[1] / p_C[2];
    T xd = x, yd = y;
    DistortNormalized(model_, coefficients_.data(), x, y, &xd, &yd);
    uv[0] = T(fu()) * xd + T(cu());
    uv[1] = T(fv()) * yd + T(cv());
  }

 private:
  int width_ = 0;
  int height_ = 0;
  Eigen::Vector4d intrinsics_ = Eigen::Vector4d(1, 1, 0, 0);
  DistortionModel model_ = DistortionModel::kNone;
  std::array<double, 4> coefficients_ = {0, 0, 0, 0};
};

}  // namespace mavloc
