#include "solver/laser/observability.h"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <vector>

namespace mavloc {

namespace {

constexpr int kDim = 11;
constexpr int kNumFields = 7;  // f0 .. f6
enum StateIndex { kRx = 0, kRy, kRz, kVx, kVy, kVz, kQt, kQx, kQy, kQz, kK };

// Forward-mode dual number with an 11-vector of derivatives; nesting Dual<Dual<T>> gives exact
// higher derivatives (each level is its own type, so perturbations never get confused).
template <typename T>
struct Dual {
  T v{};
  std::array<T, kDim> d{};
  Dual() = default;
  Dual(double c) : v(c) {  // NOLINT: constants promote implicitly
    d.fill(T(0.0));
  }
  Dual(const T& value, const std::array<T, kDim>& derivative) : v(value), d(derivative) {}
};

template <typename T>
Dual<T> operator+(const Dual<T>& a, const Dual<T>& b) {
  Dual<T> r = a;
  r.v = a.v + b.v;
  for (int j = 0; j < kDim; ++j) r.d[j] = a.d[j] + b.d[j];
  return r;
}
template <typename T>
Dual<T> operator-(const Dual<T>& a, const Dual<T>& b) {
  Dual<T> r = a;
  r.v = a.v - b.v;
  for (int j = 0; j < kDim; ++j) r.d[j] = a.d[j] - b.d[j];
  return r;
}
template <typename T>
Dual<T> operator-(const Dual<T>& a) {
  return Dual<T>(0.0) - a;
}
template <typename T>
Dual<T> operator*(const Dual<T>& a, const Dual<T>& b) {
  Dual<T> r;
  r.v = a.v * b.v;
  for (int j = 0; j < kDim; ++j) r.d[j] = a.d[j] * b.v + a.v * b.d[j];
  return r;
}
template <typename T>
Dual<T> operator/(const Dual<T>& a, const Dual<T>& b) {
  Dual<T> r;
  r.v = a.v / b.v;
  const T inv_b2 = T(1.0) / (b.v * b.v);
  for (int j = 0; j < kDim; ++j) r.d[j] = (a.d[j] * b.v - a.v * b.d[j]) * inv_b2;
  return r;
}
template <typename T>
Dual<T> operator*(double c, const Dual<T>& a) {
  return Dual<T>(c) * a;
}

template <typename T>
using StateT = std::array<T, kDim>;

// Outputs: 0 = h_cam (eq. 3), 1 = h_const (eq. 4).
template <typename T>
T Output(int which, const StateT<T>& S, double L) {
  const T& qt = S[kQt];
  const T& qx = S[kQx];
  const T& qy = S[kQy];
  const T& qz = S[kQz];
  if (which == 1) return qt * qt + qx * qx + qy * qy + qz * qz;
  const T& k = S[kK];
  const T numerator =
      L * (2.0 * k * qz * qy - 2.0 * k * qt * qx - qz * qz - qt * qt + qy * qy + qx * qx);
  const T denominator = S[kRz] + (2.0 * L) * qz * qx - (2.0 * L) * qy * k * qx -
                        (2.0 * L) * qy * qt - (2.0 * L) * qt * k * qz - k * S[kRy];
  return numerator / denominator;
}

// The vector fields f0..f6 of appendix B.
template <typename T>
StateT<T> Field(int i, const StateT<T>& S, double g) {
  StateT<T> f;
  f.fill(T(0.0));
  const T& qt = S[kQt];
  const T& qx = S[kQx];
  const T& qy = S[kQy];
  const T& qz = S[kQz];
  switch (i) {
    case 0:
      f[kRx] = S[kVx];
      f[kRy] = S[kVy];
      f[kRz] = S[kVz];
      f[kVz] = T(-g);
      break;
    case 1:
      f[kVx] = qt * qt + qx * qx - qy * qy - qz * qz;
      f[kVy] = 2.0 * qt * qz + 2.0 * qy * qx;
      f[kVz] = -2.0 * qt * qy + 2.0 * qz * qx;
      break;
    case 2:
      f[kVx] = -2.0 * qt * qz + 2.0 * qy * qx;
      f[kVy] = qt * qt + qy * qy - qz * qz - qx * qx;
      f[kVz] = 2.0 * qt * qx + 2.0 * qz * qy;
      break;
    case 3:
      f[kVx] = 2.0 * qt * qy + 2.0 * qz * qx;
      f[kVy] = -2.0 * qt * qx + 2.0 * qz * qy;
      f[kVz] = qt * qt + qz * qz - qx * qx - qy * qy;
      break;
    case 4:
      f[kQt] = -0.5 * qx;
      f[kQx] = 0.5 * qt;
      f[kQy] = 0.5 * qz;
      f[kQz] = -0.5 * qy;
      break;
    case 5:
      f[kQt] = -0.5 * qy;
      f[kQx] = -0.5 * qz;
      f[kQy] = 0.5 * qt;
      f[kQz] = 0.5 * qx;
      break;
    case 6:
      f[kQt] = -0.5 * qz;
      f[kQx] = 0.5 * qy;
      f[kQy] = -0.5 * qx;
      f[kQz] = 0.5 * qt;
      break;
    default:
      break;
  }
  return f;
}

// L_{f_{fields[N-1]}} ... L_{f_{fields[0]}} h, evaluated in scalar type T.
template <int N, typename T>
T Lie(const int* fields, int which, const StateT<T>& S, double L, double g) {
  if constexpr (N == 0) {
    return Output<T>(which, S, L);
  } else {
    StateT<Dual<T>> seeded;
    for (int j = 0; j < kDim; ++j) {
      std::array<T, kDim> unit;
      unit.fill(T(0.0));
      unit[j] = T(1.0);
      seeded[j] = Dual<T>(S[j], unit);
    }
    const Dual<T> inner = Lie<N - 1, Dual<T>>(fields, which, seeded, L, g);
    const StateT<T> f = Field<T>(fields[N - 1], S, g);
    T out(0.0);
    for (int j = 0; j < kDim; ++j) out = out + inner.d[j] * f[j];
    return out;
  }
}

// Gradient of an order-N Lie derivative at S.
template <int N>
Eigen::Matrix<double, 1, kDim> LieGradient(const int* fields, int which, const LaserSystemState& S,
                                           double L, double g) {
  StateT<Dual<double>> seeded;
  for (int j = 0; j < kDim; ++j) {
    std::array<double, kDim> unit{};
    unit[j] = 1.0;
    seeded[j] = Dual<double>(S[j], unit);
  }
  const Dual<double> value = Lie<N, Dual<double>>(fields, which, seeded, L, g);
  Eigen::Matrix<double, 1, kDim> row;
  for (int j = 0; j < kDim; ++j) row[j] = value.d[j];
  return row;
}

}  // namespace

ObservabilityResult LaserObservability(const LaserSystemState& S,
                                       const ObservabilityOptions& options) {
  const int max_order = std::clamp(options.max_order, 0, 2);
  const double L = options.L_m, g = options.gravity_m_s2;
  std::vector<Eigen::Matrix<double, 1, kDim>> rows;
  for (int which = 0; which < 2; ++which) {
    rows.push_back(LieGradient<0>(nullptr, which, S, L, g));
    if (max_order >= 1) {
      for (int i = 0; i < kNumFields; ++i) rows.push_back(LieGradient<1>(&i, which, S, L, g));
    }
    if (max_order >= 2) {
      for (int i = 0; i < kNumFields; ++i) {
        for (int j = 0; j < kNumFields; ++j) {
          const int fields[2] = {i, j};
          rows.push_back(LieGradient<2>(fields, which, S, L, g));
        }
      }
    }
  }
  ObservabilityResult result;
  result.rows = static_cast<int>(rows.size());
  result.matrix.resize(result.rows, kDim);
  for (int r = 0; r < result.rows; ++r) result.matrix.row(r) = rows[r];
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(result.matrix);
  result.singular_values = svd.singularValues();
  const double largest = result.singular_values.size() > 0 ? result.singular_values[0] : 0.0;
  for (int i = 0; i < result.singular_values.size(); ++i) {
    if (result.singular_values[i] > options.rank_tolerance * largest) ++result.rank;
  }
  return result;
}

LaserSystemState RandomLaserSystemState(Rng& rng, double L_m) {
  LaserSystemState S;
  while (true) {
    for (int j = 0; j < 6; ++j) S[j] = rng.Uniform(-1.0, 1.0);
    Eigen::Vector4d q{rng.Gaussian(), rng.Gaussian(), rng.Gaussian(), rng.Gaussian()};
    S.segment<4>(kQt) = q.normalized();
    S[kK] = rng.Uniform(-1.0, 1.0);
    const double distance = (S[kRz] - S[kK] * S[kRy]) / std::sqrt(1.0 + S[kK] * S[kK]);
    const double h = LaserSystemOutput(S, L_m);
    if (distance > 0.5 && std::isfinite(h) && std::abs(h) < 2.0 && std::abs(h) > 0.05) return S;
  }
}

std::array<LaserSystemState, 5> LaserSymmetries(const LaserSystemState& S) {
  const double k = S[kK], qt = S[kQt], qx = S[kQx], qy = S[kQy], qz = S[kQz];
  std::array<LaserSystemState, 5> w;
  for (auto& wi : w) wi.setZero();
  w[0][kRy] = 1.0;
  w[0][kRz] = k;
  w[1][kRx] = 1.0;
  w[2][kVy] = 1.0;
  w[2][kVz] = k;
  w[3][kVx] = 1.0;
  w[4][kQt] = qz - k * qy;
  w[4][kQx] = qy + k * qz;
  w[4][kQy] = -qx + k * qt;
  w[4][kQz] = -qt - k * qx;
  return w;
}

Eigen::Matrix<double, 6, 1> LaserObservableModesAppendixB(const LaserSystemState& S) {
  const double k = S[kK], qt = S[kQt], qx = S[kQx], qy = S[kQy], qz = S[kQz];
  const double half = 0.5 * std::atan(k);
  const double ck = std::cos(half), sk = std::sin(half);
  const double norm = std::sqrt(1.0 + k * k);
  Eigen::Matrix<double, 6, 1> m;
  m[0] = (S[kRz] - k * S[kRy]) / norm;
  m[1] = (S[kVz] - k * S[kVy]) / norm;
  m[2] = 2.0 * (ck * sk * (-qt * qt + qx * qx - qy * qy + qz * qz) +
                (2.0 * ck * ck - 1.0) * (qt * qx + qy * qz));
  m[3] = 4.0 * ck * sk * (qt * qz + qx * qy) + 2.0 * (2.0 * ck * ck - 1.0) * (qt * qy - qx * qz);
  m[4] = k;
  m[5] = qt * qt + qx * qx + qy * qy + qz * qz;
  return m;
}

double LaserSystemOutput(const LaserSystemState& S, double L_m) {
  StateT<double> s;
  for (int j = 0; j < kDim; ++j) s[j] = S[j];
  return Output<double>(0, s, L_m);
}

LaserSystemState LaserSystemField(int i, const LaserSystemState& S, double gravity_m_s2) {
  StateT<double> s;
  for (int j = 0; j < kDim; ++j) s[j] = S[j];
  const StateT<double> f = Field<double>(i, s, gravity_m_s2);
  LaserSystemState out;
  for (int j = 0; j < kDim; ++j) out[j] = f[j];
  return out;
}

}  // namespace mavloc
