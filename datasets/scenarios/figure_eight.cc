#include "datasets/scenarios/figure_eight.h"

#include <fmt/format.h>

#include <cmath>

#include "core/errors.h"
#include "core/random.h"
#include "core/rotation.h"
#include "datasets/simulation/camera_simulator.h"
#include "datasets/simulation/imu_simulator.h"
#include "datasets/simulation/spline_trajectory.h"

namespace mavloc {

namespace {

std::map<int, Eigen::Vector3d> RoomLandmarks(int count, Rng& rng) {
  // Walls at x, y = +-4 m, 0..3 m high, and the floor z = 0.
  std::map<int, Eigen::Vector3d> landmarks;
  for (int id = 0; id < count; ++id) {
    const int face = id % 5;
    const double a = rng.Uniform(-4.0, 4.0), h = rng.Uniform(0.0, 3.0);
    Eigen::Vector3d p;
    switch (face) {
      case 0:
        p = {4.0, a, h};
        break;
      case 1:
        p = {-4.0, a, h};
        break;
      case 2:
        p = {a, 4.0, h};
        break;
      case 3:
        p = {a, -4.0, h};
        break;
      default:
        p = {a, rng.Uniform(-4.0, 4.0), 0.0};
        break;
    }
    landmarks[id] = p;
  }
  return landmarks;
}

}  // namespace

Dataset GenerateFigureEight(const ScenarioOptions& options) {
  const double duration_s = options.duration_s.value_or(20.0);
  if (!(duration_s >= 2.0))
    throw InputError("scenario mav-figure-eight: --duration must be >= 2 s");
  const double imu_rate_hz = options.GetDouble("imu_rate_hz", 200.0);
  const double camera_rate_hz = options.GetDouble("camera_rate_hz", 20.0);
  const double pixel_noise_px = options.GetDouble("pixel_noise_px", 1.0);
  const int num_landmarks = options.GetInt("landmarks", 200);
  const bool imu_noise = options.GetBool("imu_noise", true);
  const bool bias = options.GetBool("bias", true);
  if (!(imu_rate_hz > 0 && camera_rate_hz > 0 && pixel_noise_px >= 0 && num_landmarks >= 0))
    throw InputError("scenario mav-figure-eight: rates must be > 0, noise and landmarks >= 0");
  const SimulationSeeds seeds = SimulationSeeds::FromMaster(options.seed);

  // Figure-eight p(t) = (A sin(w t), B sin(2 w t), h + c sin(w t)), one loop per 10 s, with a
  // random phase and size drawn from the motion seed; yaw follows the direction of travel.
  Rng motion(seeds.motion);
  const double A = motion.Uniform(1.5, 2.5), B = motion.Uniform(0.8, 1.5);
  const double h = motion.Uniform(1.2, 1.8), c = motion.Uniform(0.0, 0.3);
  const double w = 2.0 * M_PI / 10.0;
  std::vector<Waypoint> waypoints;
  const double step_s = 0.25;
  for (double t = 0.0; t <= duration_s + 1e-9; t += step_s) {
    Waypoint wp;
    wp.t_s = t;
    wp.p_W = {A * std::sin(w * t), B * std::sin(2.0 * w * t), h + c * std::sin(w * t)};
    const Eigen::Vector2d v(A * w * std::cos(w * t), 2.0 * B * w * std::cos(2.0 * w * t));
    wp.yaw_rad = std::atan2(v.y(), v.x());
    waypoints.push_back(wp);
  }
  const auto trajectory = SplineTrajectory::FromWaypoints(kScenarioStartNs, waypoints,
                                                          AttitudeMode::kQuadrotor, step_s);

  Dataset d;
  d.scenario = "mav-figure-eight";
  d.name = "mav-figure-eight";

  const ImuSimulationOptions imu_options =
      EurocLikeImuOptions(imu_rate_hz, imu_noise, bias, seeds.other);
  AddSimulatedImu(*trajectory, imu_options, seeds.imu, &d);

  CameraSensor cam0;
  cam0.name = "cam0";
  cam0.rate_hz = camera_rate_hz;
  cam0.model = EurocCam0Model();
  // Camera looks forward along x_B, tilted 20 deg down: z_C = cos20 x_B - sin20 z_B.
  const double tilt = 20.0 * M_PI / 180.0;
  Eigen::Matrix3d R_B_C;
  R_B_C.col(2) = Eigen::Vector3d(std::cos(tilt), 0.0, -std::sin(tilt));  // optical axis
  R_B_C.col(0) = Eigen::Vector3d(0.0, -1.0, 0.0);                        // image x: right
  R_B_C.col(1) = R_B_C.col(2).cross(R_B_C.col(0));                       // image y: down
  cam0.T_B_C = Pose(R_B_C, Eigen::Vector3d(0.05, 0.0, -0.02));

  Rng world(SplitMix64(seeds.other + 17));
  d.map.landmarks_W = RoomLandmarks(num_landmarks, world);
  CameraSimulationOptions camera_options;
  camera_options.rate_hz = camera_rate_hz;
  camera_options.noise_kind = pixel_noise_px > 0 ? CameraNoiseKind::kPixel : CameraNoiseKind::kNone;
  camera_options.noise_sigma = pixel_noise_px;
  for (const auto& obs :
       ObservePoints(*trajectory, cam0, d.map.landmarks_W, camera_options, seeds.camera))
    d.features.push_back({obs.t_ns, obs.landmark_id, obs.xy});
  for (const TimeNs t : CameraFrameTimes(*trajectory, camera_rate_hz))
    cam0.frames.push_back({t, ""});
  d.cameras.push_back(cam0);

  d.scenario_info = {
      {"seed", std::to_string(options.seed)},
      {"duration_s", fmt::format("{}", NsToSeconds(trajectory->end_ns() - trajectory->start_ns()))},
      {"imu_rate_hz", fmt::format("{}", imu_rate_hz)},
      {"camera_rate_hz", fmt::format("{}", camera_rate_hz)},
      {"pixel_noise_px", fmt::format("{}", pixel_noise_px)},
      {"landmarks", std::to_string(num_landmarks)},
      {"imu_noise", imu_noise ? "EuRoC ADIS16448 densities" : "none"},
      {"bias", bias ? "random initial bias, random walk" : "none"},
      {"figure_eight",
       fmt::format("A={:.3f} m, B={:.3f} m, h={:.3f} m, c={:.3f} m, period 10 s", A, B, h, c)},
  };
  return d;
}

}  // namespace mavloc
