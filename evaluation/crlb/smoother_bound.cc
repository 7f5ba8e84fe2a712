#include "evaluation/crlb/smoother_bound.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "core/board_frame.h"
#include "core/heap_release.h"
#include "core/imu.h"
#include "core/rotation.h"
#include "core/tag_geometry.h"
#include "evaluation/crlb/laser_bound.h"
#include "evaluation/crlb/markov_information.h"
#include "evaluation/crlb/pixel_jacobian.h"
#include "solver/estimators/smoother_estimator.h"
#include "solver/smoother/smoother_initialization.h"

namespace mavloc {

namespace {

constexpr TimeNs kAttachToleranceNs = 1'000'000;  // the smoother's: 1 ms

ImuNoise WithFloor(const ImuNoise& noise, const ImuNoise& floor) {
  return {std::max(noise.gyroscope_noise_density, floor.gyroscope_noise_density),
          std::max(noise.gyroscope_random_walk, floor.gyroscope_random_walk),
          std::max(noise.accelerometer_noise_density, floor.accelerometer_noise_density),
          std::max(noise.accelerometer_random_walk, floor.accelerometer_random_walk)};
}

// Linearised transition of the error state from t0 to t1 (see the header): Phi and Q. With
// true_rates, the rate and specific force held over each interval [a, b) are the true ones
// (from the ground truth at a and b) instead of the bias-corrected sample.
void ImuTransition(const Dataset& dataset, const ImuNoise& noise, TimeNs t0, TimeNs t1,
                   bool true_rates, Matrix15d* Phi, Matrix15d* Q) {
  const auto& samples = dataset.imu.samples;
  Phi->setIdentity();
  Q->setZero();
  auto it = std::upper_bound(samples.begin(), samples.end(), t0,
                             [](TimeNs t, const ImuSample& s) { return t < s.t_ns; });
  // The sample held over [a, b): the last one at or before a.
  size_t held = it == samples.begin() ? 0 : static_cast<size_t>(it - samples.begin()) - 1;
  TimeNs a = t0;
  const double var_g = noise.gyroscope_noise_density * noise.gyroscope_noise_density;
  const double var_a = noise.accelerometer_noise_density * noise.accelerometer_noise_density;
  const double var_wg = noise.gyroscope_random_walk * noise.gyroscope_random_walk;
  const double var_wa = noise.accelerometer_random_walk * noise.accelerometer_random_walk;
  while (a < t1) {
    TimeNs b = t1;
    if (held + 1 < samples.size() && samples[held + 1].t_ns < t1 && samples[held + 1].t_ns > a)
      b = samples[held + 1].t_ns;
    const double h = NsToSeconds(b - a);
    const GroundTruthState truth = InterpolatedTruth(dataset.ground_truth, a);
    const Eigen::Matrix3d R = truth.T_W_B.R();
    Eigen::Vector3d w = samples[held].gyro_rad_s - truth.b_g;
    Eigen::Vector3d f = samples[held].accel_m_s2 - truth.b_a;
    Eigen::Vector3d f_p = f;  // the specific force in the position row
    if (true_rates) {
      // The exact increments of the true motion: R_b = R_a Exp(w h),
      // v_b - v_a - g h = R_a f h, p_b - p_a - v_a h - g h^2 / 2 = R_a f_p h^2 / 2.
      const GroundTruthState end = InterpolatedTruth(dataset.ground_truth, b);
      w = LogSO3(R.transpose() * end.T_W_B.R()) / h;
      f = R.transpose() * ((end.v_W - truth.v_W) / h - GravityW());
      f_p = R.transpose() *
            (2.0 * (end.T_W_B.p - truth.T_W_B.p - truth.v_W * h) / (h * h) - GravityW());
    }
    const Eigen::Matrix3d Jr = RightJacobianSO3(w * h);
    const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();

    Matrix15d F = Matrix15d::Identity();
    F.block<3, 3>(kCrlbP, kCrlbV) = h * I;
    F.block<3, 3>(kCrlbP, kCrlbTheta) = -0.5 * h * h * R * Skew(f_p);
    F.block<3, 3>(kCrlbP, kCrlbBa) = -0.5 * h * h * R;
    F.block<3, 3>(kCrlbTheta, kCrlbTheta) = ExpSO3(-w * h);
    F.block<3, 3>(kCrlbTheta, kCrlbBg) = -h * Jr;
    F.block<3, 3>(kCrlbV, kCrlbTheta) = -h * R * Skew(f);
    F.block<3, 3>(kCrlbV, kCrlbBa) = -h * R;

    // Noise of this interval: the sample noise (variance density / dt per sample, held over the
    // interval: velocity noise variance var_a h, position h^2/4 of it, correlation h/2) and the
    // bias walks.
    Matrix15d Qs = Matrix15d::Zero();
    Qs.block<3, 3>(kCrlbTheta, kCrlbTheta) = var_g * h * Jr * Jr.transpose();
    Qs.block<3, 3>(kCrlbV, kCrlbV) = var_a * h * I;
    Qs.block<3, 3>(kCrlbP, kCrlbP) = 0.25 * h * h * var_a * h * I;
    Qs.block<3, 3>(kCrlbP, kCrlbV) = 0.5 * h * var_a * h * I;
    Qs.block<3, 3>(kCrlbV, kCrlbP) = 0.5 * h * var_a * h * I;
    Qs.block<3, 3>(kCrlbBg, kCrlbBg) = var_wg * h * I;
    Qs.block<3, 3>(kCrlbBa, kCrlbBa) = var_wa * h * I;

    *Phi = F * *Phi;
    *Q = F * *Q * F.transpose() + Qs;
    a = b;
    if (held + 1 < samples.size() && samples[held + 1].t_ns <= a) ++held;
  }
}

// The true gravity direction in the board frame M, from the truth quantities board_roll and
// board_pitch (roll and pitch of R_W_M, core/board_frame.h; the scenario writes them per frame).
std::optional<Eigen::Vector3d> TrueUpInBoard(const Dataset& dataset) {
  const QuantityTable& q = dataset.truth_quantities;
  const int roll = q.Index("board_roll"), pitch = q.Index("board_pitch");
  if (roll < 0 || pitch < 0 || q.empty()) return std::nullopt;
  const double r = q.rows[0][roll], p = q.rows[0][pitch];
  if (!std::isfinite(r) || !std::isfinite(p)) return std::nullopt;
  return UpInBoard(Eigen::Matrix3d(Eigen::AngleAxisd(p, Eigen::Vector3d::UnitY()) *
                                   Eigen::AngleAxisd(r, Eigen::Vector3d::UnitX())));
}

// K (15 x 2): d(reported error state) / d(tilt d) at the truth. The smoother re-expresses its
// solution in the canonical W of core/board_frame.h, a rotation Rz(psi) about z_W with
// psi = psi(d) (solver/smoother/smoother_problem.cc): position and velocity turn by e_z x (.) psi,
// the attitude (R Exp(dtheta)) by R^T e_z psi. dpsi/dd by central differences of
// CanonicalBoardToWorldRotation(Exp((d1, d2, 0)) R_W_M).
Eigen::Matrix<double, 15, 2> CanonicalYawJacobian(const Eigen::Matrix3d& R_W_M, const Pose& T_W_B,
                                                  const Eigen::Vector3d& v_W) {
  const auto psi = [&](const Eigen::Vector2d& d) {
    const Eigen::Matrix3d R = ExpSO3(Eigen::Vector3d(d.x(), d.y(), 0.0)) * R_W_M;
    const Eigen::Matrix3d R_z = CanonicalBoardToWorldRotation(R) * R.transpose();
    return std::atan2(R_z(1, 0), R_z(0, 0));
  };
  const double h = 1e-6;
  Eigen::RowVector2d g;
  for (int c = 0; c < 2; ++c)
    g(c) = (psi(h * Eigen::Vector2d::Unit(c)) - psi(-h * Eigen::Vector2d::Unit(c))) / (2.0 * h);
  const Eigen::Vector3d e_z = Eigen::Vector3d::UnitZ();
  Eigen::Matrix<double, 15, 1> c = Eigen::Matrix<double, 15, 1>::Zero();
  c.segment<3>(kCrlbP) = e_z.cross(T_W_B.p);
  c.segment<3>(kCrlbTheta) = T_W_B.R().transpose() * e_z;
  c.segment<3>(kCrlbV) = e_z.cross(v_W);
  return c * g;
}

// tags0 or tags1 (with a second camera) holding a map tag (as the smoother decides laser-only).
bool HasMapTags(const Dataset& dataset) {
  const auto in_map = [&](const std::vector<TagObservation>& stream) {
    for (const TagObservation& obs : stream)
      if (dataset.map.tags.count(obs.tag_id)) return true;
    return false;
  };
  return in_map(dataset.tags) || (dataset.cameras.size() > 1 && in_map(dataset.tags1));
}

// Index of the keyframe within the smoother's attach tolerance of t_ns, or -1.
int KeyframeAt(const std::vector<TimeNs>& times, TimeNs t_ns) {
  auto it = std::lower_bound(times.begin(), times.end(), t_ns - kAttachToleranceNs);
  if (it == times.end() || *it > t_ns + kAttachToleranceNs) return -1;
  int best = static_cast<int>(it - times.begin());
  for (auto c = it; c != times.end() && *c <= t_ns + kAttachToleranceNs; ++c)
    if (std::abs(*c - t_ns) < std::abs(times[best] - t_ns))
      best = static_cast<int>(c - times.begin());
  return best;
}

}  // namespace

SmootherCrlb ComputeSmootherCrlb(const Dataset& dataset, const EstimatorOptions& smoother_options,
                                 const CrlbModelOptions& model) {
  const auto start = std::chrono::steady_clock::now();
  SmootherCrlb out;
  if (dataset.ground_truth.size() < 2 || dataset.imu.samples.size() < 2) {
    out.reason = "no ground truth or no IMU stream";
    return out;
  }
  if (dataset.cameras.empty()) {
    out.reason = "no camera";
    return out;
  }
  const SmootherEstimator smoother(smoother_options);
  const SmootherProblemOptions options = smoother.ProblemOptionsFor(dataset);
  const bool board = dataset.map.frame == MapFrame::kBoard;
  Eigen::Matrix3d R_W_M = Eigen::Matrix3d::Identity();
  if (board) {
    if (options.estimate_time_offset || options.estimate_extrinsics) {
      out.reason =
          "board map with estimate_time_offset or estimate_extrinsics: the time offset and the "
          "extrinsics are not in the bound's model (only the board tilt)";
      return out;
    }
    const auto up_M = TrueUpInBoard(dataset);
    if (!up_M) {
      out.reason = "board map without the true tilt (truth quantities board_roll, board_pitch)";
      return out;
    }
    R_W_M = BoardToWorldRotation(*up_M);
  }
  // Laser-only data (as SmootherEstimator::IsLaserOnly): the plane is a nuisance parameter.
  const bool laser_only =
      !dataset.laser.empty() && dataset.features.empty() && !HasMapTags(dataset);
  const bool features_used = !dataset.features.empty();
  if (features_used && options.landmarks != LandmarkMode::kKnown) {
    out.reason = options.features_as_bearings
                     ? "bearings: no finite Cramér–Rao bound (the simulated angular noise, a "
                       "Gaussian angle about a uniformly random axis, has a density with a 1/r "
                       "cusp at zero error and infinite Fisher information), and unknown "
                       "landmarks are not in the bound's model"
                     : "unknown landmarks (feature positions are parameters): not in the bound's "
                       "model";
    return out;
  }
  if (features_used && options.features_as_bearings) {
    out.reason =
        "bearings: no finite Cramér–Rao bound (the simulated angular noise has infinite Fisher "
        "information)";
    return out;
  }

  const std::vector<TimeNs> times =
      SmootherKeyframeTimes(dataset, smoother_options.GetInt("keyframe_stride", 1));
  const int n = static_cast<int>(times.size());
  if (n < 2) {
    out.reason = "fewer than 2 keyframes";
    return out;
  }
  MarkovInformation info;
  info.node.assign(n, Eigen::MatrixXd::Zero(15, 15));
  std::vector<GroundTruthState> truth(n);
  for (int k = 0; k < n; ++k) truth[k] = InterpolatedTruth(dataset.ground_truth, times[k]);

  std::optional<LaserSpotModel> laser;
  if (laser_only) {
    std::string why;
    laser = LaserSpotModelFor(dataset, options.laser_beam, options.laser_sigma_rad, truth[0].T_W_B,
                              &why);
    if (!laser) {
      out.reason = why;
      return out;
    }
    out.laser_only = true;
  }

  // Priors: the first biases.
  for (int i = 0; i < 3; ++i) {
    info.node[0](kCrlbBg + i, kCrlbBg + i) +=
        1.0 / (options.gyro_bias_prior_rad_s * options.gyro_bias_prior_rad_s);
    info.node[0](kCrlbBa + i, kCrlbBa + i) +=
        1.0 / (options.accel_bias_prior_m_s2 * options.accel_bias_prior_m_s2);
  }

  // Board map: the tilt d (TiltManifold's tangent) is a nuisance parameter coupled to every
  // keyframe that sees the board (see the header).
  if (board) {
    info.coupling.assign(n, Eigen::MatrixXd::Zero(15, 2));
    info.nuisance = Eigen::MatrixXd::Zero(2, 2);  // no prior on the tilt (as the smoother)
    // No nuisance_node: the filtering bound is the one with the tilt known (see the header).
  }

  // Vision: map points in pixels.
  const auto add_point = [&](int k, const CameraSensor& camera, const Eigen::Vector3d& p_map) {
    const Eigen::Vector3d p_W = board ? Eigen::Vector3d(R_W_M * p_map) : p_map;
    Eigen::Matrix<double, 2, 8> J;
    if (!PixelJacobian(camera, truth[k].T_W_B, p_W, options.pixel_sigma_px, board, &J)) return;
    const Eigen::Matrix<double, 2, 6> J_x = J.leftCols<6>();
    info.node[k].topLeftCorner<6, 6>() += J_x.transpose() * J_x;
    if (board) {
      const Eigen::Matrix<double, 2, 2> J_d = J.rightCols<2>();
      info.coupling[k].topRows<6>() += J_x.transpose() * J_d;
      info.nuisance += J_d.transpose() * J_d;
    }
    ++out.visual_residuals;
  };
  if (features_used) {
    for (const FeatureObservation& obs : dataset.features) {
      const int k = KeyframeAt(times, obs.t_ns);
      auto it = dataset.map.landmarks_W.find(obs.landmark_id);
      if (k < 0 || it == dataset.map.landmarks_W.end()) continue;
      add_point(k, dataset.cameras.front(), it->second);
    }
  }
  for (const int c : options.cameras) {
    if (c < 0 || c >= static_cast<int>(dataset.cameras.size())) continue;
    const auto& stream = c == 0 ? dataset.tags : dataset.tags1;
    if (c > 1) continue;
    for (const TagObservation& obs : stream) {
      const int k = KeyframeAt(times, obs.t_ns);
      auto it = dataset.map.tags.find(obs.tag_id);
      if (k < 0 || it == dataset.map.tags.end()) continue;
      for (const Eigen::Vector3d& corner : TagCornersInWorld(it->second))
        add_point(k, dataset.cameras[c], corner);
    }
  }

  // Laser-only data: the spot's bearing angle with the plane (tangent delta, 3) as a nuisance
  // parameter known to no prior, and the smoother's gauge priors (laser_bound.h).
  if (laser) {
    info.coupling.assign(n, Eigen::MatrixXd::Zero(15, 3));
    info.nuisance = Eigen::MatrixXd::Zero(3, 3);
    info.nuisance_node.assign(n, Eigen::MatrixXd::Zero(3, 3));
    const int g =
        model.laser_gauge_keyframe < 0 ? n - 1 : std::min(model.laser_gauge_keyframe, n - 1);
    info.node[g] += LaserGaugePriorInformation(truth[g].T_W_B.R(), laser->plane.n_W);
    for (const LaserObservation& obs : dataset.laser) {
      const int k = KeyframeAt(times, obs.t_ns);
      if (k < 0) continue;
      Eigen::Matrix<double, 1, 9> J;
      if (!LaserSpotBearingJacobian(*laser, truth[k].T_W_B, &J)) continue;
      J /= laser->sigma_rad;
      const Eigen::Matrix<double, 1, 6> J_x = J.leftCols<6>();
      const Eigen::Matrix<double, 1, 3> J_d = J.rightCols<3>();
      info.node[k].topLeftCorner<6, 6>() += J_x.transpose() * J_x;
      info.coupling[k].topRows<6>() += J_x.transpose() * J_d;
      info.nuisance += J_d.transpose() * J_d;
      info.nuisance_node[k] += J_d.transpose() * J_d;
      ++out.visual_residuals;
    }
  }
  if (out.visual_residuals == 0) {
    out.reason = laser ? "no laser spot at a keyframe" : "no map point observed at a keyframe";
    return out;
  }

  // IMU transitions.
  const ImuNoise noise = WithFloor(dataset.imu.noise, options.noise_floor);
  const bool true_rates = laser && model.laser_true_imu_rates;
  for (int k = 0; k + 1 < n; ++k) {
    Matrix15d Phi, Q;
    ImuTransition(dataset, noise, times[k], times[k + 1], true_rates, &Phi, &Q);
    info.AddTransition(Phi, Q);
  }

  MarkovBounds bounds = ComputeMarkovBounds(std::move(info));
  if (!bounds.smoothing_ok || (laser && bounds.nuisance_covariance.size() == 0)) {
    out.reason = "the information matrix is singular (unobservable states)";
    return out;
  }
  if (board) out.tilt_covariance = Eigen::Matrix2d(bounds.nuisance_covariance);
  if (laser) out.plane_covariance = Eigen::Matrix3d(bounds.nuisance_covariance);
  out.keyframes.reserve(n);
  for (int k = 0; k < n; ++k) {
    CrlbKeyframe kf;
    kf.t_ns = times[k];
    kf.T_W_B = truth[k].T_W_B;
    kf.smoothing = bounds.smoothing[k];
    if (bounds.filtering[k]) kf.filtering = Matrix15d(*bounds.filtering[k]);
    if (!laser) {  // the laser quantities below read this keyframe's blocks again
      bounds.smoothing[k] = Eigen::MatrixXd();
      bounds.filtering[k].reset();
    }
    if (board) {
      // The reported error is dx_k + K_k d (the canonical re-expression, see the header):
      // Cov = Sigma_xx + K Sigma_dx + Sigma_xd K^T + K Sigma_dd K^T.
      const Eigen::Matrix<double, 15, 2> K =
          CanonicalYawJacobian(R_W_M, truth[k].T_W_B, truth[k].v_W);
      const Eigen::Matrix<double, 15, 2> X = bounds.smoothing_cross[k];
      const Matrix15d C = kf.smoothing + K * X.transpose() + X * K.transpose() +
                          K * bounds.nuisance_covariance * K.transpose();
      kf.smoothing = 0.5 * (C + C.transpose());
    }
    if (laser) {
      CrlbLaserQuantities q;
      q.truth = LaserQuantitiesAt(*laser, truth[k].T_W_B, truth[k].v_W);
      const Eigen::Matrix<double, 5, 18> J =
          LaserQuantityJacobian(*laser, truth[k].T_W_B, truth[k].v_W);
      q.smoothing = LaserQuantityCovariance(J, bounds.smoothing[k], bounds.smoothing_cross[k],
                                            bounds.nuisance_covariance);
      if (bounds.filtering[k] && k < static_cast<int>(bounds.filtering_cross.size()) &&
          bounds.filtering_cross[k].size() > 0)
        q.filtering = LaserQuantityCovariance(J, *bounds.filtering[k], bounds.filtering_cross[k],
                                              bounds.filtering_nuisance[k]);
      kf.laser = q;
    }
    out.keyframes.push_back(kf);
    if (!laser && (k + 1) % 8192 == 0) ReleaseFreeHeapPages();  // the blocks converted so far
  }
  ReleaseFreeHeapPages();
  out.ok = true;
  out.compute_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

Eigen::Matrix<double, 5, 1> CrlbLaserQuantities::SmoothingSigmas() const {
  Eigen::Matrix<double, 5, 1> s;
  for (int i = 0; i < 5; ++i)
    s(i) = smoothing(i, i) > 0.0 ? std::sqrt(smoothing(i, i)) : std::nan("");
  return s;
}

std::optional<Eigen::Matrix<double, 5, 1>> CrlbLaserQuantities::FilteringSigmas() const {
  if (!filtering) return std::nullopt;
  Eigen::Matrix<double, 5, 1> s;
  for (int i = 0; i < 5; ++i)
    s(i) = (*filtering)(i, i) > 0.0 ? std::sqrt((*filtering)(i, i)) : std::nan("");
  return s;
}

CrlbSigmas SigmasOf(const Matrix15d& C, const Eigen::Quaterniond& q_W_B) {
  CrlbSigmas s;
  const auto sd = [&](int i) { return std::sqrt(std::max(C(i, i), 0.0)); };
  s.position_m = std::sqrt(std::max(C.block<3, 3>(kCrlbP, kCrlbP).trace(), 0.0));
  s.attitude_rad = std::sqrt(std::max(C.block<3, 3>(kCrlbTheta, kCrlbTheta).trace(), 0.0));
  for (int i = 0; i < 3; ++i) {
    s.xyz_m[i] = sd(kCrlbP + i);
    s.v_m_s[i] = sd(kCrlbV + i);
    s.b_g_rad_s[i] = sd(kCrlbBg + i);
    s.b_a_m_s2[i] = sd(kCrlbBa + i);
  }
  // d(roll, pitch, yaw) / d(dtheta) by central differences (R Exp(dtheta)).
  Eigen::Matrix3d E;
  const double h = 1e-6;
  for (int c = 0; c < 3; ++c) {
    const EulerRpy a = EulerFromQuaternion(q_W_B * ExpQuaternion(h * Eigen::Vector3d::Unit(c)));
    const EulerRpy b = EulerFromQuaternion(q_W_B * ExpQuaternion(-h * Eigen::Vector3d::Unit(c)));
    E.col(c) = Eigen::Vector3d(WrapAngle(a.roll - b.roll), WrapAngle(a.pitch - b.pitch),
                               WrapAngle(a.yaw - b.yaw)) /
               (2.0 * h);
  }
  const Eigen::Matrix3d rpy = E * C.block<3, 3>(kCrlbTheta, kCrlbTheta) * E.transpose();
  for (int i = 0; i < 3; ++i) s.rpy_rad[i] = std::sqrt(std::max(rpy(i, i), 0.0));
  return s;
}

}  // namespace mavloc
