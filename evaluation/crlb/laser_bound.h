// The laser-spot pieces of the smoother's Cramér–Rao bound (evaluation/crlb/smoother_bound.h
// assembles them). Laser-only data (laser-plane, euroc-laser): the laser spot of
// Martinelli & Troiani, "Vision-Aided Inertial Navigation Using Virtual Features", INRIA RR-7906,
// 2012 (../shared/papers/laser-spot-virtual-feature.txt), on a plane the smoother estimates.
//
// Measurement: the simulator's model (datasets/scenarios/laser_plane.h, SimulateLaserSpots), not
// the smoother's residual (solver/smoother/residuals/laser_spot_plane_factor.h): a laser at
// o_C = (L, 0, 0) along l_C = e_z of the camera C (T_W_C = T_W_B T_B_C) meets the plane
// n_W . x = d_m at the range s = (d_m - n_W . o_W) / (n_W . l_W) (o_W = T_W_C o_C,
// l_W = R_W_C l_C); the camera sees the spot at the normalized x = L / s, y = 0, and the simulator
// adds Gaussian noise of sigma to each bearing angle atan(x), atan(y). The measurement
// z = atan(x) + noise is exactly Gaussian, so its Fisher information is J^T J / sigma^2 with
// J = d atan(L / s) / d(state, plane); atan(y) = 0 for every state carries none.
//
// Parameters: the error state of smoother_bound.h (right perturbation R_W_B Exp(dtheta)) and the
// plane as the smoother parameterises it (smoother_problem.cc: the unit normal n_W on the sphere
// manifold, the offset d_m free, no prior), as the tangent delta = (dn1, dn2, dd):
// n_W = normalize(n0 + dn1 b1 + dn2 b2), d_m = d0 + dd, with (b1, b2) an orthonormal basis
// perpendicular to n0 (the bound on gauge-invariant quantities does not depend on the choice of
// chart: the CRLB of a function is invariant under a reparameterisation).
//
// Quantities (the paper's observable modes, sec. 4 and appendix B; defined as the simulator's
// truth quantities, LaserTruthQuantities, which the smoother's output, ModesFromPose and
// QuantitiesFromModes of solver/laser/laser_spot_model.h, reproduces): for the camera C and the
// plane with its normal towards the camera,
//   d = |n_W . p_W_C - d_m|,  v_o = n_W . v_W,  n_C = R_W_C^T n_W,
//   roll = atan2(n_C.y, n_C.z),  pitch = asin(-n_C.x),  alpha = acos(-n_W . g_W / |g|).
// (v_W is the body's velocity, as the simulator writes it: T_B_C has no translation in the laser
// scenarios.)
//
// Gauge (smoother_problem.cc, the laser-only problem): the position, the in-plane velocity, the
// rotation about gravity and the rotation about the plane normal (with a constant acceleration
// along the plane; RR-7906 appendix B) are unobservable, 7 directions (6 when the plane is
// horizontal). The smoother fixes them by priors on its first keyframe: 1e6 (square-root
// information) on the position and on the rotation about gravity and about the normal's component
// perpendicular to gravity, and 1 / (0.1 m/s) on the velocity along the plane. These are minimal
// (one prior direction per unobservable direction), so neither their place nor their strength
// changes the bound on the five gauge-invariant quantities (tests/evaluation/
// crlb_laser_bound_test.cc moves them to the last keyframe and gets the same bound within 4e-5);
// the bound uses 1e3 instead of 1e6 for numerical conditioning (laser_bound.cc). The bounds on the
// position and attitude are those of this gauge (relative to the first keyframe), not errors
// against the truth's frame.
//
// Long runs: the forward pass of markov_information.cc runs in square-root form (no Q^-1, whose
// bias-walk floors are ~1e15 beside the weak laser information; the information form lost its
// positive definiteness at 60 s for 4 seeds of 20 and on euroc-laser). Left: the plane's Schur
// complement C - B^T A^-1 B is still a subtraction, and fails for 1 seed of 16 at 300 s.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "core/dataset.h"
#include "core/pose.h"
#include "evaluation/crlb/smoother_bound.h"
#include "solver/laser/laser_spot_model.h"

namespace mavloc {

using Vector5d = Eigen::Matrix<double, 5, 1>;
using Matrix5d = Eigen::Matrix<double, 5, 5>;

// The five quantities in order, their units (SI).
const std::vector<std::string>& LaserQuantityNames();  // d, v_o, roll, pitch, alpha
const std::vector<std::string>& LaserQuantityUnits();  // m, m/s, rad, rad, rad

// The plane tangent (see the header): the basis (b1, b2) perpendicular to n_W (unit), and the
// perturbed plane.
Eigen::Matrix<double, 3, 2> PlaneTangentBasis(const Eigen::Vector3d& n_W);
Plane PerturbPlane(const Plane& plane, const Eigen::Vector3d& delta);

// The simulator's laser: at (L_m, 0, 0) along z of the camera T_W_B * T_B_C.
struct LaserSpotModel {
  double L_m = 0.0;
  double sigma_rad = 0.0;  // noise of the bearing angle atan(x)
  Plane plane;             // the true plane, its normal towards the vehicle
  Pose T_B_C;
};

// The bearing angle atan(L / s) of the spot, or nullopt where the simulator has no spot (the beam
// misses the plane: s <= 0).
std::optional<double> LaserSpotBearing(const LaserSpotModel& model, const Pose& T_W_B);

// Analytic Jacobian of the bearing angle (not whitened), columns [dp_W (3); dtheta (3); plane
// delta (3)], at the pose and the model's plane; false where there is no spot.
bool LaserSpotBearingJacobian(const LaserSpotModel& model, const Pose& T_W_B,
                              Eigen::Matrix<double, 1, 9>* J);

// The five quantities at a true state (the simulator's definition, see the header).
Vector5d LaserQuantitiesAt(const LaserSpotModel& model, const Pose& T_W_B,
                           const Eigen::Vector3d& v_W);
// Their analytic Jacobian: columns the 15 error-state components (CrlbStateIndex order), then the
// plane delta (3). The alpha row is zero (and alpha has no bound) on a horizontal plane, where acos
// is not differentiable.
Eigen::Matrix<double, 5, 18> LaserQuantityJacobian(const LaserSpotModel& model, const Pose& T_W_B,
                                                   const Eigen::Vector3d& v_W);

// The information (15 x 15, CrlbStateIndex order) of the smoother's gauge priors of the laser-only
// problem placed at the state with attitude R_W_B, for the plane normal n_W (see the header).
Matrix15d LaserGaugePriorInformation(const Eigen::Matrix3d& R_W_B, const Eigen::Vector3d& n_W);

// The model of a laser-only dataset for the smoother's beam (SmootherProblemOptions::laser_beam)
// and laser noise, with the true plane of map.yaml oriented towards the camera at T_W_B0; nullopt
// with *why when the dataset has no true plane or the beam is not the simulator's (origin
// (L, 0, 0), direction e_z).
std::optional<LaserSpotModel> LaserSpotModelFor(const Dataset& dataset,
                                                const std::optional<LaserBeam>& beam,
                                                double sigma_rad, const Pose& T_W_B0,
                                                std::string* why);

// Covariance of the quantities from the joint covariance of (x_k, plane): J [Sxx Sxd; Sdx Sdd] J^T.
Matrix5d LaserQuantityCovariance(const Eigen::Matrix<double, 5, 18>& J, const Eigen::MatrixXd& Sxx,
                                 const Eigen::MatrixXd& Sxd, const Eigen::MatrixXd& Sdd);

}  // namespace mavloc
