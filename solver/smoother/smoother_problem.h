// The batch smoother (DESIGN.md "Estimators"): a Ceres problem over keyframe states
// x_k = (R_W_B, p_W, v_W, b_g, b_a) at camera times, with
// - preintegrated IMU factors between consecutive keyframes (Forster et al., T-RO 2017, eq. 45),
// - bias random-walk factors (eq. 40) and a weak zero-mean prior on the first biases,
// - visual residuals: known map points (tag corners, surveyed landmarks) reprojected in pixels;
//   bearings of unknown ground features (Troiani et al., ECMR 2013: the features are parameters);
//   the laser spot on an unknown plane (Martinelli & Troiani, RR-7906: the plane is a parameter),
// - optional robust loss (Huber or Cauchy) on the visual residuals,
// - calibration blocks, constant unless asked for: per camera the extrinsic T_B_C
//   (quaternion manifold + translation, weak prior around the dataset's value), one camera-IMU
//   time offset t_d shared by the cameras (bounded to +-max_time_offset_s), and on a board map
//   (MapFrame::kBoard) the board's tilt to gravity q_W_M (solver/smoother/tilt_manifold.h: 2 DoF,
//   the yaw of W is gauge); with any of them the tag corners go through
//   CalibratedReprojectionFactor, else through MapPointReprojectionFactor as before,
// solved by Levenberg-Marquardt with a sparse Cholesky factorisation (SuiteSparse), and marginal
// covariances of the keyframe poses and of the calibration on request (SmootherCovarianceMethod).
// On a board map the solution is re-expressed in the W of core/board_frame.h (a rotation of every
// state about z_W, which leaves the IMU factors unchanged).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/dataset.h"
#include "core/pose.h"
#include "solver/laser/laser_spot_model.h"
#include "solver/smoother/imu_preintegration.h"
#include "solver/smoother/residuals/marginal_prior_factor.h"
#include "solver/smoother/smoother_covariance.h"
#include "solver/smoother/track_landmarks.h"

namespace mavloc {

struct SmootherKeyframe {
  TimeNs t_ns = 0;
  ImuKeyframeState state;
};

enum class SmootherLoss { kNone, kHuber, kCauchy };

// How the features0 landmarks enter the problem.
enum class LandmarkMode {
  kKnown,          // positions from map.landmarks_W, constant
  kUnknownGround,  // parameters on the ground plane z = 0 (three-point scenario gauge, see .cc)
  kUnknown,        // free 3-D parameters (gauge from a prior on the first pose)
  // Feature tracks (frontends/features/): each landmark anchored in its first keyframe and
  // parameterised by inverse depth (track_landmarks.h); features0 and features1; gauge as kUnknown.
  kTracks,
};

// How the marginal covariances (compute_covariance, calibration_covariance) are computed. Both give
// the blocks of (J^T J)^-1 in the tangent space at the solution, J the Jacobian of every residual
// (robust-loss corrections applied) over the non-constant parameter blocks; both report a rank
// deficient J (gauge freedom) as failure: pose_covariances stay nullopt and, when calibration
// covariances were asked for, SmootherCalibration::covariance_failed is set.
enum class SmootherCovarianceMethod {
  // solver/smoother/smoother_covariance.h: J^T J as a sparse matrix, a sparse Cholesky factor in
  // keyframe time order (calibration and long-seen landmarks as its border) and Takahashi's
  // selected inversion on the factor's pattern. Time and memory linear in the keyframes.
  kStructured,
  // ceres::Covariance (SPARSE_QR): one sparse triangular solve per requested column, time growing
  // quadratically with the keyframes (600 s of mav-figure-eight: minutes). Kept as the reference
  // for tests/evaluation/smoother_covariance_test.cc and benchmarks/smoother_benchmark.cc.
  kCeres,
};

struct SmootherProblemOptions {
  SmootherLoss loss = SmootherLoss::kHuber;
  double loss_scale = 2.0;  // in standard deviations (residuals are whitened)
  int max_iterations = 50;
  // Ceres' stopping tolerances (relative cost change, relative step). The tight defaults make a
  // converged solve agree to rounding between Jacobian implementations; the feature-track smoother
  // stops at 1e-8, far below the change any measurement noise could make.
  double function_tolerance = 1e-12;
  double parameter_tolerance = 1e-12;
  int num_threads = 2;
  bool compute_covariance = false;
  SmootherCovarianceMethod covariance_method = SmootherCovarianceMethod::kStructured;
  bool verbose = false;
  // The IMU and map-point reprojection factors differentiated automatically instead of by their
  // analytic Jacobians: the reference those are checked and timed against (same solution to
  // rounding).
  bool autodiff_jacobians = false;

  // Visual noise (standard deviations).
  double pixel_sigma_px = 1.0;           // tags0 corners and features0 in pixel mode
  double bearing_sigma_rad = 0.0174533;  // features0 in bearing mode (1 deg, the papers' noise)
  double laser_sigma_rad = 0.0174533;    // laser0
  bool features_as_bearings = false;     // features0 residual: pixels (false) or bearings (true)
  LandmarkMode landmarks = LandmarkMode::kKnown;
  TrackLandmarkOptions tracks;  // kTracks
  // Keyframes at which the vehicle is known to be at rest (feature tracks that do not move,
  // track_keyframes.h StationaryFrames): a prior v_W = 0 on each, a zero-velocity update. A static
  // mono camera sees no parallax, so nothing else stops an accelerometer bias from moving it.
  std::vector<TimeNs> zero_velocity_times;
  // Unknown landmarks (tracks, the laser plane): the prior that holds the first keyframe's
  // position and yaw. Without it those 4 degrees of freedom are free and the information matrix is
  // rank deficient (a covariance then fails and says so): for tests of the gauge.
  bool hold_gauge = true;
  double zero_velocity_sigma_m_s = 0.02;
  // kUnknownGround: the distance D = |P1 P2| when given (as the closed-form solvers are given it);
  // unset = estimated from the IMU.
  std::optional<double> given_D_m;

  // Laser (laser0): the beam in C, and whether the plane is a parameter (true) or map.plane.
  std::optional<LaserBeam> laser_beam;
  bool estimate_plane = true;

  // Tag corners: the cameras whose tag stream is used (0: tags0 with cameras[0], 1: tags1 with
  // cameras[1]).
  std::vector<int> cameras = {0};
  // Calibration (see the header comment). Extrinsics start from initial_T_B_C (per camera index;
  // the dataset's T_B_C where absent) with a prior of the given sigmas around the dataset's value.
  bool estimate_extrinsics = false;
  std::map<int, Pose> initial_T_B_C;
  double extrinsics_prior_m = 0.1;
  double extrinsics_prior_rad = 0.174533;  // 10 deg
  bool estimate_time_offset = false;
  double initial_time_offset_s = 0.0;
  double max_time_offset_s = 0.03;
  // Board map: the initial board-to-world rotation (the tilt is then estimated). Unset on world
  // maps (the map is in W).
  std::optional<Eigen::Quaterniond> initial_q_W_M;
  // Marginal covariances of the estimated calibration blocks.
  bool calibration_covariance = true;

  // The IMU residuals' fit at the solution (SmootherResult::imu_fit): their chi2 against their
  // redundancy, which says by how much the IMU noise densities are off (smoother_covariance.h,
  // ResidualGroupFit).
  bool fit_imu_noise = false;
  // Noise floors (continuous densities) used where the dataset's IMU noise is zero or smaller.
  ImuNoise noise_floor{1e-4, 1e-7, 1e-3, 1e-6};
  // Prior on the first keyframe's biases (zero mean).
  double gyro_bias_prior_rad_s = 0.05;
  double accel_bias_prior_m_s2 = 0.5;
  // Re-preintegrate at the estimated biases and solve again, up to this many times, when the
  // biases moved further than the thresholds from the linearization point.
  int relinearize_rounds = 1;
  double relinearize_gyro_rad_s = 2e-3;
  double relinearize_accel_m_s2 = 2e-2;

  // Windows (solver/smoother/smoother_windows.h). A prior on the first keyframe's whole state that
  // stands for the keyframes and residuals before it (it replaces the zero-mean bias priors).
  std::optional<KeyframeMarginalPrior> first_keyframe_prior;
  // > 0: after the last solve, keyframes 0..m-1 and their residuals are eliminated onto keyframe m
  // (SmootherResult::marginal_prior, solver/smoother/smoother_marginalization.h).
  int marginalize_before_keyframe = 0;
  // The first constant_keyframes keyframes are held at their initial states: the context of a
  // sliding window, solved before, that fixes the gauge and carries what the measurements before
  // the window said through the landmarks they share and the IMU factor into the window. No bias
  // or gauge prior is added then.
  int constant_keyframes = 0;
  // Dropped measurements at or after this time are not counted (the next window counts them).
  TimeNs count_dropped_before_ns = std::numeric_limits<TimeNs>::max();
};

struct SmootherStatistics {
  int num_keyframes = 0;
  int num_imu_factors = 0;
  int num_visual_residuals = 0;
  int num_parameters = 0;
  int iterations = 0;
  int solves = 0;   // 1 + relinearization rounds that ran
  int windows = 1;  // 1 for a batch solve; residual counts add up over windows, overlaps included
  double preintegration_s = 0.0;
  double solve_s = 0.0;  // Ceres total time, all solves
  double linear_solver_s = 0.0;
  double residual_evaluation_s = 0.0;
  double jacobian_evaluation_s = 0.0;
  double covariance_s = 0.0;
  // kStructured (smoother_covariance.h): min_j L_jj^2 / H_jj of the information matrix's Cholesky
  // factor (how close to rank deficient; 0 when not computed).
  double covariance_min_relative_pivot = 0.0;
  double initial_cost = 0.0;
  double final_cost = 0.0;
  // Whether the last Ceres solve of this result stopped on its tolerances (for windows: every
  // window's did) rather than at max_iterations, and the relative cost decrease of that solve's
  // last iteration. A solution that did not converge is not at the optimum: its numbers move with
  // the arithmetic's rounding (another Jacobian, compiler or machine). AddStatistics leaves both
  // to the result they are added to.
  bool converged = true;
  double last_relative_cost_change = 0.0;
  std::string linear_solver;
  std::string ceres_brief_report;
  std::string ceres_full_report;
};

// The calibration at the solution (what was estimated, and what was held).
struct SmootherCalibration {
  std::map<int, Pose> T_B_C;  // per camera index used for tag corners
  // Marginal covariance of [p_B_C (m); dtheta (rad, right perturbation R_B_C Exp(dtheta))].
  std::map<int, Eigen::Matrix<double, 6, 6>> T_B_C_covariance;
  double time_offset_s = 0.0;
  std::optional<double> time_offset_sigma_s;
  // Board map: R_W_M in the convention of core/board_frame.h, and the covariance of the tilt as a
  // left perturbation Exp((d1, d2, 0)) R_W_M about W's x and y axes (rad^2).
  std::optional<Eigen::Quaterniond> q_W_M;
  std::optional<Eigen::Matrix2d> tilt_covariance;
  bool covariance_failed = false;  // asked for and not computable (rank deficiency)
};

// Tag corners at the solution: pixel errors (before the robust loss) and how many corners the loss
// down-weights (whitened error beyond loss_scale).
struct SmootherCornerStatistics {
  int corners = 0;
  double rms_px = 0.0;
  int downweighted = 0;
};

struct SmootherResult {
  bool usable = false;
  std::string message;  // why the solution is not usable, or Ceres' termination message
  std::vector<SmootherKeyframe> keyframes;
  // Marginal covariance of [p_W (m); dtheta (rad, right perturbation R Exp(dtheta))] per keyframe,
  // when requested and computable.
  std::vector<std::optional<Eigen::Matrix<double, 6, 6>>> pose_covariances;
  std::map<int, Eigen::Vector3d> landmarks_W;  // estimated (unknown-landmark modes)
  std::optional<Plane> plane;                  // estimated (laser with estimate_plane)
  std::map<std::string, int> dropped;          // measurements not used, by reason
  SmootherCalibration calibration;
  SmootherCornerStatistics corner_statistics;
  SmootherStatistics statistics;
  // With options.fit_imu_noise: the IMU preintegration and bias random-walk factors' fit.
  std::optional<ResidualGroupFit> imu_fit;
  // With options.marginalize_before_keyframe: the prior for the next window, or why there is none.
  std::optional<KeyframeMarginalPrior> marginal_prior;
  std::string marginalization_failure;
};

// Adds the iterations, solves and times of `from` to `to` (several solves of one problem).
void AddStatistics(const SmootherStatistics& from, SmootherStatistics* to);

// Solves the smoother from initial keyframe states (sorted by time, inside the IMU stream; in the
// W of options.initial_q_W_M on a board map) and, for unknown landmarks, their initial positions.
// Measurements are attached to the keyframe at their time (within 1 ms); others are dropped and
// counted.
SmootherResult SolveSmoother(const Dataset& dataset, const std::vector<SmootherKeyframe>& initial,
                             const std::map<int, Eigen::Vector3d>& initial_landmarks_W,
                             const std::optional<Plane>& initial_plane,
                             const SmootherProblemOptions& options);

}  // namespace mavloc
