// An analytic smooth motion and its noiseless IMU, shared by the solver suites (preintegration,
// smoother initialization): Euler angles and position are sums of sines.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <vector>

#include "core/imu.h"
#include "core/rotation.h"
#include "core/time.h"

namespace mavloc::testing {

struct AnalyticMotion {
  static EulerRpy Angles(double t) {
    return {0.3 * std::sin(1.1 * t), 0.2 * std::sin(0.7 * t + 0.5),
            0.8 * std::sin(0.4 * t) + 0.3 * t};
  }
  static EulerRpy AngleRates(double t) {
    return {0.33 * std::cos(1.1 * t), 0.14 * std::cos(0.7 * t + 0.5),
            0.32 * std::cos(0.4 * t) + 0.3};
  }
  static Eigen::Vector3d Position(double t) {
    return {2.0 * std::sin(0.5 * t), 1.5 * std::sin(0.8 * t), 1.0 + 0.3 * std::sin(1.2 * t)};
  }
  static Eigen::Vector3d Velocity(double t) {
    return {1.0 * std::cos(0.5 * t), 1.2 * std::cos(0.8 * t), 0.36 * std::cos(1.2 * t)};
  }
  static Eigen::Vector3d Acceleration(double t) {
    return {-0.5 * std::sin(0.5 * t), -0.96 * std::sin(0.8 * t), -0.432 * std::sin(1.2 * t)};
  }
  // Body rates of R = Rz(yaw) Ry(pitch) Rx(roll).
  static Eigen::Vector3d AngularVelocityB(double t) {
    const EulerRpy a = Angles(t), r = AngleRates(t);
    const double sr = std::sin(a.roll), cr = std::cos(a.roll);
    const double sp = std::sin(a.pitch), cp = std::cos(a.pitch);
    return {r.roll - r.yaw * sp, r.pitch * cr + r.yaw * cp * sr, -r.pitch * sr + r.yaw * cp * cr};
  }
};

// Samples at t = k / rate_hz, k = 0 .. duration * rate (t = 0 is time stamp 0).
inline std::vector<ImuSample> SimulateAnalyticImu(double rate_hz, double duration_s,
                                                  const ImuBiases& biases) {
  std::vector<ImuSample> samples;
  const int n = static_cast<int>(std::round(duration_s * rate_hz));
  for (int k = 0; k <= n; ++k) {
    const double t = k / rate_hz;
    ImuSample s;
    s.t_ns = SecondsToNs(t);
    const Eigen::Matrix3d R_W_B = RotationFromEuler(AnalyticMotion::Angles(t));
    s.gyro_rad_s = AnalyticMotion::AngularVelocityB(t) + biases.b_g;
    s.accel_m_s2 = R_W_B.transpose() * (AnalyticMotion::Acceleration(t) - GravityW()) + biases.b_a;
    samples.push_back(s);
  }
  return samples;
}

}  // namespace mavloc::testing
