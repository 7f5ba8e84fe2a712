// Cramér–Rao bounds of the batch smoother's problem on a simulated dataset: the Fisher
// information of all measurements about the keyframe states x_k = (p_W, theta, v_W, b_g, b_a) at
// the smoother's keyframe times, evaluated at the TRUE states (the ground truth), with the
// dataset's stated noise models and the priors and gauge the smoother uses.
//
// The Jacobians do not come from the smoother's residual code (solver/smoother/residuals):
// - IMU: the linearised error-state propagation of the strapdown model of DESIGN.md "Conventions"
//   (w_m = w + b_g + n_g, a_m = R^T (a - g) + b_a + n_a, biases as random walks; e.g. Sola,
//   "Quaternion kinematics for the error-state Kalman filter", 2017, sec. 5.3 and 7.2, with the
//   right perturbation R = R_true Exp(dtheta)) over every IMU sample interval between two
//   keyframes, with the true attitude and the bias-corrected samples held over each interval
//   (zero-order hold, as the samples are simulated): x_{k+1} = Phi x_k + w, w ~ N(0, Q), whose
//   information enters as Tichavsky et al.'s D11, D12, D22 (markov_information.h). The bias walk
//   inside the interval is part of Q (the smoother models it as a separate factor).
// - Vision: the analytic pixel Jacobian (pixel_jacobian.h: CameraModel::ProjectWithJacobian, the
//   simulator's projection differentiated by hand) of every map point observed at a keyframe (tag
//   corners of tags0/tags1, features0 landmarks in pixels), whitened by the pixel noise sigma.
// - Priors: the smoother's zero-mean prior on the first biases (the turn-on bias sigma the
//   dataset states, SmootherEstimator::ProblemOptionsFor); no pose prior: known map points fix
//   the gauge, as in the smoother.
// - Board maps (MapFrame::kBoard, e.g. aprilgrid-calibration): the smoother estimates the board's
//   tilt to gravity q_W_M (solver/smoother/smoother_problem.h, TiltManifold: 2 DoF, the yaw of W
//   is gauge), so the bound includes it as a nuisance parameter d (map point p_W = Exp((d1, d2, 0))
//   R_W_M p_M, the manifold's tangent at the true R_W_M from the truth quantities board_roll,
//   board_pitch) and marginalises it out exactly (markov_information.h). The keyframe states stay
//   in the W whose yaw the manifold fixes; the smoother then re-expresses its solution in the
//   canonical W of core/board_frame.h, a rotation about z_W by psi(d), so the reported pose is a
//   function of (x_k, d) and its bound is L Sigma L^T with L = [I, K_k], K_k = d(Rz(psi) x_k)/dd
//   (the CRLB of a function of the parameters). The filtering bound is the one with the tilt
//   KNOWN (no K either): the papers' estimators on a board map initialise gravity from a window of
//   the log (solver/board/board_world.h, gravity_init_s), i.e. they are causal in the pose but not
//   in the tilt, and a bound with the tilt unknown to a causal estimator (markov_information.h
//   can compute it: nuisance_node) is huge over the first frames, where gravity in M is not yet
//   observable from the IMU (126 mm RMS over aprilgrid-calibration, against 0.24 mm with the
//   tilt known), so it says nothing about them. With the tilt known the bound is smaller, still a
//   lower bound for any estimator causal in the pose; it can be below the smoothing bound, which
//   has the tilt unknown. Marginalising rather than bounding gauge-invariant
//   quantities only: the reported T_W_B in the canonical W is already gauge-invariant (it depends
//   only on T_M_B and the gravity direction in M). The time offset and extrinsics, when asked to be
//   estimated, are not modelled (no bound).
// - Laser-only data (laser-plane, euroc-laser; evaluation/crlb/laser_bound.h): the spot's bearing
//   angle atan(x) of the simulator's model with the stated angular noise (scenario.yaml
//   bearing_noise_deg, as the smoother reads it), the plane (unit normal on the sphere, offset) a
//   static nuisance parameter without prior, marginalised exactly (markov_information.h, with
//   nuisance_node: the filtering bound has the plane unknown too), and the smoother's gauge priors
//   on its first keyframe. The position, the in-plane velocity, the yaw and the rotation about the
//   plane normal are unobservable, so the 15 x 15 bounds are those of the smoother's gauge (errors
//   relative to its first keyframe, not against the truth's frame); what is bounded is the five
//   gauge-invariant quantities of RR-7906 (d, v_o, roll, pitch, alpha: CrlbKeyframe::laser), by
//   J Sigma J^T with Sigma the joint covariance of (x_k, plane). Here the IMU transition is
//   linearised at the TRUE motion over each sample interval [a, b] (from the ground truth:
//   w = Log(R_a^T R_b) / h, and the specific force of the velocity row
//   f = R_a^T ((v_b - v_a) / h - g) and of the position row
//   f_p = R_a^T (2 (p_b - p_a - v_a h) / h^2 - g), the exact increments of the true states)
//   instead of the noisy samples held over the interval: the Fisher information is the one of the
//   measurement means at the true states, and only then are the unobservable rotations (about
//   gravity; about the normal with the in-plane acceleration) exact null directions of it. With
//   the samples they would look slightly observable through the sample noise and the
//   discretisation, and the gauge priors would leak into the quantities' bound
//   (tests/evaluation/crlb_laser_bound_test.cc prints by how much).
// Unsupported (reported, no bound): unknown landmarks and bearings
// (three-point scenario). Bearings have no
// finite bound under the simulator's angular noise
// (datasets/simulation/camera_simulator.h PerturbBearing: a Gaussian angle theta ~ N(0, s^2)
// about a uniformly random perpendicular axis): the 2-D tangent error e = theta u has the density
// 2 N(r; 0, s) / (2 pi r) with a 1/r cusp at r = 0, so E[|d log p / de|^2] >= E[1/r^2] diverges
// and the Fisher information is infinite (tests/evaluation/crlb_angular_noise_test.cc measures
// the cusp: P(r < eps) grows like eps, not eps^2).
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "core/dataset.h"
#include "solver/estimator.h"

namespace mavloc {

using Matrix15d = Eigen::Matrix<double, 15, 15>;

// Error-state order of the bound: [dp_W (m); dtheta (rad, R Exp(dtheta)); dv_W (m/s); db_g; db_a].
enum CrlbStateIndex { kCrlbP = 0, kCrlbTheta = 3, kCrlbV = 6, kCrlbBg = 9, kCrlbBa = 12 };

// Laser-only data: the bound on the five gauge-invariant quantities d [m], v_o [m/s], roll, pitch,
// alpha [rad] (evaluation/crlb/laser_bound.h, LaserQuantityNames) at a keyframe.
struct CrlbLaserQuantities {
  Eigen::Matrix<double, 5, 1> truth = Eigen::Matrix<double, 5, 1>::Zero();  // true values
  Eigen::Matrix<double, 5, 5> smoothing = Eigen::Matrix<double, 5, 5>::Zero();
  std::optional<Eigen::Matrix<double, 5, 5>> filtering;  // unset before the state is observable
  // Standard deviations (sqrt of the diagonal); alpha's is NaN on a horizontal plane.
  Eigen::Matrix<double, 5, 1> SmoothingSigmas() const;
  std::optional<Eigen::Matrix<double, 5, 1>> FilteringSigmas() const;
};

struct CrlbKeyframe {
  TimeNs t_ns = 0;
  Pose T_W_B;                                // true pose
  Matrix15d smoothing;                       // covariance bound of the batch problem
  std::optional<Matrix15d> filtering;        // causal bound (unset before the state is observable)
  std::optional<CrlbLaserQuantities> laser;  // laser-only data
};

struct SmootherCrlb {
  bool ok = false;
  std::string reason;  // why there is no bound
  std::vector<CrlbKeyframe> keyframes;
  int visual_residuals = 0;  // 2-D measurements in the information
  // Board map: the bound on the tilt d (left perturbation Exp((d1, d2, 0)) R_W_M about W's x and y
  // axes, rad^2; as SmootherCalibration::tilt_covariance).
  std::optional<Eigen::Matrix2d> tilt_covariance;
  // Laser-only data: the keyframes carry `laser`; the 15 x 15 bounds are in the smoother's gauge.
  bool laser_only = false;
  // Laser-only data: the bound on the plane tangent (dn1, dn2 [rad], dd [m]; laser_bound.h).
  std::optional<Eigen::Matrix3d> plane_covariance;
  double compute_s = 0.0;
};

// Model choices of the bound that tests vary (the defaults are the smoother's problem).
struct CrlbModelOptions {
  // Laser-only data: the keyframe that carries the smoother's gauge priors (-1: the last one;
  // the smoother's: 0). The bound on the five quantities must not depend on it.
  int laser_gauge_keyframe = 0;
  // Laser-only data: linearise the IMU transitions at the true rates (see the header) rather than
  // at the noisy samples (the other data always use the samples).
  bool laser_true_imu_rates = true;
};

// The bound for the smoother with the given estimator options (as `--option` gives them; the
// noise sigmas, bias priors and keyframe_stride are read as the smoother reads them).
SmootherCrlb ComputeSmootherCrlb(const Dataset& dataset,
                                 const EstimatorOptions& smoother_options = EstimatorOptions(),
                                 const CrlbModelOptions& model = CrlbModelOptions());

// Standard deviations of a 15 x 15 bound at attitude R_W_B.
struct CrlbSigmas {
  double position_m = 0.0;    // sqrt(trace): bound on the RMS position error (ATE translation)
  double attitude_rad = 0.0;  // sqrt(trace): bound on the RMS rotation angle (ATE rotation)
  Eigen::Vector3d xyz_m, rpy_rad, v_m_s, b_g_rad_s, b_a_m_s2;
};
CrlbSigmas SigmasOf(const Matrix15d& covariance, const Eigen::Quaterniond& q_W_B);

}  // namespace mavloc
