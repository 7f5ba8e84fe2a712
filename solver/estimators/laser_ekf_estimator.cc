#include "solver/estimators/laser_ekf_estimator.h"

#include <algorithm>
#include <cmath>

#include "core/errors.h"
#include "core/random.h"
#include "core/rotation.h"
#include "solver/laser/laser_calibration.h"
#include "solver/laser/laser_spot_model.h"

namespace mavloc {

namespace {

const char* const kLaserKeys[4] = {"laser_Lx", "laser_Ly", "laser_theta", "laser_phi"};

LaserCalibration CalibrationFromMap(const WorldMap& map) {
  return {map.parameters.at("laser_Lx"), map.parameters.at("laser_Ly"),
          map.parameters.at("laser_theta"), map.parameters.at("laser_phi")};
}

// d, v_o, roll, pitch, alpha of the camera C from the modes in C' (same origin, R_C_Cp).
std::vector<double> OutputQuantities(const LaserState& m, XiSign sign,
                                     const Eigen::Matrix3d& R_C_Cp) {
  const double xi = Xi(m[2], m[3], sign);
  const Eigen::Vector3d n_C = R_C_Cp * Eigen::Vector3d(-m[3], m[2], xi);
  const LaserQuantities q = QuantitiesFromModes(m, sign, kGravityMagnitude);
  return {q.d_m, q.v_o_m_s, std::atan2(n_C.y(), n_C.z()),
          std::asin(std::clamp(-n_C.x(), -1.0, 1.0)), q.alpha_rad};
}

}  // namespace

LaserEkfEstimator::LaserEkfEstimator(const EstimatorOptions& options)
    : camera_(options.GetString("camera", "cam0")),
      init_error_min_(options.GetDouble("init_error_min", 0.1)),
      init_error_max_(options.GetDouble("init_error_max", 0.2)),
      init_seed_(static_cast<uint64_t>(options.GetInt("init_seed", 1))),
      bearing_sigma_rad_(options.GetDouble("bearing_sigma_deg", 1.0) * kDeg),
      accel_noise_density_(options.GetDouble("accel_noise_density", -1.0)),
      gyro_noise_density_(options.GetDouble("gyro_noise_density", -1.0)),
      gz_random_walk_(options.GetDouble("gz_random_walk", 0.0)),
      v_o_random_walk_(options.GetDouble("v_o_random_walk", 0.0)),
      normal_random_walk_(options.GetDouble("normal_random_walk", 0.0)),
      gate_sigmas_(options.GetDouble("gate_sigmas", 0.0)),
      bias_from_ground_truth_(options.GetBool("bias_from_ground_truth", false)),
      lever_arm_(options.GetBool("lever_arm", true)) {
  if (!(init_error_min_ >= 0.0 && init_error_max_ >= init_error_min_))
    throw InputError("laser-ekf: need 0 <= init_error_min <= init_error_max");
  if (!(bearing_sigma_rad_ > 0.0)) throw InputError("laser-ekf: bearing_sigma_deg must be > 0");
}

Applicability LaserEkfEstimator::AppliesTo(const Dataset& dataset) const {
  if (dataset.imu.samples.size() < 3) return Applicability::No("needs imu0 samples");
  if (dataset.laser.empty()) return Applicability::No("needs laser spot observations (laser0)");
  if (dataset.Camera(camera_) == nullptr) return Applicability::No("needs camera " + camera_);
  for (const char* key : kLaserKeys) {
    if (!dataset.map.parameters.count(key))
      return Applicability::No(std::string("needs the laser parameter ") + key + " in map.yaml");
  }
  if (!dataset.map.plane) return Applicability::No("needs the plane (initial state) in map.yaml");
  if (dataset.ground_truth.empty()) return Applicability::No("needs ground truth (initial state)");
  if (dataset.ground_truth.back().t_ns <= dataset.imu.samples.front().t_ns)
    return Applicability::No("ground truth ends before the IMU stream");
  return Applicability::Yes();
}

Estimate LaserEkfEstimator::Run(const Dataset& dataset) {
  Estimate estimate;
  estimate.quantities =
      QuantityTable({"d", "v_o", "roll", "pitch", "alpha"}, {"m", "m/s", "rad", "rad", "rad"});
  estimate.covariance_names = estimate.quantities.names;
  const CameraSensor& camera = *dataset.Camera(camera_);
  const ChosenLaserFrame chosen = ChosenFrameFromCalibration(CalibrationFromMap(dataset.map));
  const Eigen::Matrix3d R_C_Cp = chosen.q_C_Cp.toRotationMatrix();
  const Eigen::Matrix3d R_Cp_B = R_C_Cp.transpose() * camera.T_B_C.R().transpose();
  const Eigen::Vector3d r_B = lever_arm_ ? camera.T_B_C.p : Eigen::Vector3d::Zero();
  const std::vector<ImuSample>& imu = dataset.imu.samples;

  // Start at the first IMU sample with ground truth.
  const TimeNs t_truth0 = dataset.ground_truth.front().t_ns;
  size_t i0 = 0;
  while (i0 + 2 < imu.size() && imu[i0].t_ns < t_truth0) ++i0;
  const GroundTruthState& truth0 = NearestTruth(dataset.ground_truth, imu[i0].t_ns);
  Eigen::Vector3d b_g = Eigen::Vector3d::Zero(), b_a = Eigen::Vector3d::Zero();
  if (bias_from_ground_truth_) {
    b_g = dataset.ground_truth.front().b_g;
    b_a = dataset.ground_truth.front().b_a;
  }

  // True initial modes in C', then 10-20 % off (5.1.3).
  const Pose T_W_Cp = truth0.T_W_B * camera.T_B_C * Pose(chosen.q_C_Cp, Eigen::Vector3d::Zero());
  const Eigen::Vector3d w0_B = imu[i0].gyro_rad_s - b_g;
  const Eigen::Vector3d v0_W = truth0.v_W + truth0.T_W_B.q * w0_B.cross(r_B);
  const Plane plane = OrientPlaneTowards(*dataset.map.plane, T_W_Cp.p);
  const LaserModes truth_modes = ModesFromPose(T_W_Cp, v0_W, plane, GravityW());
  Rng rng(init_seed_);
  const double typical[4] = {1.0, 0.5, 0.5, 0.5};
  LaserState m0 = truth_modes.m;
  LaserCovariance P0 = LaserCovariance::Zero();
  for (int i = 0; i < 4; ++i) {
    const double sign = rng.Uniform() < 0.5 ? -1.0 : 1.0;
    const double scale = std::max(std::abs(m0[i]), typical[i]);
    m0[i] += sign * rng.Uniform(init_error_min_, init_error_max_) * scale;
    P0(i, i) = std::pow(std::max(init_error_max_, 0.02) * scale, 2);
  }
  const double k_true = std::sqrt(std::max(0.0, std::pow(kGravityMagnitude / m0[4], 2) - 1.0));
  const double k_sign = rng.Uniform() < 0.5 ? -1.0 : 1.0;
  const double k0 = k_true * (1.0 + k_sign * rng.Uniform(init_error_min_, init_error_max_));
  m0[4] = std::copysign(kGravityMagnitude / std::sqrt(1.0 + k0 * k0), truth_modes.m[4]);
  P0(4, 4) = std::pow(std::max(0.5 * init_error_max_ / 0.2, 0.05), 2);

  LaserEkfOptions ekf_options;
  ekf_options.L_m = chosen.L_m;
  ekf_options.accel_noise_density =
      accel_noise_density_ >= 0.0 ? accel_noise_density_
                                  : std::max(dataset.imu.noise.accelerometer_noise_density, 1e-3);
  ekf_options.gyro_noise_density = gyro_noise_density_ >= 0.0
                                       ? gyro_noise_density_
                                       : std::max(dataset.imu.noise.gyroscope_noise_density, 1e-4);
  ekf_options.gz_random_walk = gz_random_walk_;
  ekf_options.v_o_random_walk = v_o_random_walk_;
  ekf_options.normal_random_walk = normal_random_walk_;
  ekf_options.bearing_sigma_rad = bearing_sigma_rad_;
  ekf_options.gate_sigmas = gate_sigmas_;
  LaserEkf ekf(ekf_options);
  ekf.Initialize(m0, P0, truth_modes.xi_sign);

  auto input_at = [&](size_t i) {
    const Eigen::Vector3d w = imu[i].gyro_rad_s - b_g;
    Eigen::Vector3d a = imu[i].accel_m_s2 - b_a;
    if (r_B.squaredNorm() > 0.0) {
      const size_t lo = i > 0 ? i - 1 : i, hi = std::min(i + 1, imu.size() - 1);
      const Eigen::Vector3d w_dot =
          hi > lo ? Eigen::Vector3d(((imu[hi].gyro_rad_s - imu[lo].gyro_rad_s) /
                                     NsToSeconds(imu[hi].t_ns - imu[lo].t_ns)))
                  : Eigen::Vector3d::Zero();
      a += w_dot.cross(r_B) + w.cross(w.cross(r_B));
    }
    LaserInput u;
    u << R_Cp_B * a, R_Cp_B * w;
    return u;
  };
  auto record = [&](TimeNs t) {
    estimate.quantities.Append(t, OutputQuantities(ekf.state(), ekf.xi_sign(), R_C_Cp));
  };
  auto record_covariance = [&](TimeNs t) {
    // J = d(d, v_o, roll, pitch, alpha)/dm by central differences of the output map.
    Eigen::Matrix<double, 5, 5> J;
    for (int j = 0; j < 5; ++j) {
      const double step = 1e-7;
      LaserState plus = ekf.state(), minus = ekf.state();
      plus[j] += step;
      minus[j] -= step;
      const auto fp = OutputQuantities(plus, ekf.xi_sign(), R_C_Cp);
      const auto fm = OutputQuantities(minus, ekf.xi_sign(), R_C_Cp);
      for (int r = 0; r < 5; ++r) J(r, j) = (fp[r] - fm[r]) / (2 * step);
    }
    estimate.covariances.push_back({t, J * ekf.covariance() * J.transpose()});
  };

  size_t next_spot = 0;
  while (next_spot < dataset.laser.size() && dataset.laser[next_spot].t_ns < imu[i0].t_ns)
    ++next_spot;
  record(imu[i0].t_ns);
  for (size_t i = i0; i + 1 < imu.size(); ++i) {
    const LaserInput u = input_at(i);
    TimeNs t = imu[i].t_ns;
    const TimeNs t_next = imu[i + 1].t_ns;
    while (next_spot < dataset.laser.size() && dataset.laser[next_spot].t_ns <= t_next) {
      const LaserObservation& spot = dataset.laser[next_spot++];
      ekf.Propagate(u, NsToSeconds(spot.t_ns - t));
      t = spot.t_ns;
      const Eigen::Vector3d bearing_Cp =
          R_C_Cp.transpose() * Eigen::Vector3d(spot.xy.x(), spot.xy.y(), 1.0);
      if (bearing_Cp.z() <= 1e-9) {
        estimate.CountFailure("laser spot behind the chosen laser frame");
        continue;
      }
      const LaserUpdateStatus status = ekf.Update(bearing_Cp.x() / bearing_Cp.z());
      if (status != LaserUpdateStatus::kOk) {
        estimate.CountFailure(LaserUpdateStatusName(status));
      } else {
        record_covariance(t);
      }
    }
    ekf.Propagate(u, NsToSeconds(t_next - t));
    record(t_next);
  }
  if (ekf.decomposition_switches() > 0)
    estimate.failures["local decomposition switches (eq. 10)"] = ekf.decomposition_switches();
  return estimate;
}

}  // namespace mavloc
