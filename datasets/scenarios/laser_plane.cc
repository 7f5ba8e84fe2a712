#include "datasets/scenarios/laser_plane.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "core/errors.h"
#include "core/random.h"
#include "core/rotation.h"
#include "datasets/simulation/camera_simulator.h"
#include "datasets/simulation/imu_simulator.h"
#include "datasets/simulation/random_motion_trajectory.h"

namespace mavloc {

namespace {

constexpr const char* kLaserPlane = "laser-plane";

}  // namespace

std::vector<LaserObservation> SimulateLaserSpots(const std::function<Pose(TimeNs)>& T_W_C_at,
                                                 const std::vector<TimeNs>& times, double L_m,
                                                 const Plane& plane, double bearing_noise_rad,
                                                 uint64_t camera_seed, int* missed) {
  Rng rng(camera_seed);
  std::vector<LaserObservation> spots;
  *missed = 0;
  for (const TimeNs t : times) {
    // Draw the noise first so that the stream depends on the seed only.
    const double noise_x = rng.Gaussian(0.0, bearing_noise_rad);
    const double noise_y = rng.Gaussian(0.0, bearing_noise_rad);
    const Pose T_W_C = T_W_C_at(t);
    const Eigen::Vector3d origin_W = T_W_C * Eigen::Vector3d(L_m, 0.0, 0.0);
    const Eigen::Vector3d direction_W = T_W_C.q * Eigen::Vector3d::UnitZ();
    const double along_normal = plane.n_W.dot(direction_W);
    const double range =
        std::abs(along_normal) > 1e-12 ? (plane.d_m - plane.n_W.dot(origin_W)) / along_normal : -1;
    if (range <= 0.0) {  // the beam misses the plane (the spot is at z = range > 0 in C)
      ++*missed;
      continue;
    }
    const Eigen::Vector2d xy(L_m / range, 0.0);
    LaserObservation spot;
    spot.t_ns = t;
    spot.xy = Eigen::Vector2d(std::tan(std::atan(xy.x()) + noise_x),
                              std::tan(std::atan(xy.y()) + noise_y));
    spots.push_back(spot);
  }
  return spots;
}

QuantityTable LaserTruthQuantities(const std::vector<GroundTruthState>& ground_truth,
                                   const Pose& T_B_C, const Plane& plane) {
  QuantityTable table({"d", "v_o", "roll", "pitch", "alpha"}, {"m", "m/s", "rad", "rad", "rad"});
  const double alpha =
      std::acos(std::clamp(-plane.n_W.dot(GravityW()) / kGravityMagnitude, -1.0, 1.0));
  for (const auto& row : ground_truth) {
    const Pose T_W_C = row.T_W_B * T_B_C;
    const Eigen::Vector3d n_C = T_W_C.q.conjugate() * plane.n_W;
    table.Append(row.t_ns,
                 {std::abs(plane.n_W.dot(T_W_C.p) - plane.d_m), plane.n_W.dot(row.v_W),
                  std::atan2(n_C.y(), n_C.z()), std::asin(std::clamp(-n_C.x(), -1.0, 1.0)), alpha});
  }
  return table;
}

void AddLaserParameters(double L_m, WorldMap* map) {
  map->parameters["laser_Lx"] = L_m;
  map->parameters["laser_Ly"] = 0.0;
  map->parameters["laser_theta"] = 0.0;
  map->parameters["laser_phi"] = 0.0;
}

LaserStreamsSummary AddLaserStreams(const std::function<Pose(TimeNs)>& T_W_B_at,
                                    const CameraSensor& cam0,
                                    const std::vector<TimeNs>& frame_times, double L_m,
                                    const Plane& plane, double bearing_noise_rad,
                                    uint64_t camera_seed, Dataset* d) {
  LaserStreamsSummary summary;
  d->laser = SimulateLaserSpots([&](TimeNs t) { return T_W_B_at(t) * cam0.T_B_C; }, frame_times,
                                L_m, plane, bearing_noise_rad, camera_seed, &summary.missed);
  d->truth_quantities = LaserTruthQuantities(d->ground_truth, cam0.T_B_C, plane);
  summary.min_d_m = 1e9;
  for (const double value : d->truth_quantities.Column("d")) {
    summary.min_d_m = std::min(summary.min_d_m, value);
    summary.max_d_m = std::max(summary.max_d_m, value);
  }
  return summary;
}

Dataset GenerateLaserPlane(const ScenarioOptions& options) {
  CheckRegisteredScenarioOptions(kLaserPlane, options);
  const double alpha_deg = options.GetDouble("alpha_deg", 22.5);
  const double L = options.GetDouble("L", 0.3);
  const double distance_m = options.GetDouble("distance_m", 1.0);
  const double speed_m_s = options.GetDouble("speed_m_s", 1.0);
  const double sigma_accel = options.GetDouble("sigma_accel", 1.0);
  const double sigma_rate_deg_s = options.GetDouble("sigma_rate_deg_s", 10.0);
  const double correlation_time_s = options.GetDouble("correlation_time_s", 0.5);
  const double tilt_deg = options.GetDouble("tilt_deg", 10.0);
  const double imu_rate_hz = options.GetDouble("imu_rate_hz", 100.0);
  const double gyro_sigma_deg_s = options.GetDouble("gyro_sigma_deg_s", 1.0);
  const double accel_sigma_m_s2 = options.GetDouble("accel_sigma_m_s2", 0.01);
  const bool bias = options.GetBool("bias", false);
  const double gyro_bias_deg_s = options.GetDouble("gyro_bias_deg_s", 0.03);
  const double accel_bias_m_s2 = options.GetDouble("accel_bias_m_s2", 0.03);
  const double camera_rate_hz = options.GetDouble("camera_rate_hz", 10.0);
  const double bearing_noise_deg = options.GetDouble("bearing_noise_deg", 1.0);
  const double duration_s = options.duration_s.value_or(60.0);

  const std::string prefix = fmt::format("scenario {}: ", kLaserPlane);
  if (!(alpha_deg >= 0.0 && alpha_deg < 90.0)) throw InputError(prefix + "alpha_deg in [0, 90)");
  if (!(L > 0.0 && distance_m > L)) throw InputError(prefix + "need 0 < L < distance_m");
  if (!(duration_s > 0.0 && imu_rate_hz > 0.0 && camera_rate_hz > 0.0 && correlation_time_s > 0.0))
    throw InputError(prefix + "duration, rates and correlation_time_s must be > 0");
  if (!(sigma_accel >= 0.0 && sigma_rate_deg_s >= 0.0 && gyro_sigma_deg_s >= 0.0 &&
        accel_sigma_m_s2 >= 0.0 && bearing_noise_deg >= 0.0 && tilt_deg >= 0.0 && tilt_deg < 60.0))
    throw InputError(prefix + "sigmas must be >= 0 and tilt_deg in [0, 60)");
  const SimulationSeeds seeds = SimulationSeeds::FromMaster(options.seed);

  const Eigen::Matrix3d R_W_P = Rx(alpha_deg * kDeg);
  Rng attitude_rng(seeds.other);
  const double tilt_roll = attitude_rng.Uniform(-tilt_deg, tilt_deg) * kDeg;
  const double tilt_pitch = attitude_rng.Uniform(-tilt_deg, tilt_deg) * kDeg;
  const double yaw = attitude_rng.Uniform(-180.0, 180.0) * kDeg;
  // Looking at the plane: camera z along -n (Rx(pi)), then the random tilt and yaw about n.
  const Eigen::Matrix3d R_P_B_ref = Rz(yaw) * Rx(M_PI) * Rx(tilt_roll) * Ry(tilt_pitch);

  RandomMotionOptions motion;
  motion.start_ns = kScenarioStartNs;
  motion.duration_s = duration_s;
  motion.q_W_P = Eigen::Quaterniond(R_W_P);
  motion.p0_P = Eigen::Vector3d(0.0, 0.0, distance_m);
  motion.v0_P = Eigen::Vector3d(speed_m_s, 0.0, 0.0);
  motion.q_P_B_ref = Eigen::Quaterniond(R_P_B_ref);
  motion.sigma_accel_m_s2 = sigma_accel;
  motion.sigma_rate_rad_s = sigma_rate_deg_s * kDeg;
  motion.correlation_time_s = correlation_time_s;
  const RandomMotionTrajectory trajectory(motion, seeds.motion);

  Dataset d;
  d.scenario = kLaserPlane;
  d.name = kLaserPlane;
  ImuSimulationOptions imu_options;
  imu_options.rate_hz = imu_rate_hz;
  imu_options.noise =
      NoiseFromPerSampleSigmas(gyro_sigma_deg_s * kDeg, accel_sigma_m_s2, imu_rate_hz);
  if (bias) {
    imu_options.initial_gyro_bias = Eigen::Vector3d::Constant(gyro_bias_deg_s * kDeg);
    imu_options.initial_accel_bias = Eigen::Vector3d::Constant(accel_bias_m_s2);
  }
  AddSimulatedImu(trajectory, imu_options, seeds.imu, &d);

  CameraSensor cam0;
  cam0.name = "cam0";
  cam0.rate_hz = camera_rate_hz;
  cam0.model = CameraModel(752, 480, Eigen::Vector4d(300.0, 300.0, 376.0, 240.0));
  cam0.T_B_C = Pose();  // the vehicle frame is the camera frame (section 2)
  const std::vector<TimeNs> frame_times = CameraFrameTimes(trajectory, camera_rate_hz);
  for (const TimeNs t : frame_times) cam0.frames.push_back({t, ""});

  // The plane through the origin; its normal already points to the vehicle's side.
  const Plane plane{R_W_P.col(2), 0.0};
  d.map.plane = plane;
  AddLaserParameters(L, &d.map);
  d.map.parameters["plane_alpha_rad"] = alpha_deg * kDeg;
  const LaserStreamsSummary laser =
      AddLaserStreams([&](TimeNs t) { return trajectory.At(t).T_W_B(); }, cam0, frame_times, L,
                      plane, bearing_noise_deg * kDeg, seeds.camera, &d);
  d.cameras.push_back(cam0);
  d.scenario_info = {
      {"scenario", kLaserPlane},
      {"seed", std::to_string(options.seed)},
      {"paper", "Martinelli & Troiani, INRIA RR-7906, 2012, section 5.1"},
      {"duration_s", fmt::format("{}", duration_s)},
      {"plane", fmt::format("through the origin, alpha = {} deg to the horizontal (normal "
                            "Rx(alpha) e_z)",
                            alpha_deg)},
      {"laser", fmt::format("L = {} m: at [L, 0, 0] along z of cam0 (cam0 = chosen frame)", L)},
      {"motion",
       fmt::format("start {} m from the plane at {} m/s along it; OU accelerations sigma {} m/s^2 "
                   "and body rates sigma {} deg/s (correlation {} s) at 100 Hz, height pulled "
                   "back to the start distance, lateral velocity and attitude mean-reverting",
                   distance_m, speed_m_s, sigma_accel, sigma_rate_deg_s, correlation_time_s)},
      {"attitude_reference", fmt::format("camera looking at the plane, roll {:.2f} deg, pitch "
                                         "{:.2f} deg, yaw {:.2f} deg about the normal",
                                         tilt_roll / kDeg, tilt_pitch / kDeg, yaw / kDeg)},
      {"distance_range_m", fmt::format("{:.3f} .. {:.3f}", laser.min_d_m, laser.max_d_m)},
      {"imu_rate_hz", fmt::format("{}", imu_rate_hz)},
      {"gyro_sigma_deg_s", fmt::format("{} (per sample)", gyro_sigma_deg_s)},
      {"accel_sigma_m_s2", fmt::format("{} (per sample)", accel_sigma_m_s2)},
      {"bias", bias ? fmt::format("gyro {} deg/s, accel {} m/s^2 on every axis (constant)",
                                  gyro_bias_deg_s, accel_bias_m_s2)
                    : "none"},
      {"camera_rate_hz", fmt::format("{}", camera_rate_hz)},
      {"bearing_noise_deg", fmt::format("{} per bearing angle", bearing_noise_deg)},
      {"spots_missed", std::to_string(laser.missed)},
  };
  return d;
}

}  // namespace mavloc
