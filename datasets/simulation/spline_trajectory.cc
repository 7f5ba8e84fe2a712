#include "datasets/simulation/spline_trajectory.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "core/imu.h"
#include "core/rotation.h"

namespace mavloc {

namespace {

constexpr int kSplineDegree = 5;  // quintic: C^4, smooth jerk, so the quadrotor attitude is C^2

// d/dt of v/|v| given v and dv/dt.
Eigen::Vector3d NormalizedDerivative(const Eigen::Vector3d& v, const Eigen::Vector3d& dv) {
  const double n = v.norm();
  const Eigen::Vector3d u = v / n;
  return (dv - u * u.dot(dv)) / n;
}

// Linear interpolation of the waypoints at time t (held at the ends); yaw is unwrapped by the
// caller so that interpolation follows the intended direction.
Eigen::VectorXd InterpolateWaypoints(const std::vector<Eigen::VectorXd>& values,
                                     const std::vector<double>& times, double t) {
  if (t <= times.front()) return values.front();
  if (t >= times.back()) return values.back();
  const auto it = std::upper_bound(times.begin(), times.end(), t);
  const size_t i = static_cast<size_t>(it - times.begin()) - 1;
  const double a = (t - times[i]) / (times[i + 1] - times[i]);
  return (1.0 - a) * values[i] + a * values[i + 1];
}

}  // namespace

SplineTrajectory::SplineTrajectory(TimeNs t0_ns, UniformBSpline position, UniformBSpline attitude,
                                   AttitudeMode mode)
    : t0_ns_(t0_ns), position_(std::move(position)), attitude_(std::move(attitude)), mode_(mode) {
  if (position_.dimension() != 3) throw std::invalid_argument("position spline must be 3-D");
  const int expected = mode_ == AttitudeMode::kQuadrotor ? 1 : 3;
  if (attitude_.dimension() != expected)
    throw std::invalid_argument("attitude spline has the wrong dimension for its mode");
}

std::unique_ptr<SplineTrajectory> SplineTrajectory::FromWaypoints(
    TimeNs t0_ns, const std::vector<Waypoint>& waypoints, AttitudeMode mode, double control_dt_s) {
  if (waypoints.empty()) throw std::invalid_argument("FromWaypoints: no waypoints");
  std::vector<double> times;
  std::vector<Eigen::VectorXd> positions, angles;
  double previous_yaw = waypoints.front().yaw_rad;
  for (size_t i = 0; i < waypoints.size(); ++i) {
    const Waypoint& w = waypoints[i];
    if (i > 0 && !(w.t_s > waypoints[i - 1].t_s))
      throw std::invalid_argument("FromWaypoints: waypoint times must increase");
    times.push_back(w.t_s);
    positions.push_back(w.p_W);
    const double yaw = previous_yaw + WrapAngle(w.yaw_rad - previous_yaw);  // unwrap
    previous_yaw = yaw;
    if (mode == AttitudeMode::kQuadrotor) {
      angles.push_back(Eigen::VectorXd::Constant(1, yaw));
    } else {
      angles.push_back(Eigen::Vector3d(w.roll_rad, w.pitch_rad, yaw));
    }
  }
  // Control points: K+1 copies of the first waypoint (at rest), the path sampled every
  // control_dt_s, then K+1 copies of the last. The spline's time origin is shifted so that the
  // valid interval starts at the first waypoint's time.
  const double t_first = times.front(), t_last = times.back();
  const int interior =
      std::max(0, static_cast<int>(std::ceil((t_last - t_first) / control_dt_s)) - 1);
  const int n = 2 * (kSplineDegree + 1) + interior;
  Eigen::MatrixXd cp_position(3, n), cp_angles(angles.front().size(), n);
  for (int c = 0; c < n; ++c) {
    // The path is sampled at the Greville abscissa of control point c, t_first + (c - (K-1)/2) dt,
    // where c has its largest weight; the first and last K+1 points are then pinned (at rest).
    const double t_c = t_first + (c - 0.5 * (kSplineDegree - 1)) * control_dt_s;
    cp_position.col(c) = InterpolateWaypoints(positions, times, t_c);
    cp_angles.col(c) = InterpolateWaypoints(angles, times, t_c);
  }
  for (int c = 0; c <= kSplineDegree; ++c) {
    cp_position.col(c) = positions.front();
    cp_angles.col(c) = angles.front();
    cp_position.col(n - 1 - c) = positions.back();
    cp_angles.col(n - 1 - c) = angles.back();
  }
  // Valid interval of the spline: [t_first, t_first + (n - K) dt].
  UniformBSpline position(kSplineDegree, t_first, control_dt_s, cp_position);
  UniformBSpline attitude(kSplineDegree, t_first, control_dt_s, cp_angles);
  return std::make_unique<SplineTrajectory>(t0_ns, std::move(position), std::move(attitude), mode);
}

TimeNs SplineTrajectory::start_ns() const { return t0_ns_ + SecondsToNs(position_.start_time()); }

TimeNs SplineTrajectory::end_ns() const { return t0_ns_ + SecondsToNs(position_.end_time()); }

TrajectorySample SplineTrajectory::At(TimeNs t_ns) const {
  const double t = NsToSeconds(t_ns - t0_ns_);
  TrajectorySample s;
  s.t_ns = t_ns;
  s.p_W = position_.Evaluate(t, 0);
  s.v_W = position_.Evaluate(t, 1);
  s.a_W = position_.Evaluate(t, 2);
  Eigen::Matrix3d R, R_dot;
  if (mode_ == AttitudeMode::kQuadrotor) {
    // Differential flatness: z_B along the thrust a_W - g_W; x_B in the plane of z_B and the
    // heading x_C = (cos yaw, sin yaw, 0): y_B = z_B x x_C / |.|, x_B = y_B x z_B.
    const Eigen::Vector3d jerk = position_.Evaluate(t, 3);
    const double yaw = attitude_.Evaluate(t, 0)[0];
    const double yaw_rate = attitude_.Evaluate(t, 1)[0];
    const Eigen::Vector3d thrust = s.a_W - GravityW();
    const Eigen::Vector3d z_B = thrust.normalized();
    const Eigen::Vector3d z_B_dot = NormalizedDerivative(thrust, jerk);
    const Eigen::Vector3d x_C(std::cos(yaw), std::sin(yaw), 0.0);
    const Eigen::Vector3d x_C_dot = yaw_rate * Eigen::Vector3d(-std::sin(yaw), std::cos(yaw), 0.0);
    const Eigen::Vector3d y = z_B.cross(x_C);
    const Eigen::Vector3d y_dot = z_B_dot.cross(x_C) + z_B.cross(x_C_dot);
    const Eigen::Vector3d y_B = y.normalized();
    const Eigen::Vector3d y_B_dot = NormalizedDerivative(y, y_dot);
    const Eigen::Vector3d x_B = y_B.cross(z_B);
    const Eigen::Vector3d x_B_dot = y_B_dot.cross(z_B) + y_B.cross(z_B_dot);
    R << x_B, y_B, z_B;
    R_dot << x_B_dot, y_B_dot, z_B_dot;
  } else {
    // R = Rz(yaw) Ry(pitch) Rx(roll); dR/dt by the product rule.
    const Eigen::Vector3d rpy = attitude_.Evaluate(t, 0);
    const Eigen::Vector3d rpy_dot = attitude_.Evaluate(t, 1);
    const Eigen::Matrix3d Rx_ = Rx(rpy[0]), Ry_ = Ry(rpy[1]), Rz_ = Rz(rpy[2]);
    R = Rz_ * Ry_ * Rx_;
    R_dot = Rz_ * Skew(Eigen::Vector3d::UnitZ() * rpy_dot[2]) * Ry_ * Rx_ +
            Rz_ * Ry_ * Skew(Eigen::Vector3d::UnitY() * rpy_dot[1]) * Rx_ +
            R * Skew(Eigen::Vector3d::UnitX() * rpy_dot[0]);
  }
  s.q_W_B = Eigen::Quaterniond(R).normalized();
  s.w_B = Vee(R.transpose() * R_dot);  // R_dot = R [w_B]x
  return s;
}

}  // namespace mavloc
