#include "solver/imu/imu_integrator.h"

#include <algorithm>
#include <stdexcept>

#include "core/imu.h"

namespace mavloc {

namespace {

struct ImuDerivative {
  Eigen::Vector4d dq;  // (w, x, y, z) derivative of the quaternion
  Eigen::Vector3d dv;
  Eigen::Vector3d dp;
};

ImuDerivative Evaluate(const Eigen::Quaterniond& q, const Eigen::Vector3d& v,
                       const Eigen::Vector3d& w, const Eigen::Vector3d& f) {
  const Eigen::Quaterniond omega(0.0, w.x(), w.y(), w.z());
  const Eigen::Quaterniond qdot = q * omega;
  ImuDerivative d;
  d.dq = 0.5 * Eigen::Vector4d(qdot.w(), qdot.x(), qdot.y(), qdot.z());
  d.dv = q.normalized() * f + GravityW();
  d.dp = v;
  return d;
}

Eigen::Quaterniond Add(const Eigen::Quaterniond& q, const Eigen::Vector4d& dq) {
  return Eigen::Quaterniond(q.w() + dq[0], q.x() + dq[1], q.y() + dq[2], q.z() + dq[3]);
}

}  // namespace

void ImuIntegrator::SignalAt(TimeNs t0_ns, double offset_s, const ImuBiases& biases,
                             Eigen::Vector3d* w_B, Eigen::Vector3d* f_B) const {
  const auto& s = *samples_;
  if (s.size() < 2) throw std::invalid_argument("ImuIntegrator: fewer than 2 samples");
  const TimeNs t_ns = t0_ns + SecondsToNs(offset_s);
  // Index i with s[i].t <= t < s[i+1].t (clamped).
  auto it = std::upper_bound(s.begin(), s.end(), t_ns,
                             [](TimeNs t, const ImuSample& sample) { return t < sample.t_ns; });
  long i =
      std::clamp<long>(static_cast<long>(it - s.begin()) - 1, 0, static_cast<long>(s.size()) - 2);
  // Four nodes i-1 .. i+2 when available (cubic), else the two nodes i, i+1 (linear).
  long first = i - 1, last = i + 2;
  if (first < 0 || last >= static_cast<long>(s.size())) {
    first = i;
    last = i + 1;
  }
  const double tau = NsToSeconds(t0_ns - s[i].t_ns) + offset_s;  // time since node i
  Eigen::Vector3d w = Eigen::Vector3d::Zero(), f = Eigen::Vector3d::Zero();
  for (long j = first; j <= last; ++j) {
    double weight = 1.0;
    const double tj = NsToSeconds(s[j].t_ns - s[i].t_ns);
    for (long m = first; m <= last; ++m) {
      if (m == j) continue;
      const double tm = NsToSeconds(s[m].t_ns - s[i].t_ns);
      weight *= (tau - tm) / (tj - tm);
    }
    w += weight * s[j].gyro_rad_s;
    f += weight * s[j].accel_m_s2;
  }
  *w_B = w - biases.b_g;
  *f_B = f - biases.b_a;
}

NavState ImuIntegrator::Step(const NavState& x, TimeNs dt_ns, const ImuBiases& biases) const {
  const double dt_s = NsToSeconds(dt_ns);
  Eigen::Vector3d w0, f0, w1, f1, w2, f2;
  SignalAt(x.t_ns, 0.0, biases, &w0, &f0);
  SignalAt(x.t_ns, 0.5 * dt_s, biases, &w1, &f1);
  SignalAt(x.t_ns, dt_s, biases, &w2, &f2);
  const ImuDerivative k1 = Evaluate(x.q_W_B, x.v_W, w0, f0);
  const ImuDerivative k2 =
      Evaluate(Add(x.q_W_B, 0.5 * dt_s * k1.dq), x.v_W + 0.5 * dt_s * k1.dv, w1, f1);
  const ImuDerivative k3 =
      Evaluate(Add(x.q_W_B, 0.5 * dt_s * k2.dq), x.v_W + 0.5 * dt_s * k2.dv, w1, f1);
  const ImuDerivative k4 = Evaluate(Add(x.q_W_B, dt_s * k3.dq), x.v_W + dt_s * k3.dv, w2, f2);
  NavState next;
  next.q_W_B = Add(x.q_W_B, dt_s / 6.0 * (k1.dq + 2.0 * k2.dq + 2.0 * k3.dq + k4.dq)).normalized();
  next.v_W = x.v_W + dt_s / 6.0 * (k1.dv + 2.0 * k2.dv + 2.0 * k3.dv + k4.dv);
  next.p_W = x.p_W + dt_s / 6.0 * (k1.dp + 2.0 * k2.dp + 2.0 * k3.dp + k4.dp);
  next.t_ns = x.t_ns + dt_ns;
  return next;
}

NavState ImuIntegrator::Integrate(const NavState& state, TimeNs t_end_ns,
                                  const ImuBiases& biases) const {
  NavState x = state;
  const auto& s = *samples_;
  auto it = std::upper_bound(s.begin(), s.end(), x.t_ns,
                             [](TimeNs t, const ImuSample& sample) { return t < sample.t_ns; });
  while (x.t_ns < t_end_ns) {
    const TimeNs next_ns = (it != s.end() && it->t_ns < t_end_ns) ? it->t_ns : t_end_ns;
    x = Step(x, next_ns - x.t_ns, biases);
    if (it != s.end() && it->t_ns <= next_ns) ++it;
  }
  return x;
}

}  // namespace mavloc
