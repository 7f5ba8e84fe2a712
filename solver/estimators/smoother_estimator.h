// smoother: the Ceres batch smoother over keyframe states (solver/smoother/smoother_problem.h)
// seeded by a closed-form / PnP estimator (solver/smoother/smoother_initialization.h).
//
// Visual residuals it builds (any combination present in the dataset):
// - features0 with map landmarks: reprojection in pixels (bearings when the camera has no
//   intrinsics or the scenario states an angular noise);
// - features0 of the three-point scenario (map parameter "D"): unknown ground features as
//   parameters, with the paper's frame (P1 origin, P2 on the x axis) as gauge; D given or
//   estimated;
// - tags0 with map tags: the four corners of each tag reprojected in pixels;
// - laser0 with a laser beam (map parameters laser_Lx, laser_Ly, laser_theta, laser_phi of
//   appendix A) on an unknown plane. Laser-only data are seeded by laser-ekf's modes
//   (smoother_initialization.h, InitializeFromLaserModes); the in-plane position, the in-plane
//   velocity and the yaw about the normal are unobservable (RR-7906 appendix B) and fixed by
//   priors on the first keyframe, so only the gauge-free quantities d, v_o, roll, pitch (relative
//   to the plane) and alpha are reported.
//
// Options (`--option key=value`):
//   seed            seed estimator (default by data: tag-pnp, three-point, laser-ekf, or the
//                   built-in landmark-pnp for features0 with map landmarks)
//   seed.KEY=VALUE  passed to the seed estimator as KEY=VALUE
//   loss            huber | cauchy | none (huber)      loss_scale   in sigmas (2)
//   covariance      0/1: marginal pose covariances (smoother_covariance.h) (0)
//   max_iterations  (50)   threads (2)   keyframe_stride (1: every camera frame)
//   pixel_sigma_px, bearing_sigma_deg, laser_sigma_deg: measurement noise (default from
//                   scenario.yaml when stated, else 1 px / 1 deg)
//   landmarks       auto | known | ground | unknown (auto)
//   estimate_D      0/1: three-point world, estimate the scale D from the IMU instead of taking
//                   map.yaml's D as the closed-form solvers do (0)
//   gyro_bias_prior_deg_s, accel_bias_prior_m_s2: zero-mean prior on the first biases (default:
//                   the turn-on bias sigmas imu0/sensor.yaml states, floored at 1e-4 deg/s and
//                   1e-4 m/s^2; else 0.5 deg/s and 0.1 m/s^2)
//   relinearize     rounds of re-preintegration at the estimated biases (1)
//   graduated       0/1: with a bias prior tighter than the generic one and no known map points
//                   (laser, unknown landmarks), also solve with the generic prior first and keep
//                   the lower-cost of the two solutions (1)
//   fit_imu_noise   0/1: scale the IMU's four noise densities until the IMU factors' chi2 equals
//                   their redundancy (variance component estimation, smoother_covariance.h
//                   ResidualGroupFit), solving again each time; the scale is the parameter
//                   imu_noise_scale, with its standard deviation (0)
//
// Calibration. Tag corners of tags0 (cam0) and tags1 (cam1) each enter with their own
// camera model and T_B_C.
//   cameras              all | cam0 | cam1 | cam0,cam1: whose tags are used (all: every camera
//                        with map tags). Seed: tag-pnp when cam0 is used, else a built-in per-frame
//                        PnP on tags1 (seed name "tag-pnp-cam1").
//   estimate_extrinsics  0/1: T_B_C of each used camera as parameters (0)
//   extrinsics_prior_m, extrinsics_prior_deg: the weak prior around the dataset's T_B_C (0.1, 10)
//   estimate_time_offset 0/1: one camera-IMU time offset t_d (exposure = stamp + t_d) (0)
//   time_offset_init_ms  initial t_d (0)     max_time_offset_ms  |t_d| bound (30)
//   calibration_covariance 0/1: marginal covariances of the estimated calibration (1)
//   gravity_window_s     board maps: seed window for the initial gravity direction (2)
//   grow_window_s        laser-only data whose solution has an implausible cost (a seed gone
//                        astray): solve again on the first grow_window_s seconds, then on windows
//                        grown by up to 2 grow_window_s at a time, new keyframes from the IMU;
//                        keep the lower cost (3; 0: off)
// Long logs (solver/smoother/smoother_windows.h):
//   memory_budget_mib    the batch problem's estimated memory above which the keyframes are solved
//                        in overlapping windows, each starting from the previous one's marginal
//                        prior, each window's problem a quarter of the budget (1024)
//   window_s             > 0: always solve in windows of this length (0: by the budget)
//   window_overlap_s     the later measurements each kept keyframe has behind it (5)
// Windows are refused for what a keyframe prior cannot carry (estimated landmarks, a laser plane,
// calibration, fit_imu_noise): those problems are solved as one batch, with an event saying so.
// On a board map (MapFrame::kBoard) the gravity direction in M is always estimated: the seed's
// poses are in M; EstimateUpInBoardFromPositions (solver/board/board_gravity_from_positions.h)
// gives the initial up_M from the first gravity_window_s of them and the accelerometer; the
// smoother estimates the tilt (2 DoF) and reports poses in the W of core/board_frame.h,
// Estimate::T_W_M, the quantities board_roll and board_pitch (constant) and Estimate::parameters
// board_roll, board_pitch with sigmas. Parameters reported on every tag dataset: reprojection_rms
// [px] and downweighted_corners (corners whose whitened error exceeds loss_scale) of the final
// solution; time_offset [s] when estimated; Estimate::extrinsics (T_B_C with the 6 x 6 covariance
// of [p; dtheta]) per estimated camera.
#pragma once

#include <optional>
#include <set>
#include <string>
#include <vector>

#include "solver/estimator.h"
#include "solver/smoother/smoother_initialization.h"
#include "solver/smoother/smoother_problem.h"
#include "solver/smoother/smoother_windows.h"

namespace mavloc {

class SmootherEstimator : public Estimator {
 public:
  explicit SmootherEstimator(const EstimatorOptions& options);
  std::string name() const override { return "smoother"; }
  Applicability AppliesTo(const Dataset& dataset) const override;
  Estimate Run(const Dataset& dataset) override;

  // The same from given seed poses instead of running the seed estimator (tests, benchmarks). The
  // poses are in the map's frame: W, or the board frame M on a board map (T_M_B).
  Estimate RunFromSeedPoses(const Dataset& dataset, const std::vector<StampedPose>& seed_poses);

  // Laser-only data: keyframes from the laser EKF's modes (seed_estimate.quantities: d, v_o, roll,
  // pitch, alpha), output the modes' quantities (Run uses laser-ekf's; tests give their own).
  Estimate RunFromLaserModes(const Dataset& dataset, const Estimate& seed_estimate);

  // Feature tracks of unknown landmarks (features0/features1 of frontends/features/):
  // smoother_tracks.cc.
  Estimate RunFromTracks(const Dataset& dataset);

  // The seed estimator used for a dataset, and the problem options derived from it.
  std::string SeedEstimatorFor(const Dataset& dataset) const;
  SmootherProblemOptions ProblemOptionsFor(const Dataset& dataset) const;
  // Details of the last run (Ceres summary, timing, keyframes).
  const SmootherResult& last_result() const { return last_result_; }

 private:
  // Camera indices whose tags enter (option `cameras`).
  std::vector<int> CamerasFor(const Dataset& dataset) const;
  bool IsLaserOnly(const Dataset& dataset) const;
  // The smoother problem's options on feature tracks (smoother_tracks.cc).
  SmootherProblemOptions TrackProblemOptions(const Dataset& dataset) const;
  // The growing window over the track keyframes `times` from `start` (smoother_tracks.cc); what
  // its stages took is appended to *timing ("sliding window: ...; batch: ..."). Tracks whose
  // reprojection error stays high after a sliding solve are removed from *tracked and listed in
  // *removed.
  SmootherResult SolveTracksGrowing(Dataset* tracked, const std::vector<TimeNs>& times,
                                    const ImuKeyframeState& start,
                                    const SmootherProblemOptions& options, std::string* timing,
                                    std::set<int>* removed) const;
  // The windows to solve `keyframes` in (options window_s, window_overlap_s, memory_budget_mib),
  // nullopt for one batch; the choice is added to the estimate's events.
  std::optional<SmootherWindowOptions> WindowsFor(const Dataset& dataset,
                                                  const std::vector<SmootherKeyframe>& keyframes,
                                                  const SmootherProblemOptions& problem_options,
                                                  Estimate* estimate) const;

  EstimatorOptions options_;
  SmootherResult last_result_;
};

}  // namespace mavloc
