#include "solver/estimators/smoother_estimator.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <optional>

#include <fmt/format.h>

#include "core/board_frame.h"
#include "core/errors.h"
#include "core/rotation.h"
#include "solver/board/board_gravity_from_positions.h"
#include "solver/estimators/smoother_common.h"
#include "solver/imu/imu_integrator.h"
#include "solver/laser/laser_calibration.h"
#include "solver/smoother/smoother_windows.h"
#include "solver/smoother/tilt_manifold.h"

namespace mavloc {

namespace {

// A scenario.yaml noise (core/dataset.h ScenarioNumber): also >= 0.
std::optional<double> ScenarioNoise(const Dataset& dataset, const std::string& key) {
  const std::optional<double> value = ScenarioNumber(dataset, key);
  if (value && *value < 0.0)
    throw InputError("scenario.yaml", 0, key,
                     "'" + dataset.scenario_info.at(key) + "' is not a finite number >= 0");
  return value;
}

bool StreamHasMapTags(const Dataset& dataset, const std::vector<TagObservation>& stream) {
  for (const auto& obs : stream)
    if (dataset.map.tags.count(obs.tag_id)) return true;
  return false;
}

// tags0 or tags1 with map tags (tags1 only with a second camera).
bool HasMapTags(const Dataset& dataset) {
  return StreamHasMapTags(dataset, dataset.tags) ||
         (dataset.cameras.size() > 1 && StreamHasMapTags(dataset, dataset.tags1));
}

// "cam0" -> 0, "cam1" -> 1; -1 otherwise.
int CameraIndexFromName(const std::string& name) {
  if (name == "cam0") return 0;
  if (name == "cam1") return 1;
  return -1;
}

// The `cameras` option as camera indices (empty for "all"); throws on unknown names.
std::vector<int> ParseCameras(const std::string& text) {
  std::vector<int> cameras;
  if (text == "all") return cameras;
  size_t begin = 0;
  while (begin <= text.size()) {
    size_t end = text.find(',', begin);
    if (end == std::string::npos) end = text.size();
    const std::string name = text.substr(begin, end - begin);
    const int index = CameraIndexFromName(name);
    if (index < 0)
      throw InputError("smoother: option cameras must be all, cam0, cam1 or cam0,cam1 (got '" +
                       text + "')");
    if (std::find(cameras.begin(), cameras.end(), index) == cameras.end()) cameras.push_back(index);
    begin = end + 1;
  }
  std::sort(cameras.begin(), cameras.end());
  return cameras;
}

// d(board_roll, board_pitch) / d(tilt tangent) at q_W_M (TiltManifold's left perturbation about
// W's x and y), by central differences.
Eigen::Matrix2d BoardTiltJacobian(const Eigen::Quaterniond& q_W_M) {
  const TiltManifold manifold;
  const double x[4] = {q_W_M.x(), q_W_M.y(), q_W_M.z(), q_W_M.w()};
  auto tilt = [&](const Eigen::Vector2d& d) {
    double y[4];
    manifold.Plus(x, d.data(), y);
    const Eigen::Quaterniond q(y[3], y[0], y[1], y[2]);
    const BoardTilt t = BoardTiltFromUp(UpInBoard(q.toRotationMatrix()));
    return Eigen::Vector2d(t.roll_rad, t.pitch_rad);
  };
  Eigen::Matrix2d J;
  const double h = 1e-6;
  for (int c = 0; c < 2; ++c) {
    const Eigen::Vector2d a = tilt(h * Eigen::Vector2d::Unit(c));
    const Eigen::Vector2d b = tilt(-h * Eigen::Vector2d::Unit(c));
    J.col(c) = Eigen::Vector2d(WrapAngle(a.x() - b.x()), WrapAngle(a.y() - b.y())) / (2.0 * h);
  }
  return J;
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
  if (text == "tracks") return LandmarkMode::kTracks;
  if (text != "auto")
    throw InputError("smoother: option landmarks must be auto, known, ground, unknown or tracks");
  if (IsThreePointWorld(dataset)) return LandmarkMode::kUnknownGround;
  if (HasFeatureTracks(dataset) && !HasMapTags(dataset)) return LandmarkMode::kTracks;
  return AllFeaturesInMap(dataset) ? LandmarkMode::kKnown : LandmarkMode::kUnknown;
}

}  // namespace

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

namespace {

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
  // Continue from the first solution, calibration included (its keyframes are in its W).
  SmootherProblemOptions continued_options = options;
  continued_options.initial_T_B_C = first.calibration.T_B_C;
  continued_options.initial_time_offset_s = first.calibration.time_offset_s;
  if (first.calibration.q_W_M) continued_options.initial_q_W_M = first.calibration.q_W_M;
  SmootherResult continued = SolveSmoother(dataset, first.keyframes, first_landmarks,
                                           first.plane ? first.plane : plane, continued_options);
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

// fit_imu_noise=1 (variance component estimation, smoother_covariance.h ResidualGroupFit): the IMU
// factors' chi2 over their redundancy is the factor by which the stated variances are off. All four
// densities are scaled by its square root and the problem solved again from the solution, until
// the factor is within kImuFitTolerance of 1 or after kImuFitRounds solves (Koch 1999, sec. 3.6.4:
// the estimate is iterated because the redundancies depend on the weights).
constexpr double kImuFitTolerance = 0.02;
constexpr int kImuFitRounds = 8;
// A scale outside this range says the IMU model (or the solution) is wrong, not its size: a
// diverged solution fits the spots by trusting the IMU ever more (euroc-laser's diverged seeds
// run to x 0.0004). The fit then stops and keeps the stated densities' solution.
constexpr double kImuFitMinScale = 0.05;
constexpr double kImuFitMaxScale = 20.0;

void RefitImuNoise(const Dataset& dataset, const SmootherProblemOptions& options,
                   SmootherResult* result, Estimate* estimate) {
  if (!options.fit_imu_noise) return;
  if (!result->usable || !result->imu_fit || !(result->imu_fit->redundancy > 0.0)) {
    estimate->events.push_back("IMU noise not fitted: the IMU residuals' redundancy is unknown");
    return;
  }
  Dataset scaled = dataset;
  const SmootherResult stated = *result;
  double scale = 1.0;
  int rounds = 0;
  while (std::abs(result->imu_fit->VarianceFactor() - 1.0) > kImuFitTolerance &&
         rounds < kImuFitRounds) {
    const double factor = result->imu_fit->VarianceFactor();
    scale *= std::sqrt(factor);
    if (!(scale >= kImuFitMinScale && scale <= kImuFitMaxScale)) {
      estimate->events.push_back(fmt::format(
          "IMU noise not fitted: the IMU residuals ask for every density x {:.3g}, outside [{:g}, "
          "{:g}] (a model error or a diverged solution, not a noise level); the stated densities "
          "are kept",
          scale, kImuFitMinScale, kImuFitMaxScale));
      const SmootherStatistics all_solves = result->statistics;
      *result = stated;
      result->statistics = all_solves;
      return;
    }
    scaled.imu.noise = ScaledImuNoise(dataset.imu.noise, scale);
    SmootherProblemOptions continued = options;
    continued.initial_T_B_C = result->calibration.T_B_C;
    continued.initial_time_offset_s = result->calibration.time_offset_s;
    if (result->calibration.q_W_M) continued.initial_q_W_M = result->calibration.q_W_M;
    SmootherResult next =
        SolveSmoother(scaled, result->keyframes, result->landmarks_W, result->plane, continued);
    ++rounds;
    if (!next.usable || !next.imu_fit) break;
    AddStatistics(result->statistics, &next.statistics);
    *result = std::move(next);
  }
  const ResidualGroupFit& fit = *result->imu_fit;
  // var(chi2 / r) = 2 / r for Gaussian residuals, so the scale's standard deviation is
  // scale / sqrt(2 r) (first order).
  estimate->parameters["imu_noise_scale"] = {scale, scale / std::sqrt(2.0 * fit.redundancy), ""};
  estimate->events.push_back(fmt::format(
      "IMU noise fitted to the IMU residuals: every density x {:.3g} ({} solves; final chi2 {:.4g} "
      "over a redundancy of {:.4g} of {} residuals)",
      scale, rounds + 1, fit.chi2, fit.redundancy, fit.residuals));
}

// An estimate whose last solve stopped at max_iterations says so: it is not at the optimum, and its
// numbers move with the arithmetic's rounding (an analytic instead of an automatic Jacobian,
// another compiler) by up to the size of the steps it was still taking.
bool CountUnusableSolve(const SmootherResult& result, int frames, Estimate* estimate) {
  if (result.usable) return false;
  estimate->failures["smoother: " + (result.message.empty() ? std::string("no solution")
                                                            : result.message)] += frames;
  return true;
}

void NoteUnconverged(const SmootherResult& result, int max_iterations, Estimate* estimate) {
  if (!result.usable || result.statistics.converged) return;
  estimate->events.push_back(fmt::format(
      "the last solve stopped at max_iterations={} before converging (its last "
      "iteration still lowered the cost by {:.1e} of itself): the estimate is not at the optimum "
      "and its numbers move with the arithmetic's rounding; a larger max_iterations lets it go on",
      max_iterations, result.statistics.last_relative_cost_change));
}

namespace {

// Whether a solution's cost is plausible for its residuals: twice the cost (the sum of squared
// whitened residuals) within kPlausibleCostFactor times the number of residual dimensions (15 per
// IMU factor: preintegration and bias walk; 2 per visual residual), whose expectation it would be
// minus the parameters. A loose test: real sensors are not exactly their noise model; a seed gone
// astray leaves the cost orders of magnitude above it.
constexpr double kPlausibleCostFactor = 10.0;
// The growing window's first span (option grow_window_s; 0 turns the growing window off).
constexpr double kDefaultGrowWindowS = 3.0;

// Windows (solver/smoother/smoother_windows.h). The batch's memory is estimated from its size:
// Ceres' residual blocks, cost functions, Jacobian and sparse Cholesky per visual residual (2 rows
// of 6 tangent columns) and per keyframe (IMU factor, preintegration, 15 states). Measured as the
// difference in peak RSS of `mavloc run --estimator smoother` with window_s=0 and window_s=30 on a
// simulated 300 s mav-figure-eight (256,219 visual residuals, 6,031 keyframes): 294 MB, where
// these constants give 328 MB (docs/performance.md).
constexpr double kBytesPerVisualResidual = 1000.0;
constexpr double kBytesPerKeyframe = 12000.0;
constexpr double kDefaultMemoryBudgetMiB = 1024.0;
// Once a log needs windows, each window's problem is sized at this share of the budget: beside it
// the process holds what grows with the log (the dataset, the seeds, the estimate, and afterwards
// the Cramer-Rao bound's per-keyframe blocks). On an hour of mav-figure-eight a quarter keeps the
// whole `compare` under the budget (0.8 GB of 1 GB, docs/performance.md); windows filling the whole
// budget (985 s) took 1.6 GB.
constexpr double kWindowShareOfBudget = 0.25;
constexpr double kDefaultWindowOverlapS = 5.0;
constexpr double kMinWindowS = 30.0;

double BatchMebibytes(double keyframes, double visual_residuals) {
  return (kBytesPerKeyframe * keyframes + kBytesPerVisualResidual * visual_residuals) /
         (1024.0 * 1024.0);
}

// The visual residuals a smoother over `dataset` would build (before any is dropped).
double VisualResidualCount(const Dataset& dataset) {
  return static_cast<double>(dataset.features.size() + dataset.laser.size() +
                             4 * (dataset.tags.size() + dataset.tags1.size()));
}
// A solution that kept fewer than this share of the spots has left out the spots whose beam misses
// its plane (a seed gone astray): a small cost over the spots that are left proves nothing.
constexpr double kMinSpotShare = 0.9;
bool SolutionIsPlausible(const SmootherStatistics& statistics, int spots) {
  const double dims = 15.0 * statistics.num_imu_factors + 2.0 * statistics.num_visual_residuals;
  return 2.0 * statistics.final_cost <= kPlausibleCostFactor * std::max(dims, 1.0) &&
         statistics.num_visual_residuals >= kMinSpotShare * spots;
}

// The laser spots at keyframe times: what a solution's visual residuals should number.
int SpotsAtKeyframes(const Dataset& dataset, const std::vector<SmootherKeyframe>& keyframes) {
  std::vector<TimeNs> times;
  for (const auto& kf : keyframes) times.push_back(kf.t_ns);
  int spots = 0;
  for (const auto& spot : dataset.laser)
    spots += std::binary_search(times.begin(), times.end(), spot.t_ns) ? 1 : 0;
  return spots;
}

// The growing window of laser-only data: the seed (laser-ekf, which has no bias states) can leave
// real biases unmodelled and diverge (euroc-laser: after about 11 s), and a smoother started from
// the diverged part stalls. So the smoother is solved on the first window_s seconds of keyframes,
// then on windows twice as long but at most 2 window_s longer (dead reckoning over longer spans
// on a real IMU leaves the new keyframes' spots off the plane), until it holds every keyframe;
// each new keyframe starts from the IMU integrated (solver/imu/imu_integrator.h) from the previous
// solution's last keyframe with that keyframe's biases, and the plane from the previous solution.
// The statistics add up all solves.
SmootherResult SolveInGrowingWindows(const Dataset& dataset,
                                     const std::vector<SmootherKeyframe>& seeded,
                                     const Plane& plane, const SmootherProblemOptions& options,
                                     bool graduated, double window_s) {
  const TimeNs t0 = seeded.front().t_ns;
  TimeNs window_ns = SecondsToNs(window_s);
  // New keyframes start from IMU dead reckoning: a window grows by at most 2 window_s at a time.
  const TimeNs max_step_ns = 2 * window_ns;
  std::vector<SmootherKeyframe> current;
  for (const auto& kf : seeded)
    if (kf.t_ns - t0 <= window_ns) current.push_back(kf);
  std::optional<Plane> current_plane = plane;
  SmootherStatistics earlier;  // of the solves before the last (times and iterations add up)
  const ImuIntegrator integrator(&dataset.imu.samples);
  while (true) {
    const bool last = current.size() == seeded.size();
    SmootherProblemOptions stage_options = options;
    if (!last) stage_options.compute_covariance = false;
    SmootherResult result =
        SolveRobustly(dataset, current, {}, current_plane, stage_options, graduated);
    // Spots whose beam misses the plane at the start of a solve are left out of it; once every
    // keyframe is in, solve again from the solution while that brings spots back (at most twice).
    for (int polish = 0; last && polish < 2 && result.usable && result.plane &&
                         result.keyframes.size() == current.size();
         ++polish) {
      SmootherResult again =
          SolveRobustly(dataset, result.keyframes, {}, result.plane, stage_options, graduated);
      if (!again.usable ||
          again.statistics.num_visual_residuals <= result.statistics.num_visual_residuals) {
        AddStatistics(again.statistics, &earlier);
        break;
      }
      AddStatistics(result.statistics, &earlier);
      result = std::move(again);
    }
    if (last || !result.usable || !result.plane || result.keyframes.size() != current.size()) {
      AddStatistics(earlier, &result.statistics);
      if (!last && result.usable)
        result.message = "growing window stopped at " + std::to_string(current.size()) + " of " +
                         std::to_string(seeded.size()) + " keyframes";
      if (!last) result.usable = false;
      return result;
    }
    AddStatistics(result.statistics, &earlier);
    current_plane = result.plane;
    current = result.keyframes;
    window_ns = std::min(2 * window_ns, window_ns + max_step_ns);
    for (size_t k = current.size(); k < seeded.size() && seeded[k].t_ns - t0 <= window_ns; ++k) {
      const SmootherKeyframe& previous = current.back();
      NavState state;
      state.t_ns = previous.t_ns;
      state.q_W_B = previous.state.q_W_B;
      state.p_W = previous.state.p_W;
      state.v_W = previous.state.v_W;
      const NavState next = integrator.Integrate(state, seeded[k].t_ns, previous.state.biases);
      SmootherKeyframe kf;
      kf.t_ns = seeded[k].t_ns;
      kf.state.q_W_B = next.q_W_B;
      kf.state.p_W = next.p_W;
      kf.state.v_W = next.v_W;
      kf.state.biases = previous.state.biases;
      current.push_back(kf);
    }
  }
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
  ParseCameras(options_.GetString("cameras", "all"));  // validates the text
  options_.GetBool("autodiff_jacobians", false);       // validates the text
  options_.GetBool("fit_imu_noise", false);            // validates the text
  if (!(options_.GetDouble("extrinsics_prior_m", 0.1) > 0.0) ||
      !(options_.GetDouble("extrinsics_prior_deg", 10.0) > 0.0))
    throw InputError("smoother: extrinsics_prior_m and extrinsics_prior_deg must be > 0");
  const double max_offset_ms = options_.GetDouble("max_time_offset_ms", 30.0);
  if (!(max_offset_ms > 0.0 && max_offset_ms <= 200.0))
    throw InputError("smoother: max_time_offset_ms must be in (0, 200]");
  if (!(std::abs(options_.GetDouble("time_offset_init_ms", 0.0)) <= max_offset_ms))
    throw InputError("smoother: |time_offset_init_ms| must not exceed max_time_offset_ms");
  if (!(options_.GetDouble("gravity_window_s", 2.0) >= 0.5))
    throw InputError("smoother: gravity_window_s must be >= 0.5");
  if (!(options_.GetDouble("memory_budget_mib", kDefaultMemoryBudgetMiB) > 0.0))
    throw InputError("smoother: memory_budget_mib must be > 0");
  const double window_s = options_.GetDouble("window_s", 0.0);
  const double overlap_s = options_.GetDouble("window_overlap_s", kDefaultWindowOverlapS);
  if (!(overlap_s > 0.0)) throw InputError("smoother: window_overlap_s must be > 0");
  if (!(window_s == 0.0 || window_s > 2.0 * overlap_s))
    throw InputError(
        "smoother: window_s must be 0 (batch unless over memory_budget_mib) or more "
        "than twice window_overlap_s");
  if (!(options_.GetDouble("grow_window_s", kDefaultGrowWindowS) >= 0.0))
    throw InputError("smoother: grow_window_s must be >= 0");
}

std::vector<int> SmootherEstimator::CamerasFor(const Dataset& dataset) const {
  std::vector<int> cameras = ParseCameras(options_.GetString("cameras", "all"));
  if (!cameras.empty()) return cameras;
  if (StreamHasMapTags(dataset, dataset.tags) || dataset.tags.empty()) cameras.push_back(0);
  if (dataset.cameras.size() > 1 && StreamHasMapTags(dataset, dataset.tags1)) cameras.push_back(1);
  if (cameras.empty()) cameras.push_back(0);
  return cameras;
}

Applicability SmootherEstimator::AppliesTo(const Dataset& dataset) const {
  if (dataset.imu.samples.size() < 2) return Applicability::No("needs imu0 samples");
  if (dataset.cameras.empty()) return Applicability::No("needs cam0 (for the extrinsics)");
  const bool features =
      !dataset.features.empty() &&
      (AllFeaturesInMap(dataset) || IsThreePointWorld(dataset) || HasFeatureTracks(dataset) ||
       options_.GetString("landmarks", "auto") != "auto");
  const bool tags = HasMapTags(dataset);
  const bool laser = !dataset.laser.empty() && BeamFromMap(dataset).has_value();
  if (!features && !tags && !laser)
    return Applicability::No(
        "needs visual residuals: features0 (feature tracks, or map landmarks, or the three-point "
        "world), camera images to track features in, tags0 with map tags, or laser0 with the "
        "laser parameters in map.yaml");
  return Applicability::Yes();
}

std::string SmootherEstimator::SeedEstimatorFor(const Dataset& dataset) const {
  if (options_.Has("seed")) return options_.GetString("seed", "");
  if (HasMapTags(dataset)) {
    const std::vector<int> cameras = CamerasFor(dataset);
    const bool cam0 = std::find(cameras.begin(), cameras.end(), 0) != cameras.end();
    return cam0 && StreamHasMapTags(dataset, dataset.tags) ? "tag-pnp" : "tag-pnp-cam1";
  }
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
  o.autodiff_jacobians = options_.GetBool("autodiff_jacobians", false);
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
      "pixel_sigma_px", ScenarioNoise(dataset, "pixel_noise_px")
                            .value_or(ScenarioNoise(dataset, "corner_noise_px").value_or(1.0)));
  o.pixel_sigma_px = std::max(pixel, 1e-3);
  const double bearing_deg = options_.GetDouble(
      "bearing_sigma_deg", ScenarioNoise(dataset, "bearing_noise_deg").value_or(1.0));
  o.bearing_sigma_rad = std::max(bearing_deg, 1e-4) * kDeg;
  const double laser_deg = options_.GetDouble(
      "laser_sigma_deg", ScenarioNoise(dataset, "laser_noise_deg")
                             .value_or(ScenarioNoise(dataset, "bearing_noise_deg").value_or(1.0)));
  o.laser_sigma_rad = std::max(laser_deg, 1e-4) * kDeg;
  // Pixels when the camera has real intrinsics and no angular noise is stated; bearings otherwise.
  const bool has_intrinsics = !dataset.cameras.empty() && dataset.cameras.front().model.fu() > 2.0;
  o.features_as_bearings =
      !has_intrinsics || ScenarioNoise(dataset, "bearing_noise_deg").has_value();
  o.laser_beam = BeamFromMap(dataset);
  o.estimate_plane = true;

  // Tag cameras and calibration.
  o.cameras = CamerasFor(dataset);
  o.estimate_extrinsics = options_.GetBool("estimate_extrinsics", false);
  o.extrinsics_prior_m = options_.GetDouble("extrinsics_prior_m", 0.1);
  o.extrinsics_prior_rad = options_.GetDouble("extrinsics_prior_deg", 10.0) * kDeg;
  o.estimate_time_offset = options_.GetBool("estimate_time_offset", false);
  o.initial_time_offset_s = options_.GetDouble("time_offset_init_ms", 0.0) * 1e-3;
  o.max_time_offset_s = options_.GetDouble("max_time_offset_ms", 30.0) * 1e-3;
  o.calibration_covariance = options_.GetBool("calibration_covariance", true);
  o.fit_imu_noise = options_.GetBool("fit_imu_noise", false);
  return o;
}

Estimate SmootherEstimator::Run(const Dataset& dataset) {
  if (ProblemOptionsFor(dataset).landmarks == LandmarkMode::kTracks && !options_.Has("seed"))
    return RunFromTracks(dataset);
  const std::string seed_name = SeedEstimatorFor(dataset);
  if (seed_name == "landmark-pnp") {  // built in: no registry estimator takes features0 landmarks
    const std::vector<StampedPose> seed_poses = LandmarkPnpSeed(dataset);
    return RunFromSeedPoses(dataset, seed_poses);
  }
  if (seed_name == "tag-pnp-cam1") {  // built in: tag-pnp reads tags0 only
    const std::vector<StampedPose> seed_poses = TagPnpSeed(dataset, 1);
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
  if (IsLaserOnly(dataset)) return RunFromLaserModes(dataset, seed_estimate);
  std::vector<StampedPose> seed_poses = SeedPoses(seed_estimate);
  // On a board map a seed that already estimated its own T_W_M reports T_W_B: back into M.
  if (dataset.map.frame == MapFrame::kBoard && seed_estimate.T_W_M) {
    const Pose T_M_W = seed_estimate.T_W_M->Inverse();
    for (auto& pose : seed_poses) pose.T_W_B = T_M_W * pose.T_W_B;
  }
  return RunFromSeedPoses(dataset, seed_poses);
}

bool SmootherEstimator::IsLaserOnly(const Dataset& dataset) const {
  return !dataset.laser.empty() && dataset.features.empty() && !HasMapTags(dataset);
}

Estimate SmootherEstimator::RunFromLaserModes(const Dataset& dataset,
                                              const Estimate& seed_estimate) {
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
  const bool graduated = options_.GetBool("graduated", true);
  last_result_ =
      SolveRobustly(dataset, init.keyframes, {}, gauge_plane, problem_options, graduated);
  // A solution whose cost is far above its residuals' expectation started from a seed that went
  // astray (laser-ekf has no bias states: on the real IMU of euroc-laser it diverges after ~11 s):
  // the growing window starts from the seed's first seconds only.
  const double window_s = options_.GetDouble("grow_window_s", kDefaultGrowWindowS);
  // Implausible too: a solution that left out the spots whose beam misses its plane.
  const int spots = SpotsAtKeyframes(dataset, init.keyframes);
  const auto plausible = [&](const SmootherResult& r) {
    return r.usable && SolutionIsPlausible(r.statistics, spots);
  };
  if (window_s > 0.0 && !plausible(last_result_)) {
    SmootherResult grown = SolveInGrowingWindows(dataset, init.keyframes, gauge_plane,
                                                 problem_options, graduated, window_s);
    // A plausible solution wins over an implausible one; between two of the same kind, the
    // lower cost.
    const bool take_grown =
        grown.usable && (!last_result_.usable ||
                         (plausible(grown) != plausible(last_result_)
                              ? plausible(grown)
                              : grown.statistics.final_cost < last_result_.statistics.final_cost));
    if (take_grown) {
      AddStatistics(last_result_.statistics, &grown.statistics);
      last_result_ = std::move(grown);
    } else {
      AddStatistics(grown.statistics, &last_result_.statistics);
    }
  }
  RefitImuNoise(dataset, problem_options, &last_result_, &estimate);
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
  NoteUnconverged(result, problem_options.max_iterations, &estimate);
  return estimate;
}

std::optional<SmootherWindowOptions> SmootherEstimator::WindowsFor(
    const Dataset& dataset, const std::vector<SmootherKeyframe>& keyframes,
    const SmootherProblemOptions& problem_options, Estimate* estimate) const {
  if (keyframes.size() < 2) return std::nullopt;
  SmootherWindowOptions windows;
  windows.overlap_s = options_.GetDouble("window_overlap_s", kDefaultWindowOverlapS);
  const double budget_mib = options_.GetDouble("memory_budget_mib", kDefaultMemoryBudgetMiB);
  const double span_s = NsToSeconds(keyframes.back().t_ns - keyframes.front().t_ns);
  const double batch_mib =
      BatchMebibytes(static_cast<double>(keyframes.size()), VisualResidualCount(dataset));
  const std::string unsupported = WindowsUnsupportedReason(dataset, problem_options);
  windows.window_s = options_.GetDouble("window_s", 0.0);
  const bool by_budget = !(windows.window_s > 0.0);
  if (!by_budget) {
    if (!unsupported.empty())
      throw InputError("smoother: window_s is set, but the problem cannot be solved in windows: " +
                       unsupported);
  } else {
    if (batch_mib <= budget_mib) return std::nullopt;
    if (!unsupported.empty()) {
      estimate->events.push_back(fmt::format(
          "solved as one batch of about {:.0f} MiB, over memory_budget_mib={:.0f}: it cannot be "
          "solved in windows ({})",
          batch_mib, budget_mib, unsupported));
      return std::nullopt;
    }
    // Windows whose problem fits the window's share of the budget.
    windows.window_s = std::max({kMinWindowS, 4.0 * windows.overlap_s,
                                 span_s * kWindowShareOfBudget * budget_mib / batch_mib});
  }
  const int count = static_cast<int>(std::ceil(std::max(span_s - windows.overlap_s, 0.0) /
                                               (windows.window_s - windows.overlap_s)));
  estimate->events.push_back(fmt::format(
      "solved in {} windows of {:g} s overlapping by {:g} s, each starting from the previous "
      "one's marginal prior (the batch of {:.0f} s would take about {:.0f} MiB; "
      "memory_budget_mib={:.0f}{})",
      std::max(count, 1), windows.window_s, windows.overlap_s, span_s, batch_mib, budget_mib,
      by_budget ? ", a quarter of it per window" : ""));
  return windows;
}

Estimate SmootherEstimator::RunFromSeedPoses(const Dataset& dataset,
                                             const std::vector<StampedPose>& seed_poses_in_map) {
  SmootherProblemOptions problem_options = ProblemOptionsFor(dataset);
  const bool board = dataset.map.frame == MapFrame::kBoard;
  std::vector<std::string> names = PoseQuantityNames(true);
  names.insert(names.end(), {"bgx", "bgy", "bgz", "bax", "bay", "baz"});
  const bool ground = problem_options.landmarks == LandmarkMode::kUnknownGround;
  if (ground) names.insert(names.end(), {"D", "gamma1", "gamma2"});
  if (board) names.insert(names.end(), {"board_roll", "board_pitch"});
  std::vector<std::string> units;
  for (const auto& name : names)
    units.push_back(name.rfind("board_", 0) == 0 ? "rad" : StandardUnit(name));
  Estimate estimate;
  estimate.quantities = QuantityTable(names, units);

  const std::vector<TimeNs> times =
      SmootherKeyframeTimes(dataset, options_.GetInt("keyframe_stride", 1));

  // Board map: the seed poses are T_M_B. The initial gravity direction in M from the first
  // gravity_window_s of them (later windows when that one fails), then the poses in that W.
  std::vector<StampedPose> seed_poses = seed_poses_in_map;
  if (board) {
    std::vector<StampedPose> sorted = seed_poses;
    std::sort(sorted.begin(), sorted.end(),
              [](const StampedPose& a, const StampedPose& b) { return a.t_ns < b.t_ns; });
    const TimeNs window_ns = SecondsToNs(options_.GetDouble("gravity_window_s", 2.0));
    std::optional<Eigen::Vector3d> up_M;
    std::string why = "no seed pose";
    if (!sorted.empty()) {
      for (TimeNs t = sorted.front().t_ns; !up_M && t <= sorted.back().t_ns; t += window_ns)
        up_M = EstimateUpInBoardFromPositions(sorted, dataset.imu, t, t + window_ns, &why);
    }
    if (!up_M) {
      estimate.failures["board gravity initialisation: " + why] += static_cast<int>(times.size());
      last_result_ = SmootherResult{};
      return estimate;
    }
    const Pose T_W_M0 = BoardToWorld(*up_M);
    for (auto& pose : seed_poses) pose.T_W_B = T_W_M0 * pose.T_W_B;
    problem_options.initial_q_W_M = T_W_M0.q;
  }

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
  const std::optional<SmootherWindowOptions> windows =
      WindowsFor(dataset, init.keyframes, problem_options, &estimate);
  last_result_ =
      windows
          ? SolveSmootherInWindows(dataset, init.keyframes, problem_options, *windows)
          : SolveRobustly(dataset, init.keyframes, landmarks, plane, problem_options, graduated);
  RefitImuNoise(dataset, problem_options, &last_result_, &estimate);
  const SmootherResult& result = last_result_;
  if (CountUnusableSolve(result, static_cast<int>(times.size()), &estimate)) return estimate;

  double D = std::numeric_limits<double>::quiet_NaN(), gamma1 = D, gamma2 = D;
  if (ground && result.landmarks_W.size() >= 2) {
    auto it = result.landmarks_W.begin();
    const Eigen::Vector3d P1 = it->second, P2 = (++it)->second;
    D = (P2 - P1).norm();
    if (++it != result.landmarks_W.end())
      std::tie(gamma1, gamma2) = TriangleAngles(P1, P2, it->second);
  }

  // Calibration and statistics of the solution.
  const SmootherCalibration& cal = result.calibration;
  BoardTilt tilt;
  if (board && cal.q_W_M) {
    estimate.T_W_M = Pose(*cal.q_W_M, Eigen::Vector3d::Zero());
    tilt = BoardTiltFromUp(UpInBoard(cal.q_W_M->toRotationMatrix()));
    EstimatedParameter roll{tilt.roll_rad, std::nullopt, "rad"};
    EstimatedParameter pitch{tilt.pitch_rad, std::nullopt, "rad"};
    if (cal.tilt_covariance) {
      const Eigen::Matrix2d J = BoardTiltJacobian(*cal.q_W_M);
      const Eigen::Matrix2d C = J * *cal.tilt_covariance * J.transpose();
      roll.sigma = std::sqrt(std::max(C(0, 0), 0.0));
      pitch.sigma = std::sqrt(std::max(C(1, 1), 0.0));
    }
    estimate.parameters["board_roll"] = roll;
    estimate.parameters["board_pitch"] = pitch;
  }
  if (problem_options.estimate_time_offset)
    estimate.parameters["time_offset"] = {cal.time_offset_s, cal.time_offset_sigma_s, "s"};
  if (problem_options.estimate_extrinsics) {
    for (const auto& [cam, T_B_C] : cal.T_B_C) {
      EstimatedExtrinsic extrinsic;
      extrinsic.T_B_C = T_B_C;
      auto it = cal.T_B_C_covariance.find(cam);
      if (it != cal.T_B_C_covariance.end()) extrinsic.covariance = it->second;
      estimate.extrinsics[dataset.cameras[cam].name] = extrinsic;
    }
  }
  if (result.corner_statistics.corners > 0) {
    estimate.parameters["reprojection_rms"] = {result.corner_statistics.rms_px, std::nullopt, "px"};
    estimate.parameters["downweighted_corners"] = {
        static_cast<double>(result.corner_statistics.downweighted), std::nullopt, ""};
  }

  if (problem_options.compute_covariance) estimate.covariance_names = PoseQuantityNames(false);
  for (size_t k = 0; k < result.keyframes.size(); ++k) {
    const SmootherKeyframe& kf = result.keyframes[k];
    const Pose T_W_B(kf.state.q_W_B, kf.state.p_W);
    std::vector<double> values = PoseQuantityValues(T_W_B, kf.state.v_W);
    const ImuBiases& b = kf.state.biases;
    values.insert(values.end(), {b.b_g.x(), b.b_g.y(), b.b_g.z(), b.b_a.x(), b.b_a.y(), b.b_a.z()});
    if (ground) values.insert(values.end(), {D, gamma1, gamma2});
    if (board) values.insert(values.end(), {tilt.roll_rad, tilt.pitch_rad});
    estimate.quantities.Append(kf.t_ns, values);
    estimate.poses.push_back({kf.t_ns, T_W_B});
    if (k < result.pose_covariances.size() && result.pose_covariances[k]) {
      Eigen::Matrix<double, 6, 6> J = Eigen::Matrix<double, 6, 6>::Identity();
      J.bottomRightCorner<3, 3>() = EulerJacobian(kf.state.q_W_B);
      estimate.covariances.push_back({kf.t_ns, J * *result.pose_covariances[k] * J.transpose()});
    }
  }
  NoteUnconverged(result, problem_options.max_iterations, &estimate);
  return estimate;
}

}  // namespace mavloc
