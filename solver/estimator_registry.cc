// The list of estimators known to mavloc, in the order reports show them. Adding an estimator is
// one entry here.
#include <fmt/format.h>

#include <cmath>
#include <initializer_list>
#include <limits>
#include <map>
#include <memory>
#include <set>
#include <string>

#include "core/errors.h"
#include "core/number_text.h"
#include "core/physical_limits.h"

#include "solver/estimator.h"
#include "solver/estimators/gravity_ekf_estimator.h"
#include "solver/estimators/imu_dead_reckoning.h"
#include "solver/estimators/laser_ekf_estimator.h"
#include "solver/estimators/pixhawk_kf_estimator.h"
#include "solver/estimators/pnp_estimator.h"
#include "solver/estimators/smoother_estimator.h"
#include "solver/estimators/tag_ekf_estimator.h"
#include "solver/estimators/tag_pnp_estimator.h"
#include "solver/estimators/three_point_estimator.h"
#include "solver/estimators/two_point_estimator.h"
#include "solver/estimators/upright_2p_estimator.h"
#include "solver/imu_gap_guard.h"

namespace mavloc {

namespace {

// An entry whose create rejects undeclared options (CheckEstimatorOptions) before constructing,
// and hands the declared keys to the getters (EstimatorOptions::DeclareFor).
// Value ranges of the numeric estimator options: a key here is checked
// for every estimator that declares it, before the estimator is constructed, so that rate_hz=0, a
// negative noise density or loss_scale=-2 is refused with the option named instead of giving a
// one-pose trajectory, an allocation failure or a silently different cost. Keys not listed are
// text, booleans, or signed values (time offsets) that the getters check for finiteness.
struct OptionRange {
  double lo, hi;
  bool lo_open;  // (lo, hi] instead of [lo, hi]
  const char* unit;
};

constexpr double kUnbounded = std::numeric_limits<double>::infinity();

// Longest window or span of an option in seconds: 11.6 days, longer than any MAV log, and far
// below the 2^62 ns (146 years) that a time difference may reach without int64 overflow (a
// window_s of 1e18 overflowed to a window of no states, a delay_s of 1e9 put every measurement
// after the log's end).
constexpr double kMaxOptionSpan_s = 1e6;
// Variances of process and measurement noise (the tag EKF's): 1e6 in SI units squared is
// (1 km)^2, (1000 m/s^2)^2, (1000 rad/s)^2, far beyond any sensor, and keeps the covariances
// finite.
constexpr double kMaxOptionVariance = 1e6;
constexpr double kMaxOptionDelay_ms = limits::kMaxProcessingDelay_s * 1e3;

const std::map<std::string, OptionRange>& OptionRanges() {
  static const std::map<std::string, OptionRange> kRanges = {
      // Rates and noise: core/physical_limits.h.
      {"rate_hz", {0.0, limits::kMaxEstimateRate_hz, true, "Hz"}},
      {"gyro_noise_density", {0.0, limits::kMaxGyroNoise, false, "rad/s/sqrt(Hz)"}},
      {"accel_noise_density", {0.0, limits::kMaxAccelNoise, false, "m/s^2/sqrt(Hz)"}},
      {"accel_dynamics_sigma", {0.0, limits::kMaxSpecificForce_m_s2, false, "m/s^2"}},
      {"gyro_bias_sigma", {0.0, limits::kMaxGyroBias_rad_s, false, "rad/s"}},
      {"gyro_bias_prior_deg_s", {0.0, limits::kMaxGyroBias_rad_s * 180.0 / M_PI, true, "deg/s"}},
      {"accel_bias_prior_m_s2", {0.0, limits::kMaxAccelBias_m_s2, true, "m/s^2"}},
      {"bearing_sigma_deg", {0.0, limits::kMaxAngleNoise_deg, false, "deg"}},
      {"laser_sigma_deg", {0.0, limits::kMaxAngleNoise_deg, false, "deg"}},
      {"pixel_sigma_px", {0.0, limits::kMaxPixelCoordinate, false, "px"}},
      {"threshold_px", {0.0, limits::kMaxPixelCoordinate, true, "px"}},
      {"D", {0.0, limits::kMaxPosition_m, false, "m"}},
      // Sigmas, variances, random walks, gates, windows: >= 0 (0 = off where the estimator says).
      {"loss_scale", {0.0, kUnbounded, true, ""}},
      {"gz_random_walk", {0.0, kUnbounded, false, ""}},
      {"v_o_random_walk", {0.0, kUnbounded, false, ""}},
      {"normal_random_walk", {0.0, kUnbounded, false, ""}},
      {"gate_sigmas", {0.0, kUnbounded, false, ""}},
      {"gate_chi2", {0.0, kUnbounded, false, ""}},
      {"reacquire_pos_sigma", {0.0, kUnbounded, true, "m"}},
      {"ransac_threshold_px", {0.0, limits::kMaxPixelCoordinate, true, "px"}},
      {"min_ambiguity_ratio", {0.0, kUnbounded, false, ""}},
      {"refine_sigma_m", {0.0, kUnbounded, true, "m"}},
      {"refine_sigma_rad", {0.0, kUnbounded, true, "rad"}},
      {"refine_loss_px", {0.0, limits::kMaxPixelCoordinate, true, "px"}},
      {"refine_gate_px", {0.0, limits::kMaxPixelCoordinate, true, "px"}},
      {"neighbour_gate_m", {0.0, kUnbounded, false, "m"}},
      {"neighbour_window_s", {0.0, kUnbounded, false, "s"}},
      {"reacquire_vel_sigma", {0.0, kUnbounded, true, "m/s"}},
      {"reacquire_att_sigma", {0.0, kUnbounded, true, "rad"}},
      {"position_sigma_m", {0.0, kUnbounded, false, "m"}},
      {"yaw_sigma_deg", {0.0, kUnbounded, false, "deg"}},
      {"position_accel_density", {0.0, kUnbounded, false, "m^2/s^3"}},
      {"yaw_accel_density", {0.0, kUnbounded, false, "rad^2/s^3"}},
      {"coast_limit_s", {0.0, kUnbounded, false, "s"}},
      {"attitude_check_deg", {0.0, kUnbounded, false, "deg"}},
      {"attitude_error_deg", {0.0, kUnbounded, false, "deg"}},
      {"attitude_error_tau_s", {0.0, kUnbounded, true, "s"}},
      {"max_correction_deg", {0.0, kUnbounded, false, "deg"}},
      {"min_inlier_ratio", {0.0, 1.0, false, ""}},
      {"gravity_init_s", {0.0, kUnbounded, true, "s"}},
      {"keyframe_parallax_px", {0.0, limits::kMaxPixelCoordinate, false, "px"}},
      {"keyframe_max_interval_s", {0.0, 10.0, true, "s"}},
      {"track_outlier_px", {0.0, limits::kMaxPixelCoordinate, true, "px"}},
      {"track_step_s", {0.0, 3600.0, true, "s"}},
      {"track_window_s", {0.0, 3600.0, false, "s"}},
      // Counts and seeds.
      {"threads", {1.0, 256.0, false, ""}},
      {"max_iterations", {1.0, 1e6, false, ""}},
      {"keyframe_stride", {1.0, kUnbounded, false, ""}},
      {"relinearize", {0.0, 100.0, false, ""}},
      {"min_inliers", {0.0, kUnbounded, false, ""}},
      {"min_filter_updates", {0.0, kUnbounded, false, ""}},
      {"gravity_min_tags", {1.0, kUnbounded, false, ""}},
      {"reacquire_frames", {2.0, kUnbounded, false, ""}},
      {"ransac_min_tags", {1.0, kUnbounded, false, ""}},
      {"neighbour_frames", {2.0, kUnbounded, false, ""}},
      {"init_seed", {0.0, kUnbounded, false, ""}},
      {"attitude_error_seed", {0.0, kUnbounded, false, ""}},
      // Times that become nanoseconds.
      {"delay_s", {0.0, limits::kMaxProcessingDelay_s, false, "s"}},
      {"image_delay_ms", {-kMaxOptionDelay_ms, kMaxOptionDelay_ms, false, "ms"}},
      {"window_s", {0.0, kMaxOptionSpan_s, false, "s"}},
      {"window_overlap_s", {0.0, kMaxOptionSpan_s, true, "s"}},
      {"grow_window_s", {0.0, kMaxOptionSpan_s, false, "s"}},
      {"gravity_window_s", {0.5, kMaxOptionSpan_s, false, "s"}},
      // Budgets: about 1 TB.
      {"memory_budget_mib", {0.0, 1e6, true, "MiB"}},
      // Priors of the calibration states.
      {"extrinsics_prior_m", {0.0, 10.0, true, "m"}},
      {"extrinsics_prior_deg", {0.0, 180.0, true, "deg"}},
      // The tag EKF's noise (process: may be 0; measurement: > 0) and initial state.
      {"accel_var", {0.0, kMaxOptionVariance, false, "(m/s^2)^2"}},
      {"gyro_var", {0.0, kMaxOptionVariance, false, "(rad/s)^2"}},
      {"accel_bias_var", {0.0, kMaxOptionVariance, false, "(m/s^2)^2"}},
      {"gyro_bias_var", {0.0, kMaxOptionVariance, false, "(rad/s)^2"}},
      {"position_var", {0.0, kMaxOptionVariance, true, "m^2"}},
      {"attitude_var", {0.0, kMaxOptionVariance, true, "rad^2"}},
      {"init_pos_sigma", {0.0, limits::kMaxPosition_m, false, "m"}},
      {"init_vel_sigma", {0.0, limits::kMaxSpeed_m_s, false, "m/s"}},
      {"init_att_sigma", {0.0, 10.0, false, "rad"}},
      {"init_ba_sigma", {0.0, limits::kMaxAccelBias_m_s2, false, "m/s^2"}},
      {"init_bg_sigma", {0.0, limits::kMaxGyroBias_rad_s, false, "rad/s"}},
      {"init_p0_scale", {0.0, 1e6, false, ""}},
      // The laser EKF's initial error (a fraction of each mode) and the triangle angles.
      {"init_error_min", {0.0, 10.0, false, ""}},
      {"init_error_max", {0.0, 10.0, false, ""}},
      {"gamma1_deg", {0.0, 180.0, false, "deg"}},
      {"gamma2_deg", {0.0, 180.0, false, "deg"}},
  };
  return kRanges;
}

std::string RangeDescription(const OptionRange& range) {
  std::string text = fmt::format("{}{:g}, ", range.lo_open ? "(" : "[", range.lo);
  text += std::isinf(range.hi) ? std::string("inf)") : fmt::format("{:g}]", range.hi);
  if (*range.unit) text += std::string(" ") + range.unit;
  return text;
}

// Throws InputError "--option KEY=VALUE: 'VALUE' is outside RANGE (estimator NAME)" for the first
// given option of a declared key whose value is out of its range (OptionRanges).
void CheckOptionRanges(const EstimatorEntry& entry, const EstimatorOptions& given) {
  for (const auto& [key, text] : given.values()) {
    const auto range = OptionRanges().find(key);
    if (range == OptionRanges().end() || !entry.options.count(key)) continue;
    const OptionRange& r = range->second;
    const ParsedNumber<double> parsed = ParseDoubleText(text);
    if (!parsed.ok())
      throw InputError(fmt::format(
          "--option {}={}: {} (estimator {}; range {})", key, PrintableMessage(text, 60),
          DescribeNumberText(text, parsed, "a finite number"), entry.name, RangeDescription(r)));
    const double value = parsed.value;
    const bool above_lo = r.lo_open ? value > r.lo : value >= r.lo;
    if (!above_lo || !(value <= r.hi))
      throw InputError(fmt::format("--option {}={}: '{}' is outside {} (estimator {})", key,
                                   PrintableMessage(text, 60), PrintableMessage(text, 60),
                                   RangeDescription(r), entry.name));
  }
}

template <typename T>
EstimatorEntry Entry(std::string name, std::string description, std::set<std::string> options,
                     std::vector<std::string> prefixes = {}) {
  EstimatorEntry entry{std::move(name), std::move(description), nullptr, std::move(options),
                       std::move(prefixes)};
  entry.create = [entry_name =
                      entry.name](const EstimatorOptions& given) -> std::unique_ptr<Estimator> {
    const EstimatorEntry* self = FindEstimator(entry_name);
    CheckEstimatorOptions(*self, given);
    CheckOptionRanges(*self, given);
    EstimatorOptions declared = given;
    declared.DeclareFor(self);
    return std::make_unique<T>(declared);
  };
  return entry;
}

// An estimator that integrates the IMU: the same entry with the imu_gaps option, created inside an
// ImuGapGuard (solver/imu_gap_guard.h).
template <typename T>
EstimatorEntry ImuEntry(std::string name, std::string description, std::set<std::string> options,
                        std::vector<std::string> prefixes = {}) {
  options.insert(kImuGapsOption);
  EstimatorEntry entry =
      Entry<T>(std::move(name), std::move(description), std::move(options), std::move(prefixes));
  entry.create = [create = entry.create](const EstimatorOptions& given) {
    return std::unique_ptr<Estimator>(
        new ImuGapGuard([create, given] { return create(given); }, given));
  };
  return entry;
}

std::set<std::string> Keys(std::initializer_list<std::set<std::string>> groups) {
  std::set<std::string> keys;
  for (const auto& group : groups) keys.insert(group.begin(), group.end());
  return keys;
}

// Option groups read by shared helpers (the function that reads them in brackets).
// Gravity EKF (GravityEkfOptionsFor, solver/estimators/gravity_ekf_estimator.cc).
const std::set<std::string> kGravityEkf = {"gyro_noise_density", "accel_noise_density",
                                           "accel_dynamics_sigma", "estimate_gyro_bias",
                                           "gyro_bias_sigma"};
// Board-map initialisation (ParseBoardInitOptions, solver/board/board_world.cc).
const std::set<std::string> kBoardInit = {"gravity_init_s", "gravity_min_tags"};
const std::set<std::string> kCornerRansac = {"ransac",     "ransac_threshold_px", "ransac_min_tags",
                                             "single_tag", "min_ambiguity_ratio", "map_check"};
// Tag map refinement (ParseTagMapRefineOptions, solver/pose/tag_map_refine.cc).
const std::set<std::string> kTagMapRefine = {"refine_map",  "refine_sigma_m", "refine_sigma_rad",
                                             "refine_loss", "refine_loss_px", "refine_gate_px"};
// Check across frames (ParseNeighbourGateOptions, solver/pose/neighbour_gate.cc).
const std::set<std::string> kNeighbourGate = {"neighbour_gate_m", "neighbour_frames",
                                              "neighbour_window_s"};
// Roll/pitch source (ParseRollPitchSourceOptions, solver/pixhawk/roll_pitch_source.cc).
const std::set<std::string> kRollPitchSource = {"attitude", "attitude_error_deg",
                                                "attitude_error_tau_s", "attitude_error_seed",
                                                "image_delay_ms"};
// Upright 2-point RANSAC (ParseUpright2pSettings, solver/estimators/upright_2p_estimator.cc).
const std::set<std::string> kUpright2p = {"threshold_px", "ransac", "max_iterations", "min_inliers",
                                          "min_inlier_ratio"};

}  // namespace

const std::vector<EstimatorEntry>& EstimatorRegistry() {
  static const std::vector<EstimatorEntry> kEntries = {
      ImuEntry<ImuDeadReckoning>(
          "imu-dead-reckoning",
          "IMU strapdown integration (RK4) from the true initial state; drifts", {"rate_hz"}),
      ImuEntry<GravityEkfEstimator>("gravity-ekf",
                                    "three-point paper IV: roll, pitch from the IMU (gravity EKF)",
                                    kGravityEkf),
      ImuEntry<TwoPointEstimator>("two-point",
                                  "three-point paper IV-A: pose from IMU roll/pitch, 2 bearings, D",
                                  Keys({kGravityEkf, {"D"}})),
      ImuEntry<ThreePointEstimator>(
          "three-point", "three-point paper IV-B/C: roll/pitch refined by triangle angles",
          Keys({kGravityEkf,
                {"D", "bearing_sigma_deg", "gamma1_deg", "gamma2_deg", "max_correction_deg",
                 "min_filter_updates", "true_angles"}})),
      Entry<PnpEstimator>(
          "pnp", "PIXHAWK 3.1/7.2 baseline: vision-only pose from marker corners (+ RANSAC)",
          Keys({kBoardInit, kCornerRansac, {"image_delay_ms"}})),
      ImuEntry<Upright2pEstimator>(
          "upright-2p", "PIXHAWK 3.2: IMU roll/pitch + known-vertical 2-point RANSAC + LS",
          Keys({kUpright2p, kRollPitchSource, kGravityEkf, kBoardInit})),
      ImuEntry<PixhawkKfEstimator>(
          "pixhawk-kf", "PIXHAWK 3.3/5.1: outlier rejection + 4 x 1-D CV Kalman filters",
          Keys(
              {kUpright2p,
               kRollPitchSource,
               kGravityEkf,
               kBoardInit,
               {"source", "attitude_check_deg", "use_measured_dt", "position_sigma_m",
                "yaw_sigma_deg", "position_accel_density", "yaw_accel_density", "coast_limit_s"}})),
      ImuEntry<LaserEkfEstimator>(
          "laser-ekf", "laser paper 4/C: EKF on the observable modes d, v_o, roll, pitch, alpha",
          {"camera", "init_error_min", "init_error_max", "init_seed", "bearing_sigma_deg",
           "accel_noise_density", "gyro_noise_density", "gz_random_walk", "v_o_random_walk",
           "normal_random_walk", "gate_sigmas", "bias_from_ground_truth", "lever_arm"}),
      Entry<TagPnpEstimator>(
          "tag-pnp", "AprilTag paper III-A baseline: vision-only PnP on the tags (+ RANSAC)",
          Keys({kBoardInit, kCornerRansac, kTagMapRefine, kNeighbourGate, {"camera"}})),
      ImuEntry<TagEkfEstimator>(
          "tag-ekf", "AprilTag paper II-III: 15-state EKF, per-tag updates, delay handling",
          Keys({kBoardInit,
                {"init",
                 "camera",
                 "use_tags",
                 "accel_var",
                 "gyro_var",
                 "accel_bias_var",
                 "gyro_bias_var",
                 "position_var",
                 "attitude_var",
                 "compensate_delay",
                 "gate_chi2",
                 "delay_s",
                 "init_pos_sigma",
                 "init_vel_sigma",
                 "init_att_sigma",
                 "init_ba_sigma",
                 "init_bg_sigma",
                 "init_seed",
                 "init_p0_scale",
                 "rate_hz",
                 "reacquire",
                 "reacquire_frames",
                 "reacquire_pos_sigma",
                 "reacquire_vel_sigma",
                 "reacquire_att_sigma"}})),
      ImuEntry<SmootherEstimator>(
          "smoother",
          "Ceres batch smoother: Forster preintegration + visual residuals, "
          "seeded by the closed-form/PnP estimators",
          {"accel_bias_prior_m_s2",
           "autodiff_jacobians",
           "bearing_sigma_deg",
           "calibration_covariance",
           "cameras",
           "covariance",
           "estimate_D",
           "estimate_extrinsics",
           "estimate_time_offset",
           "extrinsics_prior_deg",
           "extrinsics_prior_m",
           "fit_imu_noise",
           "gauge_prior",
           "graduated",
           "gravity_window_s",
           "grow_window_s",
           "gyro_bias_prior_deg_s",
           "keyframe_max_interval_s",
           "keyframe_parallax_px",
           "keyframe_stride",
           "landmarks",
           "laser_sigma_deg",
           "loss",
           "loss_scale",
           "max_iterations",
           "max_time_offset_ms",
           "memory_budget_mib",
           "pixel_sigma_px",
           "relinearize",
           "seed",
           "threads",
           "time_offset_init_ms",
           "track_outlier_px",
           "track_step_s",
           "track_window_s",
           "verbose",
           "window_overlap_s",
           "window_s"},
          {"seed."}),
  };
  return kEntries;
}

}  // namespace mavloc
