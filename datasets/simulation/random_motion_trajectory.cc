#include "datasets/simulation/random_motion_trajectory.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "core/random.h"
#include "core/rotation.h"

namespace mavloc {

namespace {

constexpr int kRandomMotionDegree = 5;  // quintic: C^4 position, C^2 acceleration
constexpr int kCentre =
    (kRandomMotionDegree - 1) / 2;  // the curve at knot i lies near control point i + 2

struct ProcessState {
  Eigen::Vector3d p_W, v_W;
  Eigen::Quaterniond q_W_B;
};

}  // namespace

RandomMotionTrajectory::RandomMotionTrajectory(const RandomMotionOptions& options,
                                               uint64_t motion_seed) {
  if (!(options.step_s > 0.0 && options.duration_s > 0.0 && options.correlation_time_s > 0.0 &&
        options.smoothing_spacing_s >= options.step_s)) {
    throw std::invalid_argument(
        "RandomMotionTrajectory: step, duration, correlation time > 0, smoothing >= step");
  }
  start_ns_ = options.start_ns;
  end_ns_ = start_ns_ + SecondsToNs(options.duration_s);
  const double dt = options.step_s;
  const int steps_per_control = static_cast<int>(std::lround(options.smoothing_spacing_s / dt));
  const double h = steps_per_control * dt;
  // Control point j is the process at time (j - kCentre) h; the spline covers [0, duration] when
  // num_control - kRandomMotionDegree segments reach past the end.
  const int num_segments = static_cast<int>(std::ceil(options.duration_s / h));
  const int num_control = num_segments + kRandomMotionDegree;
  const Eigen::Matrix3d R_W_P = options.q_W_P.toRotationMatrix();
  const Eigen::Matrix3d R_P_B_ref = options.q_P_B_ref.toRotationMatrix();
  const Eigen::Matrix3d R_W_B_ref = R_W_P * R_P_B_ref;
  const double rho = std::exp(-dt / options.correlation_time_s);
  const double spread = std::sqrt(1.0 - rho * rho);

  Rng rng(motion_seed);
  // Start the random parts in their stationary distribution. Control point kCentre is the initial
  // state; the ones before it continue the initial motion backwards at constant velocity and
  // attitude, so the curve starts near p0, v0 and the reference attitude.
  Eigen::Vector3d random_accel_P = rng.Gaussian3(options.sigma_accel_m_s2);
  Eigen::Vector3d random_rate_B = rng.Gaussian3(options.sigma_rate_rad_s);
  ProcessState s{R_W_P * options.p0_P, R_W_P * options.v0_P, Eigen::Quaterniond(R_W_B_ref)};
  Eigen::MatrixXd position_control(3, num_control), rotation_control(3, num_control);
  for (int j = 0; j < kCentre; ++j) {
    position_control.col(j) = s.p_W - (kCentre - j) * h * s.v_W;
    rotation_control.col(j).setZero();
  }
  for (int j = kCentre; j < num_control; ++j) {
    position_control.col(j) = s.p_W;
    const Eigen::Vector3d phi = LogSO3(R_W_B_ref.transpose() * s.q_W_B.toRotationMatrix());
    if (phi.norm() > 0.75 * M_PI)
      throw std::runtime_error("RandomMotionTrajectory: attitude left the reference by > 135 deg");
    rotation_control.col(j) = phi;
    for (int k = 0; k < steps_per_control; ++k) {
      // One process step: constant a_W and w_B (the paper's draws plus the mean-reverting pulls).
      const Eigen::Vector3d p_P = R_W_P.transpose() * s.p_W;
      const Eigen::Vector3d v_P = R_W_P.transpose() * s.v_W;
      const Eigen::Vector3d pull_P(-options.velocity_reversion_1_s * (v_P.x() - options.v0_P.x()),
                                   -options.velocity_reversion_1_s * (v_P.y() - options.v0_P.y()),
                                   -options.height_stiffness_1_s2 * (p_P.z() - options.p0_P.z()) -
                                       options.height_damping_1_s * v_P.z());
      const Eigen::Vector3d a_W = R_W_P * (pull_P + random_accel_P);
      const Eigen::Matrix3d R_P_B = R_W_P.transpose() * s.q_W_B.toRotationMatrix();
      const Eigen::Vector3d w_B =
          -options.attitude_reversion_1_s * LogSO3(R_P_B_ref.transpose() * R_P_B) + random_rate_B;
      s.p_W += s.v_W * dt + 0.5 * a_W * dt * dt;
      s.v_W += a_W * dt;
      s.q_W_B = (s.q_W_B * ExpQuaternion(w_B * dt)).normalized();
      random_accel_P = rho * random_accel_P + spread * rng.Gaussian3(options.sigma_accel_m_s2);
      random_rate_B = rho * random_rate_B + spread * rng.Gaussian3(options.sigma_rate_rad_s);
    }
  }
  // Exact start velocity v(0) = v0: the control points before the start (which only shape the
  // curve near t = 0) move together by delta; v(0) is linear in them, with gain g per metre.
  {
    const UniformBSpline before(kRandomMotionDegree, 0.0, h, position_control);
    Eigen::MatrixXd unit = Eigen::MatrixXd::Zero(1, num_control);
    unit.leftCols(kCentre).setOnes();
    const double g = UniformBSpline(kRandomMotionDegree, 0.0, h, unit).Evaluate(0.0, 1)[0];
    const Eigen::Vector3d delta = (R_W_P * options.v0_P - before.Evaluate(0.0, 1)) / g;
    position_control.leftCols(kCentre).colwise() += delta;
  }
  position_ = std::make_unique<UniformBSpline>(kRandomMotionDegree, 0.0, h, position_control);
  rotation_ = std::make_unique<UniformBSpline>(kRandomMotionDegree, 0.0, h, rotation_control);

  // Exact start position and attitude: p(0) = p0, R(0) = R_W_B_ref (constant offsets).
  position_offset_W_ = R_W_P * options.p0_P - Eigen::Vector3d(position_->Evaluate(0.0, 0));
  const Eigen::Vector3d phi0 = rotation_->Evaluate(0.0, 0);
  q_W_ref_ = (Eigen::Quaterniond(R_W_B_ref) * ExpQuaternion(-phi0)).normalized();
}

TrajectorySample RandomMotionTrajectory::At(TimeNs t_ns) const {
  t_ns = std::clamp(t_ns, start_ns_, end_ns_);
  const double t = NsToSeconds(t_ns - start_ns_);
  TrajectorySample sample;
  sample.t_ns = t_ns;
  sample.p_W = position_->Evaluate(t, 0) + position_offset_W_;
  sample.v_W = position_->Evaluate(t, 1);
  sample.a_W = position_->Evaluate(t, 2);
  const Eigen::Vector3d phi = rotation_->Evaluate(t, 0);
  const Eigen::Vector3d phi_dot = rotation_->Evaluate(t, 1);
  sample.q_W_B = (q_W_ref_ * ExpQuaternion(phi)).normalized();
  sample.w_B = RightJacobianSO3(phi) * phi_dot;
  return sample;
}

}  // namespace mavloc
