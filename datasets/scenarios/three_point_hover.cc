#include "datasets/scenarios/three_point_hover.h"

#include <fmt/format.h>

#include <cmath>
#include <set>

#include "core/errors.h"
#include "core/random.h"
#include "core/rotation.h"
#include "datasets/simulation/camera_simulator.h"
#include "datasets/simulation/imu_simulator.h"
#include "datasets/simulation/spline_trajectory.h"

namespace mavloc {

namespace {

constexpr const char* kThreePointHover = "three-point-hover";

// The down-looking camera: x_C = x_B, y_C = -y_B, z_C = -z_B, 3 cm below the IMU.
CameraSensor DownLookingCamera(double period_s) {
  CameraSensor cam0;
  cam0.name = "cam0";
  cam0.rate_hz = 1.0 / period_s;
  cam0.model = CameraModel(752, 480, Eigen::Vector4d(260.0, 260.0, 376.0, 240.0));
  cam0.T_B_C = Pose(Eigen::Matrix3d(Eigen::Vector3d(1.0, -1.0, -1.0).asDiagonal()),
                    Eigen::Vector3d(0.0, 0.0, -0.03));
  return cam0;
}

std::string FormatVec(const Eigen::Vector3d& v) {
  return fmt::format("[{:.4f}, {:.4f}, {:.4f}]", v.x(), v.y(), v.z());
}

}  // namespace

Dataset GenerateThreePointHover(const ScenarioOptions& options) {
  CheckRegisteredScenarioOptions(kThreePointHover, options);
  const double D = options.GetDouble("D", 0.1);
  const Eigen::Vector3d P1(0.0, 0.0, 0.0);
  const Eigen::Vector3d P2(D, 0.0, 0.0);
  const Eigen::Vector3d P3 =
      D * Eigen::Vector3d(options.GetDouble("p3_x", 0.5),
                          options.GetDouble("p3_y", std::sqrt(3.0) / 2.0), 0.0);
  const Eigen::Vector3d centroid = (P1 + P2 + P3) / 3.0;
  const Eigen::Vector3d start(options.GetDouble("start_x", centroid.x()),
                              options.GetDouble("start_y", centroid.y()),
                              options.GetDouble("start_z", 0.5));
  const Eigen::Vector3d goal(options.GetDouble("goal_x", centroid.x() + 0.2),
                             options.GetDouble("goal_y", centroid.y() + 0.12),
                             options.GetDouble("goal_z", 0.4));
  const double start_yaw_deg = options.GetDouble("start_yaw_deg", 0.0);
  const double goal_yaw_deg = options.GetDouble("goal_yaw_deg", 30.0);
  const double move_start_s = options.GetDouble("move_start_s", 1.0);
  const double move_end_s = options.GetDouble("move_end_s", 8.0);
  const double duration_s = options.duration_s.value_or(20.0);
  const double imu_rate_hz = options.GetDouble("imu_rate_hz", 100.0);
  const double gyro_sigma_deg_s = options.GetDouble("gyro_sigma_deg_s", 1.0);
  const double accel_sigma_m_s2 = options.GetDouble("accel_sigma_m_s2", 0.01);
  const double gyro_bias_deg_s = options.GetDouble("gyro_bias_deg_s", 0.0);
  const double accel_bias_m_s2 = options.GetDouble("accel_bias_m_s2", 0.0);
  const double camera_period_s = options.GetDouble("camera_period_s", 0.3);
  const double bearing_noise_deg = options.GetDouble("bearing_noise_deg", 1.0);

  const std::string prefix = fmt::format("scenario {}: ", kThreePointHover);
  if (!(D > 0.0)) throw InputError(prefix + "D must be > 0");
  if (!(std::abs(P3.y()) > 1e-6 * D))
    throw InputError(prefix + "P3 must not lie on the line P1 P2 (p3_y != 0)");
  if (!(start.z() > 0.0 && goal.z() > 0.0))
    throw InputError(prefix + "start_z and goal_z must be > 0 (above the features' plane)");
  if (!(0.0 < move_start_s && move_start_s < move_end_s && move_end_s < duration_s))
    throw InputError(prefix + "need 0 < move_start_s < move_end_s < duration");
  if (!(imu_rate_hz > 0.0 && camera_period_s > 0.0))
    throw InputError(prefix + "imu_rate_hz and camera_period_s must be > 0");
  if (!(gyro_sigma_deg_s >= 0.0 && accel_sigma_m_s2 >= 0.0 && gyro_bias_deg_s >= 0.0 &&
        accel_bias_m_s2 >= 0.0 && bearing_noise_deg >= 0.0))
    throw InputError(prefix + "noise and bias sigmas must be >= 0");
  const SimulationSeeds seeds = SimulationSeeds::FromMaster(options.seed);

  // Rest, smooth move to the goal, hold.
  std::vector<Waypoint> waypoints(4);
  waypoints[0] = {0.0, start, start_yaw_deg * kDeg};
  waypoints[1] = {move_start_s, start, start_yaw_deg * kDeg};
  waypoints[2] = {move_end_s, goal, goal_yaw_deg * kDeg};
  waypoints[3] = {duration_s, goal, goal_yaw_deg * kDeg};
  const auto trajectory =
      SplineTrajectory::FromWaypoints(kScenarioStartNs, waypoints, AttitudeMode::kQuadrotor);

  Dataset d;
  d.scenario = kThreePointHover;
  d.name = kThreePointHover;

  ImuSimulationOptions imu_options;
  imu_options.rate_hz = imu_rate_hz;
  imu_options.noise =
      NoiseFromPerSampleSigmas(gyro_sigma_deg_s * kDeg, accel_sigma_m_s2, imu_rate_hz);
  Rng bias_rng(seeds.other);
  imu_options.initial_gyro_bias = bias_rng.Gaussian3(gyro_bias_deg_s * kDeg);
  imu_options.initial_accel_bias = bias_rng.Gaussian3(accel_bias_m_s2);
  imu_options.gyro_bias_sigma_rad_s = gyro_bias_deg_s * kDeg;
  imu_options.accel_bias_sigma_m_s2 = accel_bias_m_s2;
  AddSimulatedImu(*trajectory, imu_options, seeds.imu, &d);

  CameraSensor cam0 = DownLookingCamera(camera_period_s);
  d.map.landmarks_W = {{1, P1}, {2, P2}, {3, P3}};
  d.map.plane = Plane{Eigen::Vector3d::UnitZ(), 0.0};
  const double gamma1 = std::atan2(P3.y() - P1.y(), P3.x() - P1.x());
  const double gamma2 = std::atan2(P3.y() - P2.y(), P3.x() - P2.x());
  d.map.parameters = {{"D", D}, {"gamma1_rad", gamma1}, {"gamma2_rad", gamma2}};

  CameraSimulationOptions camera_options;
  camera_options.rate_hz = cam0.rate_hz;
  camera_options.noise_kind =
      bearing_noise_deg > 0.0 ? CameraNoiseKind::kAngular : CameraNoiseKind::kNone;
  camera_options.noise_sigma = std::sqrt(2.0) * bearing_noise_deg * kDeg;
  for (const auto& obs :
       ObservePoints(*trajectory, cam0, d.map.landmarks_W, camera_options, seeds.camera))
    d.features.push_back({obs.t_ns, obs.landmark_id, obs.xy});
  d.truth_quantities = QuantityTable({"gamma1", "gamma2"}, {"rad", "rad"});
  for (const TimeNs t : CameraFrameTimes(*trajectory, cam0.rate_hz)) {
    cam0.frames.push_back({t, ""});
    d.truth_quantities.Append(t, {gamma1, gamma2});
  }
  d.cameras.push_back(cam0);

  d.scenario_info = {
      {"scenario", kThreePointHover},
      {"seed", std::to_string(options.seed)},
      {"paper", "Troiani, Al Zanati, Martinelli, ECMR 2013, sect. V-A"},
      {"duration_s", fmt::format("{}", NsToSeconds(trajectory->end_ns() - trajectory->start_ns()))},
      {"features",
       fmt::format("P1 = {}, P2 = {}, P3 = {} m (D = {} m, gamma1 = {:.4f} deg, "
                   "gamma2 = {:.4f} deg)",
                   FormatVec(P1), FormatVec(P2), FormatVec(P3), D, gamma1 / kDeg, gamma2 / kDeg)},
      {"start", fmt::format("p = {} m, yaw = {} deg, at rest until t = {} s", FormatVec(start),
                            start_yaw_deg, move_start_s)},
      {"goal", fmt::format("p = {} m, yaw = {} deg, reached at t = {} s and held", FormatVec(goal),
                           goal_yaw_deg, move_end_s)},
      {"start_goal_choice",
       "the paper does not state them; chosen to keep the three features in view (start above "
       "the centroid, goal with the centroid about 30 deg off the vertical)"},
      {"attitude", "quadrotor differential flatness (thrust along z_B)"},
      {"imu_rate_hz", fmt::format("{}", imu_rate_hz)},
      {"gyro_sigma_deg_s", fmt::format("{} (per sample)", gyro_sigma_deg_s)},
      {"accel_sigma_m_s2", fmt::format("{} (per sample)", accel_sigma_m_s2)},
      {"gyro_bias", fmt::format("constant, drawn N(0, ({} deg/s)^2) per axis", gyro_bias_deg_s)},
      {"accel_bias", fmt::format("constant, drawn N(0, ({} m/s^2)^2) per axis", accel_bias_m_s2)},
      {"camera_period_s", fmt::format("{}", camera_period_s)},
      {"camera",
       "down-looking pinhole 752x480, f = 260 px, T_B_C: x_C = x_B, z_C = -z_B, "
       "3 cm below the IMU"},
      {"bearing_noise_deg",
       fmt::format("{} per bearing angle (simulator angular sigma sqrt(2) x this)",
                   bearing_noise_deg)},
  };
  return d;
}

}  // namespace mavloc
