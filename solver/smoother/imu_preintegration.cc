#include "solver/smoother/imu_preintegration.h"

#include <ceres/jet.h>

#include <Eigen/Cholesky>
#include <algorithm>

#include "core/rotation.h"

namespace mavloc {

namespace {

// The biases as 6 infinitesimal directions (d b_g, d b_a) for forward-mode differentiation.
using Jet6 = ceres::Jet<double, 6>;
template <typename T>
using Vec3 = Eigen::Matrix<T, 3, 1>;
template <typename T>
using Vec4 = Eigen::Matrix<T, 4, 1>;  // quaternion (w, x, y, z)

template <typename T>
Vec4<T> QuaternionProduct(const Vec4<T>& a, const Vec4<T>& b) {
  return Vec4<T>(a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
                 a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
                 a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1],
                 a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0]);
}

// Rotates v by the (not necessarily unit) quaternion q / |q|.
template <typename T>
Vec3<T> Rotate(const Vec4<T>& q_raw, const Vec3<T>& v) {
  const Vec4<T> q = q_raw / q_raw.norm();
  const Vec4<T> qv(T(0.0), v[0], v[1], v[2]);
  const Vec4<T> q_conj(q[0], -q[1], -q[2], -q[3]);
  const Vec4<T> r = QuaternionProduct(QuaternionProduct(q, qv), q_conj);
  return Vec3<T>(r[1], r[2], r[3]);
}

template <typename T>
struct DeltaState {
  Vec4<T> q;
  Vec3<T> v;
  Vec3<T> p;
};

template <typename T>
struct DeltaDerivative {
  Vec4<T> dq;
  Vec3<T> dv;
  Vec3<T> dp;
};

template <typename T>
DeltaDerivative<T> Derivative(const DeltaState<T>& x, const Vec3<T>& w_B, const Vec3<T>& f_B) {
  const Vec4<T> omega(T(0.0), w_B[0], w_B[1], w_B[2]);
  DeltaDerivative<T> d;
  d.dq = T(0.5) * QuaternionProduct(x.q, omega);
  d.dv = Rotate(x.q, f_B);
  d.dp = x.v;
  return d;
}

template <typename T>
DeltaState<T> Advance(const DeltaState<T>& x, const DeltaDerivative<T>& d, double h) {
  return {x.q + T(h) * d.dq, x.v + T(h) * d.dv, x.p + T(h) * d.dp};
}

Vec3<Jet6> ToJet(const Eigen::Vector3d& v) { return v.cast<Jet6>(); }

}  // namespace

ImuPreintegration::ImuPreintegration(const std::vector<ImuSample>& samples, TimeNs t_i_ns,
                                     TimeNs t_j_ns, const ImuBiases& linearization_biases,
                                     const ImuNoise& noise)
    : t_i_ns_(t_i_ns),
      t_j_ns_(t_j_ns),
      dt_s_(NsToSeconds(t_j_ns - t_i_ns)),
      biases0_(linearization_biases),
      noise_(noise) {
  Propagate(samples);
}

void ImuPreintegration::Repropagate(const std::vector<ImuSample>& samples,
                                    const ImuBiases& linearization_biases) {
  biases0_ = linearization_biases;
  Propagate(samples);
}

void ImuPreintegration::Propagate(const std::vector<ImuSample>& samples) {
  num_steps_ = 0;
  covariance_.setZero();
  const ImuIntegrator integrator(&samples);
  const ImuBiases zero_biases;

  // Bias as Jets: b = b0 + delta, delta the 6 infinitesimal directions.
  Vec3<Jet6> b_g, b_a;
  for (int k = 0; k < 3; ++k) {
    b_g[k] = Jet6(biases0_.b_g[k], k);
    b_a[k] = Jet6(biases0_.b_a[k], 3 + k);
  }
  DeltaState<Jet6> x{Vec4<Jet6>(Jet6(1.0), Jet6(0.0), Jet6(0.0), Jet6(0.0)), Vec3<Jet6>::Zero(),
                     Vec3<Jet6>::Zero()};

  const double var_g = noise_.gyroscope_noise_density * noise_.gyroscope_noise_density;
  const double var_a = noise_.accelerometer_noise_density * noise_.accelerometer_noise_density;

  auto it = std::upper_bound(samples.begin(), samples.end(), t_i_ns_,
                             [](TimeNs t, const ImuSample& s) { return t < s.t_ns; });
  TimeNs t_ns = t_i_ns_;
  while (t_ns < t_j_ns_) {
    const TimeNs next_ns = (it != samples.end() && it->t_ns < t_j_ns_) ? it->t_ns : t_j_ns_;
    if (it != samples.end() && it->t_ns <= next_ns) ++it;
    const double h = NsToSeconds(next_ns - t_ns);

    // The raw interpolated signal at the start, middle and end of the interval (no bias).
    Eigen::Vector3d w0, f0, w1, f1, w2, f2;
    integrator.SignalAt(t_ns, 0.0, zero_biases, &w0, &f0);
    integrator.SignalAt(t_ns, 0.5 * h, zero_biases, &w1, &f1);
    integrator.SignalAt(t_ns, h, zero_biases, &w2, &f2);

    // Covariance step (eq. 62-63), at the linearization point, before the state advances.
    {
      const Eigen::Vector4d q_k(x.q[0].a, x.q[1].a, x.q[2].a, x.q[3].a);
      const Eigen::Matrix3d dR_k =
          Eigen::Quaterniond(q_k[0], q_k[1], q_k[2], q_k[3]).normalized().toRotationMatrix();
      const Eigen::Vector3d w_mid = w1 - biases0_.b_g;
      const Eigen::Vector3d a_mid = f1 - biases0_.b_a;
      PreintegrationStepMatrices m;
      m.dt_s = h;
      m.A.setIdentity();
      m.A.block<3, 3>(0, 0) = ExpSO3(w_mid * h).transpose();
      m.A.block<3, 3>(3, 0) = -dR_k * Skew(a_mid) * h;
      m.A.block<3, 3>(6, 0) = -0.5 * dR_k * Skew(a_mid) * h * h;
      m.A.block<3, 3>(6, 3) = Eigen::Matrix3d::Identity() * h;
      m.B.block<3, 3>(0, 0) = RightJacobianSO3(w_mid * h) * h;
      m.B.block<3, 3>(3, 3) = dR_k * h;
      m.B.block<3, 3>(6, 3) = 0.5 * dR_k * h * h;
      if (h > 0.0) {
        Eigen::Matrix<double, 6, 6> noise_cov = Eigen::Matrix<double, 6, 6>::Zero();
        noise_cov.diagonal().head<3>().setConstant(var_g / h);
        noise_cov.diagonal().tail<3>().setConstant(var_a / h);
        covariance_ = m.A * covariance_ * m.A.transpose() + m.B * noise_cov * m.B.transpose();
      }
      ++num_steps_;
    }

    // RK4 step of the mean with the bias Jets.
    const Vec3<Jet6> w0j = ToJet(w0) - b_g, w1j = ToJet(w1) - b_g, w2j = ToJet(w2) - b_g;
    const Vec3<Jet6> f0j = ToJet(f0) - b_a, f1j = ToJet(f1) - b_a, f2j = ToJet(f2) - b_a;
    const DeltaDerivative<Jet6> k1 = Derivative(x, w0j, f0j);
    const DeltaDerivative<Jet6> k2 = Derivative(Advance(x, k1, 0.5 * h), w1j, f1j);
    const DeltaDerivative<Jet6> k3 = Derivative(Advance(x, k2, 0.5 * h), w1j, f1j);
    const DeltaDerivative<Jet6> k4 = Derivative(Advance(x, k3, h), w2j, f2j);
    const Jet6 sixth(h / 6.0);
    x.q += sixth * (k1.dq + Jet6(2.0) * k2.dq + Jet6(2.0) * k3.dq + k4.dq);
    x.q /= x.q.norm();
    x.v += sixth * (k1.dv + Jet6(2.0) * k2.dv + Jet6(2.0) * k3.dv + k4.dv);
    x.p += sixth * (k1.dp + Jet6(2.0) * k2.dp + Jet6(2.0) * k3.dp + k4.dp);
    t_ns = next_ns;
  }
  covariance_ = 0.5 * (covariance_ + covariance_.transpose()).eval();

  // Values and bias Jacobians.
  delta_q_ = Eigen::Quaterniond(x.q[0].a, x.q[1].a, x.q[2].a, x.q[3].a).normalized();
  for (int k = 0; k < 3; ++k) {
    delta_v_[k] = x.v[k].a;
    delta_p_[k] = x.p[k].a;
    J_v_bg_.row(k) = x.v[k].v.head<3>().transpose();
    J_v_ba_.row(k) = x.v[k].v.tail<3>().transpose();
    J_p_bg_.row(k) = x.p[k].v.head<3>().transpose();
    J_p_ba_.row(k) = x.p[k].v.tail<3>().transpose();
  }
  // dR(b0 + d) = dR Exp(J_R_bg d_g)  =>  dq/dd_g = q0 (x) [0, 1/2 J_R_bg]  =>
  // J_R_bg = 2 vec(q0^-1 (x) dq/dd_g).
  const Eigen::Vector4d q0_conj(delta_q_.w(), -delta_q_.x(), -delta_q_.y(), -delta_q_.z());
  for (int c = 0; c < 3; ++c) {
    const Eigen::Vector4d dq(x.q[0].v[c], x.q[1].v[c], x.q[2].v[c], x.q[3].v[c]);
    const Eigen::Vector4d r = QuaternionProduct<double>(q0_conj, dq);
    J_R_bg_.col(c) = 2.0 * r.tail<3>();
  }
}

Eigen::Matrix<double, 9, 9> ImuPreintegration::SqrtInformation(double rotation_floor_rad,
                                                               double velocity_floor_m_s,
                                                               double position_floor_m) const {
  Eigen::Matrix<double, 9, 9> cov = covariance_;
  cov.diagonal().segment<3>(0).array() += rotation_floor_rad * rotation_floor_rad;
  cov.diagonal().segment<3>(3).array() += velocity_floor_m_s * velocity_floor_m_s;
  cov.diagonal().segment<3>(6).array() += position_floor_m * position_floor_m;
  Eigen::Matrix<double, 9, 9> information =
      cov.ldlt().solve(Eigen::Matrix<double, 9, 9>::Identity());
  information = 0.5 * (information + information.transpose()).eval();
  return information.llt().matrixU();
}

Eigen::Quaterniond ImuPreintegration::CorrectedDeltaQ(const ImuBiases& biases) const {
  return (delta_q_ * ExpQuaternion(J_R_bg_ * (biases.b_g - biases0_.b_g))).normalized();
}

Eigen::Vector3d ImuPreintegration::CorrectedDeltaV(const ImuBiases& biases) const {
  return delta_v_ + J_v_bg_ * (biases.b_g - biases0_.b_g) + J_v_ba_ * (biases.b_a - biases0_.b_a);
}

Eigen::Vector3d ImuPreintegration::CorrectedDeltaP(const ImuBiases& biases) const {
  return delta_p_ + J_p_bg_ * (biases.b_g - biases0_.b_g) + J_p_ba_ * (biases.b_a - biases0_.b_a);
}

ImuKeyframeState ImuPreintegration::Predict(const ImuKeyframeState& state_i) const {
  const Eigen::Vector3d g_W = GravityW();
  ImuKeyframeState state_j;
  state_j.biases = state_i.biases;
  state_j.q_W_B = (state_i.q_W_B * CorrectedDeltaQ(state_i.biases)).normalized();
  state_j.v_W = state_i.v_W + g_W * dt_s_ + state_i.q_W_B * CorrectedDeltaV(state_i.biases);
  state_j.p_W = state_i.p_W + state_i.v_W * dt_s_ + 0.5 * g_W * dt_s_ * dt_s_ +
                state_i.q_W_B * CorrectedDeltaP(state_i.biases);
  return state_j;
}

}  // namespace mavloc
