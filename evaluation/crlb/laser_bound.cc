#include "evaluation/crlb/laser_bound.h"

#include <algorithm>
#include <cmath>

#include "core/imu.h"
#include "core/rotation.h"

namespace mavloc {

namespace {

// The smoother's laser-only gauge priors (solver/smoother/smoother_problem.cc): square-root
// information of the first position and of the rotations about gravity and about the plane
// normal, the sigma of the in-plane velocity, and the smallest angle between the normal and
// gravity for which the rotation about the normal is a separate direction. The smoother uses
// 1e6; the bound uses 1e3 (1 mm, 1 mrad): the priors are minimal, so their strength does not
// change the bound on the gauge-invariant quantities (as their place does not: the test moves
// them), and 1e6 (1e12 beside data information of 1e2 .. 1e6) made the information of 60 s
// laser-plane runs fail the conditioning of markov_information.cc more often (seed 1 too).
constexpr double kGaugeSqrtInformation = 1e3;
constexpr double kInPlaneVelocitySigmaMS = 0.1;
constexpr double kDistinctNormalDeg = 1.0;

// The beam in W and the range along it (the simulator's SimulateLaserSpots).
struct Beam {
  Eigen::Vector3d a_B;  // the laser origin relative to B, in B: p_B_C + R_B_C o_C
  Eigen::Vector3d b_B;  // the beam direction in B: R_B_C e_z
  Eigen::Vector3d o_W;
  Eigen::Vector3d l_W;
  double numerator = 0.0;    // d_m - n . o_W
  double denominator = 0.0;  // n . l_W
  double range = -1.0;       // numerator / denominator, <= 0 when the beam misses the plane
};

Beam BeamAt(const LaserSpotModel& model, const Pose& T_W_B) {
  Beam beam;
  const Eigen::Matrix3d R_B_C = model.T_B_C.R();
  beam.a_B = model.T_B_C.p + R_B_C * Eigen::Vector3d(model.L_m, 0.0, 0.0);
  beam.b_B = R_B_C * Eigen::Vector3d::UnitZ();
  const Eigen::Matrix3d R_W_B = T_W_B.R();
  beam.o_W = T_W_B.p + R_W_B * beam.a_B;
  beam.l_W = R_W_B * beam.b_B;
  const Eigen::Vector3d& n = model.plane.n_W;
  beam.numerator = model.plane.d_m - n.dot(beam.o_W);
  beam.denominator = n.dot(beam.l_W);
  if (std::abs(beam.denominator) > 1e-12) beam.range = beam.numerator / beam.denominator;
  return beam;
}

}  // namespace

const std::vector<std::string>& LaserQuantityNames() {
  static const std::vector<std::string> kNames = {"d", "v_o", "roll", "pitch", "alpha"};
  return kNames;
}

const std::vector<std::string>& LaserQuantityUnits() {
  static const std::vector<std::string> kUnits = {"m", "m/s", "rad", "rad", "rad"};
  return kUnits;
}

Eigen::Matrix<double, 3, 2> PlaneTangentBasis(const Eigen::Vector3d& n_W) {
  const Eigen::Vector3d n = n_W.normalized();
  const Eigen::Vector3d e =
      std::abs(n.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  const Eigen::Vector3d b1 = (e - e.dot(n) * n).normalized();
  Eigen::Matrix<double, 3, 2> B;
  B.col(0) = b1;
  B.col(1) = n.cross(b1);
  return B;
}

Plane PerturbPlane(const Plane& plane, const Eigen::Vector3d& delta) {
  const Eigen::Matrix<double, 3, 2> B = PlaneTangentBasis(plane.n_W);
  Plane out;
  out.n_W = (plane.n_W.normalized() + B * delta.head<2>()).normalized();
  out.d_m = plane.d_m + delta.z();
  return out;
}

std::optional<double> LaserSpotBearing(const LaserSpotModel& model, const Pose& T_W_B) {
  const Beam beam = BeamAt(model, T_W_B);
  if (beam.range <= 0.0) return std::nullopt;
  return std::atan(model.L_m / beam.range);
}

bool LaserSpotBearingJacobian(const LaserSpotModel& model, const Pose& T_W_B,
                              Eigen::Matrix<double, 1, 9>* J) {
  const Beam beam = BeamAt(model, T_W_B);
  if (beam.range <= 0.0) return false;
  const Eigen::Vector3d& n = model.plane.n_W;
  const Eigen::Matrix3d R_W_B = T_W_B.R();
  const Eigen::Matrix<double, 3, 2> B = PlaneTangentBasis(n);
  // N = d - n . o_W, D = n . l_W; with R_W_B Exp(dtheta): do_W = -R [a_B]x dtheta,
  // dl_W = -R [b_B]x dtheta; with the plane delta: dn = B delta12, dd = delta3.
  Eigen::Matrix<double, 1, 9> dN = Eigen::Matrix<double, 1, 9>::Zero();
  Eigen::Matrix<double, 1, 9> dD = Eigen::Matrix<double, 1, 9>::Zero();
  dN.segment<3>(0) = -n.transpose();
  dN.segment<3>(3) = n.transpose() * R_W_B * Skew(beam.a_B);
  dN.segment<2>(6) = -beam.o_W.transpose() * B;
  dN(8) = 1.0;
  dD.segment<3>(3) = -n.transpose() * R_W_B * Skew(beam.b_B);
  dD.segment<2>(6) = beam.l_W.transpose() * B;
  const double s = beam.range;
  const Eigen::Matrix<double, 1, 9> ds = (dN - s * dD) / beam.denominator;
  // z = atan(L / s): dz/ds = -L / (s^2 + L^2).
  *J = -model.L_m / (s * s + model.L_m * model.L_m) * ds;
  return true;
}

Vector5d LaserQuantitiesAt(const LaserSpotModel& model, const Pose& T_W_B,
                           const Eigen::Vector3d& v_W) {
  const Pose T_W_C = T_W_B * model.T_B_C;
  const Eigen::Vector3d& n = model.plane.n_W;
  const Eigen::Vector3d n_C = T_W_C.q.conjugate() * n;
  Vector5d q;
  q << std::abs(n.dot(T_W_C.p) - model.plane.d_m), n.dot(v_W), std::atan2(n_C.y(), n_C.z()),
      std::asin(std::clamp(-n_C.x(), -1.0, 1.0)),
      std::acos(std::clamp(-n.dot(GravityW()) / kGravityMagnitude, -1.0, 1.0));
  return q;
}

Eigen::Matrix<double, 5, 18> LaserQuantityJacobian(const LaserSpotModel& model, const Pose& T_W_B,
                                                   const Eigen::Vector3d& v_W) {
  Eigen::Matrix<double, 5, 18> J = Eigen::Matrix<double, 5, 18>::Zero();
  constexpr int kPlane = 15;
  const Eigen::Vector3d& n = model.plane.n_W;
  const Eigen::Matrix3d R_W_B = T_W_B.R();
  const Eigen::Matrix3d R_B_C = model.T_B_C.R();
  const Pose T_W_C = T_W_B * model.T_B_C;
  const Eigen::Matrix<double, 3, 2> B = PlaneTangentBasis(n);

  // d = sign(m1) m1, m1 = n . p_W_C - d_m, p_W_C = p_W + R_W_B Exp(dtheta) p_B_C.
  const double sign = n.dot(T_W_C.p) - model.plane.d_m >= 0.0 ? 1.0 : -1.0;
  J.block<1, 3>(0, kCrlbP) = sign * n.transpose();
  J.block<1, 3>(0, kCrlbTheta) = -sign * n.transpose() * R_W_B * Skew(model.T_B_C.p);
  J.block<1, 2>(0, kPlane) = sign * T_W_C.p.transpose() * B;
  J(0, kPlane + 2) = -sign;

  // v_o = n . v_W.
  J.block<1, 3>(1, kCrlbV) = n.transpose();
  J.block<1, 2>(1, kPlane) = v_W.transpose() * B;

  // n_C = R_B_C^T Exp(-dtheta) R_W_B^T n: dn_C = R_B_C^T [u]x dtheta, u = R_W_B^T n;
  // with the plane: dn_C = R_W_C^T B delta12.
  const Eigen::Vector3d n_C = T_W_C.q.conjugate() * n;
  Eigen::Matrix<double, 3, 5> dn_C = Eigen::Matrix<double, 3, 5>::Zero();  // [dtheta, delta12]
  dn_C.leftCols<3>() = R_B_C.transpose() * Skew(R_W_B.transpose() * n);
  dn_C.rightCols<2>() = T_W_C.R().transpose() * B;
  const double yz2 = n_C.y() * n_C.y() + n_C.z() * n_C.z();
  const Eigen::Matrix<double, 1, 5> d_roll =
      (n_C.z() * dn_C.row(1) - n_C.y() * dn_C.row(2)) / std::max(yz2, 1e-300);
  const Eigen::Matrix<double, 1, 5> d_pitch =
      -dn_C.row(0) / std::sqrt(std::max(1.0 - n_C.x() * n_C.x(), 1e-300));
  J.block<1, 3>(2, kCrlbTheta) = d_roll.leftCols<3>();
  J.block<1, 2>(2, kPlane) = d_roll.rightCols<2>();
  J.block<1, 3>(3, kCrlbTheta) = d_pitch.leftCols<3>();
  J.block<1, 2>(3, kPlane) = d_pitch.rightCols<2>();

  // alpha = acos(c), c = -n . g / |g|: dalpha = -dc / sin(alpha).
  const double c = -n.dot(GravityW()) / kGravityMagnitude;
  const double sin_alpha = std::sqrt(std::max(1.0 - c * c, 0.0));
  if (sin_alpha > 1e-9)
    J.block<1, 2>(4, kPlane) = (GravityW().transpose() * B / kGravityMagnitude) / sin_alpha;
  return J;
}

Matrix15d LaserGaugePriorInformation(const Eigen::Matrix3d& R_W_B, const Eigen::Vector3d& n_W) {
  Matrix15d info = Matrix15d::Zero();
  const Eigen::Vector3d n = n_W.normalized();
  const Eigen::Vector3d yaw_axis_B = R_W_B.transpose() * Eigen::Vector3d::UnitZ();
  Eigen::Matrix3d L_theta = Eigen::Matrix3d::Zero();
  L_theta.row(0) = kGaugeSqrtInformation * yaw_axis_B.transpose();
  Eigen::Vector3d about_normal_B = R_W_B.transpose() * n;
  about_normal_B -= about_normal_B.dot(yaw_axis_B) * yaw_axis_B;
  if (about_normal_B.norm() > std::sin(kDistinctNormalDeg * kDeg))
    L_theta.row(1) = kGaugeSqrtInformation * about_normal_B.normalized().transpose();
  info.block<3, 3>(kCrlbTheta, kCrlbTheta) = L_theta.transpose() * L_theta;
  info.block<3, 3>(kCrlbP, kCrlbP) =
      kGaugeSqrtInformation * kGaugeSqrtInformation * Eigen::Matrix3d::Identity();
  const Eigen::Matrix3d L_v =
      (Eigen::Matrix3d::Identity() - n * n.transpose()) / kInPlaneVelocitySigmaMS;
  info.block<3, 3>(kCrlbV, kCrlbV) = L_v.transpose() * L_v;
  return info;
}

std::optional<LaserSpotModel> LaserSpotModelFor(const Dataset& dataset,
                                                const std::optional<LaserBeam>& beam,
                                                double sigma_rad, const Pose& T_W_B0,
                                                std::string* why) {
  if (!beam) {
    *why = "laser spot without the laser's parameters in map.yaml";
    return std::nullopt;
  }
  if (!dataset.map.plane) {
    *why = "laser spot without the true plane (map.yaml plane)";
    return std::nullopt;
  }
  if (dataset.cameras.empty()) {
    *why = "no camera";
    return std::nullopt;
  }
  const double L = beam->origin_C.x();
  if (!(L > 0.0) || beam->origin_C.tail<2>().norm() > 1e-12 ||
      (beam->direction_C.normalized() - Eigen::Vector3d::UnitZ()).norm() > 1e-12) {
    *why =
        "the laser is not the simulator's (at (L, 0, 0) along z of cam0, "
        "datasets/scenarios/laser_plane.h): no model of its spot";
    return std::nullopt;
  }
  if (!(sigma_rad > 0.0)) {
    *why = "no laser noise";
    return std::nullopt;
  }
  LaserSpotModel model;
  model.L_m = L;
  model.sigma_rad = sigma_rad;
  model.T_B_C = dataset.cameras.front().T_B_C;
  const double norm = dataset.map.plane->n_W.norm();
  if (!(norm > 0.0)) {
    *why = "the true plane has no normal";
    return std::nullopt;
  }
  model.plane = Plane{dataset.map.plane->n_W / norm, dataset.map.plane->d_m / norm};
  // The normal towards the vehicle (the truth quantities' and the smoother's convention).
  const Eigen::Vector3d p_W_C0 = (T_W_B0 * model.T_B_C).p;
  if (model.plane.n_W.dot(p_W_C0) - model.plane.d_m < 0.0) {
    model.plane.n_W = -model.plane.n_W;
    model.plane.d_m = -model.plane.d_m;
  }
  return model;
}

Matrix5d LaserQuantityCovariance(const Eigen::Matrix<double, 5, 18>& J, const Eigen::MatrixXd& Sxx,
                                 const Eigen::MatrixXd& Sxd, const Eigen::MatrixXd& Sdd) {
  const Eigen::Matrix<double, 5, 15> Jx = J.leftCols<15>();
  const Eigen::Matrix<double, 5, 3> Jd = J.rightCols<3>();
  const Matrix5d C = Jx * Sxx * Jx.transpose() + Jx * Sxd * Jd.transpose() +
                     Jd * Sxd.transpose() * Jx.transpose() + Jd * Sdd * Jd.transpose();
  return 0.5 * (C + C.transpose());
}

}  // namespace mavloc
