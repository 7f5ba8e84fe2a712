#include "solver/estimators/smoother_estimator.h"

#include <cmath>
#include <limits>
#include <optional>

#include "core/errors.h"
#include "core/rotation.h"
#include "solver/laser/laser_calibration.h"

namespace mavloc {

namespace {

// The leading number of a scenario.yaml value ("1 per bearing angle (...)" -> 1).
std::optional<double> ScenarioNumber(const Dataset& dataset, const std::string& key) {
  auto it = dataset.scenario_info.find(key);
  if (it == dataset.scenario_info.end()) return std::nullopt;
  try {
    size_t used = 0;
    const double value = std::stod(it->second, &used);
    if (used == 0 || !std::isfinite(value)) return std::nullopt;
    return value;
  } catch (...) {
    return std::nullopt;
  }
}

bool HasMapTags(const Dataset& dataset) {
  for (const auto& obs : dataset.tags)
    if (dataset.map.tags.count(obs.tag_id)) return true;
  return false;
}

// The three-point scenario's convention: ground features with the paper's frame (map "D").
bool IsThreePointWorld(const Dataset& dataset) { return dataset.map.parameters.count("D") > 0; }

bool AllFeaturesInMap(const Dataset& dataset) {
  if (dataset.features.empty()) return false;
  for (const auto& obs : dataset.features)
    if (!dataset.map.landmarks_W.count(obs.landmark_id)) return false;
  return true;
}

std::optional<LaserBeam> BeamFromMap(const Dataset& dataset) {
  const auto& p = dataset.map.parameters;
  auto get = [&](const std::string& key) -> std::optional<double> {
    auto it = p.find(key);
    return it == p.end() ? std::nullopt : std::optional<double>(it->second);
  };
  LaserBeam beam;
  if (get("laser_origin_x_m") && get("laser_direction_z")) {
    beam.origin_C = {*get("laser_origin_x_m"), get("laser_origin_y_m").value_or(0.0),
                     get("laser_origin_z_m").value_or(0.0)};
    beam.direction_C =
        Eigen::Vector3d(get("laser_direction_x").value_or(0.0),
                        get("laser_direction_y").value_or(0.0), *get("laser_direction_z"))
            .normalized();
    return beam;
  }
  // Appendix A's calibration parameters (laser-plane, euroc-laser scenarios).
  if (get("laser_Lx")) {
    LaserCalibration calibration;
    calibration.Lx_m = *get("laser_Lx");
    calibration.Ly_m = get("laser_Ly").value_or(0.0);
    calibration.theta_rad = get("laser_theta").value_or(0.0);
    calibration.phi_rad = get("laser_phi").value_or(0.0);
    return BeamFromCalibration(calibration);
  }
  for (const char* key : {"laser_L_m", "L_m", "L"}) {
    if (auto L = get(key)) {
      beam.origin_C = {*L, 0.0, 0.0};
      beam.direction_C = Eigen::Vector3d::UnitZ();
      return beam;
    }
  }
  return std::nullopt;
}

LandmarkMode ResolveLandmarkMode(const std::string& text, const Dataset& dataset) {
  if (text == "known") return LandmarkMode::kKnown;
  if (text == "ground") return LandmarkMode::kUnknownGround;
  if (text == "unknown") return LandmarkMode::kUnknown;
  if (text != "auto")
    throw InputError("smoother: option landmarks must be auto, known, ground or unknown");
  if (IsThreePointWorld(dataset)) return LandmarkMode::kUnknownGround;
  return AllFeaturesInMap(dataset) ? LandmarkMode::kKnown : LandmarkMode::kUnknown;
}

// d(roll, pitch, yaw) / d(dtheta) for R Exp(dtheta), by central differences.
Eigen::Matrix3d EulerJacobian(const Eigen::Quaterniond& q) {
  Eigen::Matrix3d J;
  const double h = 1e-6;
  for (int c = 0; c < 3; ++c) {
    const EulerRpy a = EulerFromQuaternion(q * ExpQuaternion(h * Eigen::Vector3d::Unit(c)));
    const EulerRpy b = EulerFromQuaternion(q * ExpQuaternion(-h * Eigen::Vector3d::Unit(c)));
    J.col(c) = Eigen::Vector3d(WrapAngle(a.roll - b.roll), WrapAngle(a.pitch - b.pitch),
                               WrapAngle(a.yaw - b.yaw)) /
               (2.0 * h);
  }
  return J;
}

// Triangle angles of the three-point paper (Fig. 7): gamma1 at P1 between P1->P2 and P1->P3,
// gamma2 the turn from P1->P2 to P2->P3.
std::pair<double, double> TriangleAngles(const Eigen::Vector3d& P1, const Eigen::Vector3d& P2,
                                         const Eigen::Vector3d& P3) {
  auto heading = [](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    return std::atan2(b.y() - a.y(), b.x() - a.x());
  };
  return {WrapAngle(heading(P1, P3) - heading(P1, P2)),
          WrapAngle(heading(P2, P3) - heading(P1, P2))};
}

constexpr double kLooseGyroBiasPriorDegS = 0.5;
constexpr double kLooseAccelBiasPriorMS2 = 0.1;

void AddStatistics(const SmootherStatistics& from, SmootherStatistics* to) {
  to->iterations += from.iterations;
  to->solves += from.solves;
  to->preintegration_s += from.preintegration_s;
  to->solve_s += from.solve_s;
  to->linear_solver_s += from.linear_solver_s;
  to->residual_evaluation_s += from.residual_evaluation_s;
  to->jacobian_evaluation_s += from.jacobian_evaluation_s;
  to->covariance_s += from.covariance_s;
}

// SolveSmoother, robust to a tight bias prior (a sensor stated bias-free). A tight prior leaves the
// optimizer no slack to absorb the seed's inconsistency with the precise IMU, and from a poor seed
// it can stall far from the solution (laser-plane seed 2); a loose prior first, then the tight one
// from that solution (continuation), can stall too (seed 19). So with `graduated`, both are run
// and the solution of lower cost (the same objective) is kept; the statistics add up all solves.
SmootherResult SolveRobustly(const Dataset& dataset, const std::vector<SmootherKeyframe>& initial,
                             const std::map<int, Eigen::Vector3d>& landmarks,
                             const std::optional<Plane>& plane,
                             const SmootherProblemOptions& options, bool graduated) {
  SmootherProblemOptions loose = options;
  loose.gyro_bias_prior_rad_s =
      std::max(options.gyro_bias_prior_rad_s, kLooseGyroBiasPriorDegS * kDeg);
  loose.accel_bias_prior_m_s2 = std::max(options.accel_bias_prior_m_s2, kLooseAccelBiasPriorMS2);
  SmootherResult direct = SolveSmoother(dataset, initial, landmarks, plane, options);
  if (!graduated || (loose.gyro_bias_prior_rad_s == options.gyro_bias_prior_rad_s &&
                     loose.accel_bias_prior_m_s2 == options.accel_bias_prior_m_s2))
    return direct;
  loose.compute_covariance = false;
  const SmootherResult first = SolveSmoother(dataset, initial, landmarks, plane, loose);
  if (!first.usable || first.keyframes.size() != initial.size()) {
    AddStatistics(first.statistics, &direct.statistics);
    return direct;
  }
  std::map<int, Eigen::Vector3d> first_landmarks = landmarks;
  for (const auto& [id, p] : first.landmarks_W) first_landmarks[id] = p;
  SmootherResult continued = SolveSmoother(dataset, first.keyframes, first_landmarks,
                                           first.plane ? first.plane : plane, options);
  const bool keep_continued =
      continued.usable &&
      (!direct.usable || continued.statistics.final_cost < direct.statistics.final_cost);
  SmootherResult& kept = keep_continued ? continued : direct;
  const SmootherResult& other = keep_continued ? direct : continued;
  AddStatistics(first.statistics, &kept.statistics);
  AddStatistics(other.statistics, &kept.statistics);
  kept.statistics.initial_cost = direct.statistics.initial_cost;
  return kept;
}

}  // namespace

SmootherEstimator::SmootherEstimator(const EstimatorOptions& options) : options_(options) {
  const std::string loss = options_.GetString("loss", "huber");
  if (loss != "huber" && loss != "cauchy" && loss != "none")
    throw InputError("smoother: option loss must be huber, cauchy or none");
  ResolveLandmarkMode(options_.GetString("landmarks", "auto"), Dataset{});  // validates the text
  if (options_.GetInt("max_iterations", 50) < 1)
    throw InputError("smoother: max_iterations must be >= 1");
  if (options_.GetInt("keyframe_stride", 1) < 1)
    throw InputError("smoother: keyframe_stride must be >= 1");
}

Applicability SmootherEstimator::AppliesTo(const Dataset& dataset) const {
  if (dataset.imu.samples.size() < 2) return Applicability::No("needs imu0 samples");
  if (dataset.cameras.empty()) return Applicability::No("needs cam0 (for the extrinsics)");
  const bool features =
      !dataset.features.empty() && (AllFeaturesInMap(dataset) || IsThreePointWorld(dataset) ||
                                    options_.GetString("landmarks", "auto") != "auto");
  const bool tags = HasMapTags(dataset);
  const bool laser = !dataset.laser.empty() && BeamFromMap(dataset).has_value();
  if (!features && !tags && !laser)
    return Applicability::No(
        "needs visual residuals: features0 with map landmarks (or the three-point world), tags0 "
        "with map tags, or laser0 with the laser parameters in map.yaml");
  return Applicability::Yes();
}

std::string SmootherEstimator::SeedEstimatorFor(const Dataset& dataset) const {
  if (options_.Has("seed")) return options_.GetString("seed", "");
  if (HasMapTags(dataset)) return "tag-pnp";
  if (IsThreePointWorld(dataset)) return "three-point";
  if (!dataset.features.empty() && AllFeaturesInMap(dataset)) return "landmark-pnp";
  return "laser-ekf";
}

SmootherProblemOptions SmootherEstimator::ProblemOptionsFor(const Dataset& dataset) const {
  SmootherProblemOptions o;
  const std::string loss = options_.GetString("loss", "huber");
  o.loss = loss == "huber"    ? SmootherLoss::kHuber
           : loss == "cauchy" ? SmootherLoss::kCauchy
                              : SmootherLoss::kNone;
  o.loss_scale = options_.GetDouble("loss_scale", 2.0);
  o.max_iterations = options_.GetInt("max_iterations", 50);
  o.num_threads = options_.GetInt("threads", 2);
  o.compute_covariance = options_.GetBool("covariance", false);
  o.verbose = options_.GetBool("verbose", false);
  o.relinearize_rounds = options_.GetInt("relinearize", 1);
  // Initial-bias prior: what the sensor description states (the papers' filters assume the same
  // knowledge: bias-free models where the data are bias-free), else a loose generic prior.
  const double stated_gyro_deg_s = dataset.imu.gyroscope_bias_sigma
                                       ? std::max(*dataset.imu.gyroscope_bias_sigma / kDeg, 1e-4)
                                       : kLooseGyroBiasPriorDegS;
  const double stated_accel_m_s2 = dataset.imu.accelerometer_bias_sigma
                                       ? std::max(*dataset.imu.accelerometer_bias_sigma, 1e-4)
                                       : kLooseAccelBiasPriorMS2;
  o.gyro_bias_prior_rad_s = options_.GetDouble("gyro_bias_prior_deg_s", stated_gyro_deg_s) * kDeg;
  o.accel_bias_prior_m_s2 = options_.GetDouble("accel_bias_prior_m_s2", stated_accel_m_s2);
  o.landmarks = ResolveLandmarkMode(options_.GetString("landmarks", "auto"), dataset);
  // The three-point world: D as the closed-form solvers get it (map.yaml), unless estimate_D=1.
  if (o.landmarks == LandmarkMode::kUnknownGround && !options_.GetBool("estimate_D", false)) {
    auto it = dataset.map.parameters.find("D");
    if (it != dataset.map.parameters.end()) o.given_D_m = it->second;
  }

  // Measurement noise: the option, else what scenario.yaml states, else 1 px / 1 deg. Noiseless
  // data get a tiny floor: exact measurements then dominate the IMU, whose discretisation (~1e-7
  // rad per frame interval on the simulator's splines) would otherwise pull the poses off.
  const double pixel = options_.GetDouble(
      "pixel_sigma_px", ScenarioNumber(dataset, "pixel_noise_px")
                            .value_or(ScenarioNumber(dataset, "corner_noise_px").value_or(1.0)));
  o.pixel_sigma_px = std::max(pixel, 1e-3);
  const double bearing_deg = options_.GetDouble(
      "bearing_sigma_deg", ScenarioNumber(dataset, "bearing_noise_deg").value_or(1.0));
  o.bearing_sigma_rad = std::max(bearing_deg, 1e-4) * kDeg;
  const double laser_deg = options_.GetDouble(
      "laser_sigma_deg", ScenarioNumber(dataset, "laser_noise_deg")
                             .value_or(ScenarioNumber(dataset, "bearing_noise_deg").value_or(1.0)));
  o.laser_sigma_rad = std::max(laser_deg, 1e-4) * kDeg;
  // Pixels when the camera has real intrinsics and no angular noise is stated; bearings otherwise.
  const bool has_intrinsics = !dataset.cameras.empty() && dataset.cameras.front().model.fu() > 2.0;
  o.features_as_bearings =
      !has_intrinsics || ScenarioNumber(dataset, "bearing_noise_deg").has_value();
  o.laser_beam = BeamFromMap(dataset);
  o.estimate_plane = true;
  return o;
}

Estimate SmootherEstimator::Run(const Dataset& dataset) {
  const std::string seed_name = SeedEstimatorFor(dataset);
  if (seed_name == "landmark-pnp") {  // built in: no registry estimator takes features0 landmarks
    const std::vector<StampedPose> seed_poses = LandmarkPnpSeed(dataset);
    return RunFromSeedPoses(dataset, seed_poses);
  }
  const EstimatorEntry* entry = FindEstimator(seed_name);
  if (!entry || seed_name == "smoother") {
    Estimate estimate;
    estimate.quantities = MakeQuantityTable(PoseQuantityNames(true));
    estimate.CountFailure("seed estimator '" + seed_name + "' is not available");
    last_result_ = SmootherResult{};
    return estimate;
  }
  EstimatorOptions seed_options;
  for (const auto& [key, value] : options_.values())
    if (key.rfind("seed.", 0) == 0) seed_options.Set(key.substr(5), value);
  std::unique_ptr<Estimator> seed = entry->create(seed_options);
  const Applicability applies = seed->AppliesTo(dataset);
  if (!applies.applies) {
    Estimate estimate;
    estimate.quantities = MakeQuantityTable(PoseQuantityNames(true));
    estimate.CountFailure("seed estimator '" + seed_name + "' does not apply: " + applies.reason);
    last_result_ = SmootherResult{};
    return estimate;
  }
  const Estimate seed_estimate = seed->Run(dataset);
  if (IsLaserOnly(dataset)) return RunLaserOnly(dataset, seed_estimate);
  return RunFromSeedPoses(dataset, SeedPoses(seed_estimate));
}

bool SmootherEstimator::IsLaserOnly(const Dataset& dataset) const {
  return !dataset.laser.empty() && dataset.features.empty() && !HasMapTags(dataset);
}

Estimate SmootherEstimator::RunLaserOnly(const Dataset& dataset, const Estimate& seed_estimate) {
  const SmootherProblemOptions problem_options = ProblemOptionsFor(dataset);
  Estimate estimate;
  estimate.quantities =
      QuantityTable({"d", "v_o", "roll", "pitch", "alpha"}, {"m", "m/s", "rad", "rad", "rad"});
  const std::vector<TimeNs> times =
      SmootherKeyframeTimes(dataset, options_.GetInt("keyframe_stride", 1));
  Plane gauge_plane;
  const SmootherInitialization init =
      InitializeFromLaserModes(dataset, times, seed_estimate.quantities, &gauge_plane);
  for (const auto& [reason, count] : init.failures)
    if (reason.find("missing") != std::string::npos) estimate.failures["init: " + reason] += count;
  last_result_ = SolveRobustly(dataset, init.keyframes, {}, gauge_plane, problem_options,
                               options_.GetBool("graduated", true));
  const SmootherResult& result = last_result_;
  if (!result.usable || !result.plane) {
    estimate.failures["smoother: " +
                      (result.message.empty() ? std::string("no solution") : result.message)] +=
        static_cast<int>(times.size());
    return estimate;
  }
  const Pose& T_B_C = dataset.cameras.front().T_B_C;
  const Pose T_W_C0 =
      Pose(result.keyframes.front().state.q_W_B, result.keyframes.front().state.p_W) * T_B_C;
  const Plane plane = OrientPlaneTowards(*result.plane, T_W_C0.p);
  for (const SmootherKeyframe& kf : result.keyframes) {
    const Pose T_W_C = Pose(kf.state.q_W_B, kf.state.p_W) * T_B_C;
    const LaserModes modes = ModesFromPose(T_W_C, kf.state.v_W, plane, GravityW());
    const LaserQuantities q = QuantitiesFromModes(modes.m, modes.xi_sign, kGravityMagnitude);
    estimate.quantities.Append(kf.t_ns, {q.d_m, q.v_o_m_s, q.roll_rad, q.pitch_rad, q.alpha_rad});
  }
  return estimate;
}

Estimate SmootherEstimator::RunFromSeedPoses(const Dataset& dataset,
                                             const std::vector<StampedPose>& seed_poses) {
  const SmootherProblemOptions problem_options = ProblemOptionsFor(dataset);
  std::vector<std::string> names = PoseQuantityNames(true);
  names.insert(names.end(), {"bgx", "bgy", "bgz", "bax", "bay", "baz"});
  const bool ground = problem_options.landmarks == LandmarkMode::kUnknownGround;
  if (ground) names.insert(names.end(), {"D", "gamma1", "gamma2"});
  Estimate estimate;
  estimate.quantities = MakeQuantityTable(names);

  const std::vector<TimeNs> times =
      SmootherKeyframeTimes(dataset, options_.GetInt("keyframe_stride", 1));
  const SmootherInitialization init = InitializeFromSeed(dataset, times, seed_poses);
  // Keyframes where the seed failed are bridged by the IMU (forwards, or backwards before the
  // first seed pose) and get a solution: seed failures are not frames without a solution.
  std::map<int, Eigen::Vector3d> landmarks;
  if (problem_options.landmarks != LandmarkMode::kKnown)
    landmarks = TriangulateFeatures(dataset, init.keyframes, ground);
  std::optional<Plane> plane;
  if (problem_options.laser_beam)
    plane = FitLaserPlane(dataset, init.keyframes, *problem_options.laser_beam);

  // Known map points (tags, surveyed landmarks) anchor every keyframe: one solve. Unknown
  // landmarks leave weak directions (scale, tilt vs bias) where the restart may be needed.
  const bool anchored = HasMapTags(dataset) || problem_options.landmarks == LandmarkMode::kKnown;
  const bool graduated = options_.GetBool("graduated", true) && !anchored;
  last_result_ =
      SolveRobustly(dataset, init.keyframes, landmarks, plane, problem_options, graduated);
  const SmootherResult& result = last_result_;
  if (!result.usable) {
    estimate.failures["smoother: " +
                      (result.message.empty() ? std::string("no solution") : result.message)] +=
        static_cast<int>(times.size());
    return estimate;
  }

  double D = std::numeric_limits<double>::quiet_NaN(), gamma1 = D, gamma2 = D;
  if (ground && result.landmarks_W.size() >= 2) {
    auto it = result.landmarks_W.begin();
    const Eigen::Vector3d P1 = it->second, P2 = (++it)->second;
    D = (P2 - P1).norm();
    if (++it != result.landmarks_W.end())
      std::tie(gamma1, gamma2) = TriangleAngles(P1, P2, it->second);
  }
  if (problem_options.compute_covariance) estimate.covariance_names = PoseQuantityNames(false);
  for (size_t k = 0; k < result.keyframes.size(); ++k) {
    const SmootherKeyframe& kf = result.keyframes[k];
    const Pose T_W_B(kf.state.q_W_B, kf.state.p_W);
    std::vector<double> values = PoseQuantityValues(T_W_B, kf.state.v_W);
    const ImuBiases& b = kf.state.biases;
    values.insert(values.end(), {b.b_g.x(), b.b_g.y(), b.b_g.z(), b.b_a.x(), b.b_a.y(), b.b_a.z()});
    if (ground) values.insert(values.end(), {D, gamma1, gamma2});
    estimate.quantities.Append(kf.t_ns, values);
    estimate.poses.push_back({kf.t_ns, T_W_B});
    if (k < result.pose_covariances.size() && result.pose_covariances[k]) {
      Eigen::Matrix<double, 6, 6> J = Eigen::Matrix<double, 6, 6>::Identity();
      J.bottomRightCorner<3, 3>() = EulerJacobian(kf.state.q_W_B);
      estimate.covariances.push_back({kf.t_ns, J * *result.pose_covariances[k] * J.transpose()});
    }
  }
  return estimate;
}

}  // namespace mavloc
