#include "datasets/scenarios/stereo_obstacles.h"

#include <fmt/format.h>
#include <unistd.h>

#include <array>
#include <cmath>
#include <filesystem>

#include "core/atomic_file.h"
#include "core/errors.h"
#include "core/image_codec.h"
#include "core/interrupt.h"
#include "core/progress.h"
#include "core/random.h"
#include "core/rotation.h"
#include "datasets/rendering/stereo_room_renderer.h"
#include "datasets/simulation/camera_simulator.h"
#include "datasets/simulation/imu_simulator.h"
#include "datasets/simulation/spline_trajectory.h"

namespace mavloc {
namespace {

constexpr double kObstacleImuRateHz = 200.0;
constexpr double kBaselineM = 0.05;
constexpr double kFocalPx = 645.0;
constexpr TimeNs kPathSampleNs = kNsPerSecond / 100;  // path sampling for obstacle placement

struct ObstacleSettings {
  double camera_rate_hz = 5.0;
  double image_noise_grey = 2.0;
  std::string image_dir;
  bool imu_noise = true;
  double cam1_misalignment_deg = 0.5;
};

// An obstacle before placement: where along the path (where the path crosses x_W = path_x_m), on
// which side
// (+1 left, -1 right), and how close its surface passes the trajectory.
struct ObstacleSpec {
  double path_x_m;
  int side;
  double gap_m;
  ObstacleShape shape;
  std::array<double, 3> box_size_m;  // box
  double yaw_offset_rad;             // box, relative to the path heading
  double radius_m;                   // cylinder
  double height_m;                   // cylinder
  const char* what;
};

ObstacleSpec Cylinder(double x_m, int side, double gap_m, double radius_m, double height_m,
                      const char* what) {
  return {x_m, side, gap_m, ObstacleShape::kCylinder, {0, 0, 0}, 0.0, radius_m, height_m, what};
}

ObstacleSpec Box(double x_m, int side, double gap_m, std::array<double, 3> size_m,
                 double yaw_offset_rad, const char* what) {
  return {x_m, side, gap_m, ObstacleShape::kBox, size_m, yaw_offset_rad, 0.0, 0.0, what};
}

// Spread along the path from x = 1.9 m to 5.9 m, so that none is beside the vehicle while it rests
// at the start (x = 0) or at the end (x = 7.5 m).
const std::vector<ObstacleSpec>& ObstacleSpecs() {
  static const std::vector<ObstacleSpec> kSpecs = {
      Cylinder(1.9, +1, 0.45, 0.20, 1.8, "cylinder r 0.20 m, h 1.8 m (person)"),
      Box(2.7, -1, 1.10, {0.5, 0.5, 1.0}, 0.2, "box 0.5 x 0.5 x 1.0 m"),
      Box(3.5, +1, 0.55, {0.4, 0.6, 1.6}, 0.3, "box 0.4 x 0.6 x 1.6 m"),
      Cylinder(4.3, -1, 0.60, 0.15, 2.2, "cylinder r 0.15 m, h 2.2 m (plant)"),
      Cylinder(5.1, +1, 1.30, 0.25, 1.2, "cylinder r 0.25 m, h 1.2 m"),
      Box(5.9, -1, 0.50, {0.6, 0.4, 1.4}, -0.2, "box 0.6 x 0.4 x 1.4 m (cardboard)"),
  };
  return kSpecs;
}

ObstacleSettings ReadObstacleSettings(const ScenarioOptions& options) {
  ObstacleSettings s;
  s.camera_rate_hz = options.GetDouble("camera_rate_hz", s.camera_rate_hz);
  s.image_noise_grey = options.GetDouble("image_noise_grey", s.image_noise_grey);
  s.image_dir = options.GetString("image_dir", options.image_dir);
  s.imu_noise = options.GetBool("imu_noise", s.imu_noise);
  s.cam1_misalignment_deg = options.GetDouble("cam1_misalignment_deg", s.cam1_misalignment_deg);
  if (!(s.camera_rate_hz > 0.0 && s.camera_rate_hz <= 60.0))
    throw InputError("scenario stereo-obstacles: camera_rate_hz must be in (0, 60]");
  if (!(s.image_noise_grey >= 0.0 && s.image_noise_grey <= 50.0))
    throw InputError("scenario stereo-obstacles: image_noise_grey must be in [0, 50]");
  if (!(std::abs(s.cam1_misalignment_deg) <= 5.0))
    throw InputError("scenario stereo-obstacles: cam1_misalignment_deg must be in [-5, 5]");
  return s;
}

double MinimumDistance(const RoomObstacle& obstacle, const std::vector<Eigen::Vector3d>& path_W) {
  double best = std::numeric_limits<double>::infinity();
  for (const auto& p : path_W) best = std::min(best, DistanceToObstacle(obstacle, p));
  return best;
}

// Places an obstacle beside the path so that its minimum distance to the sampled path is the gap:
// bisection on the offset of its centre along the path's horizontal normal where the path first
// crosses x_W = path_x_m (path_W is sampled every kPathSampleNs from the trajectory's start).
RoomObstacle PlaceObstacle(const ObstacleSpec& spec, const Trajectory& trajectory,
                           const std::vector<Eigen::Vector3d>& path_W) {
  size_t i = 0;
  while (i + 1 < path_W.size() && path_W[i].x() < spec.path_x_m) ++i;
  const TimeNs t = trajectory.start_ns() + static_cast<TimeNs>(i) * kPathSampleNs;
  const TrajectorySample sample = trajectory.At(t);
  const double heading = std::atan2(sample.v_W.y(), sample.v_W.x());
  const Eigen::Vector3d left_W(-std::sin(heading), std::cos(heading), 0.0);
  RoomObstacle obstacle;
  obstacle.shape = spec.shape;
  if (spec.shape == ObstacleShape::kBox) {
    obstacle.box_size_m =
        Eigen::Vector3d(spec.box_size_m[0], spec.box_size_m[1], spec.box_size_m[2]);
    obstacle.yaw_rad = heading + spec.yaw_offset_rad;
  } else {
    obstacle.radius_m = spec.radius_m;
    obstacle.height_m = spec.height_m;
  }
  const double height = spec.shape == ObstacleShape::kBox ? spec.box_size_m[2] : spec.height_m;
  auto at_offset = [&](double offset) {
    RoomObstacle o = obstacle;
    o.center_W = Eigen::Vector3d(sample.p_W.x(), sample.p_W.y(), 0.0) + spec.side * offset * left_W;
    o.center_W.z() = 0.5 * height;  // standing on the floor
    return o;
  };
  double lo = 0.0, hi = 4.0;
  for (int iteration = 0; iteration < 50; ++iteration) {
    const double mid = 0.5 * (lo + hi);
    (MinimumDistance(at_offset(mid), path_W) < spec.gap_m ? lo : hi) = mid;
  }
  return at_offset(hi);
}

void RenderFrames(const Dataset& d, const StereoRoom& room, const ObstacleSettings& settings,
                  uint64_t seed, uint64_t camera_seed, const std::vector<Pose>& T_W_B_frames,
                  std::vector<CameraSensor>* cameras) {
  std::string folder = settings.image_dir;
  if (folder.empty()) {
    folder =
        (std::filesystem::temp_directory_path() /
         fmt::format("mavloc_render_stereo-obstacles_{}_{}", seed, static_cast<long>(getpid())))
            .string();
  }
  StereoRenderOptions render_options;
  render_options.noise_sigma_grey = settings.image_noise_grey;
  for (size_t c = 0; c < cameras->size(); ++c) {
    CameraSensor& camera = (*cameras)[c];
    const std::filesystem::path camera_folder = std::filesystem::path(folder) / camera.name;
    std::error_code error;
    CreateOutputDirectories(camera_folder, error);
    if (error)
      throw InputError(camera_folder.string(), 0, "image_dir",
                       "cannot create folder: " + error.message());
    const StereoRoomRenderer renderer(camera.model, room, render_options);
    for (size_t i = 0; i < camera.frames.size(); ++i) {
      CameraFrame& frame = camera.frames[i];
      const cv::Mat image =
          renderer.Render(T_W_B_frames[i] * camera.T_B_C, SplitMix64(camera_seed + 2 * i + c));
      frame.image_path = (camera_folder / fmt::format("{}.png", frame.t_ns)).string();
      WriteFileAtomically(frame.image_path, EncodePng(image));
      if (i % 50 == 0)
        ReportProgress("render", fmt::format("{} {} frame {}/{}", d.scenario, camera.name, i + 1,
                                             camera.frames.size()));
    }
  }
}

}  // namespace

CameraSensor StereoObstaclesCamera(int index, double rate_hz, double cam1_misalignment_deg) {
  CameraSensor camera;
  camera.name = index == 0 ? "cam0" : "cam1";
  camera.rate_hz = rate_hz;
  camera.model = CameraModel(640, 480, Eigen::Vector4d(kFocalPx, kFocalPx, 319.5, 239.5));
  // Forward-looking: z_C = x_B (forward), x_C = -y_B (image right = vehicle right), y_C = -z_B.
  Eigen::Matrix3d R_B_C;
  R_B_C << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  // cam0 on the left (+y_B), cam1 a baseline to its right, toed in about its own y axis.
  if (index == 0) {
    camera.T_B_C = Pose(R_B_C, Eigen::Vector3d(0.08, 0.5 * kBaselineM, 0.0));
  } else {
    const Eigen::Matrix3d toe_in = Ry(-cam1_misalignment_deg * M_PI / 180.0);
    camera.T_B_C =
        Pose(Eigen::Matrix3d(R_B_C * toe_in), Eigen::Vector3d(0.08, -0.5 * kBaselineM, 0.0));
  }
  return camera;
}

Dataset GenerateStereoObstacles(const ScenarioOptions& options) {
  const std::string name = "stereo-obstacles";
  const double duration_s = options.duration_s.value_or(10.0);
  // The spline rests about 1.5 s at each end and needs 2 s of waypoints in between.
  if (!(duration_s >= 5.0 && duration_s <= 600.0))
    throw InputError("scenario " + name + ": --duration must be in [5, 600] s");
  const ObstacleSettings settings = ReadObstacleSettings(options);
  const SimulationSeeds seeds = SimulationSeeds::FromMaster(options.seed);

  // S-shaped path along x, heading along the direction of travel. The spline holds the vehicle at
  // rest around the first and last waypoints, which lengthens the trajectory: the waypoint span is
  // shortened by that extra time so that the dataset lasts duration_s.
  const std::vector<Eigen::Vector3d> points = {
      {0.0, 0.0, 1.2}, {2.5, 0.25, 1.25}, {5.0, -0.25, 1.15}, {7.5, 0.0, 1.2}};
  auto make_trajectory = [&](double span_s) {
    std::vector<Waypoint> waypoints;
    for (size_t i = 0; i < points.size(); ++i) {
      Waypoint w;
      w.t_s = span_s * static_cast<double>(i) / (points.size() - 1);
      w.p_W = points[i];
      const Eigen::Vector3d direction =
          points[std::min(i + 1, points.size() - 1)] - points[i > 0 ? i - 1 : 0];
      w.yaw_rad = std::atan2(direction.y(), direction.x());
      waypoints.push_back(w);
    }
    return SplineTrajectory::FromWaypoints(kScenarioStartNs, waypoints, AttitudeMode::kQuadrotor);
  };
  const double rest_s =
      NsToSeconds(make_trajectory(duration_s)->end_ns() - kScenarioStartNs) - duration_s;
  const auto trajectory = make_trajectory(std::max(2.0, duration_s - rest_s));

  Dataset d;
  d.name = name;
  d.scenario = name;

  ImuSimulationOptions imu_options;
  imu_options.rate_hz = kObstacleImuRateHz;
  if (settings.imu_noise) {
    imu_options.noise = {3.3937e-4, 3.8785e-5, 4.0e-3, 6.0e-3};  // ADIS16448 (RotorS)
    imu_options.bias_random_walk = true;
  }
  AddSimulatedImu(*trajectory, imu_options, seeds.imu, &d);

  // The room, with each obstacle placed at its gap from the true path (sampled at 100 Hz).
  std::vector<Eigen::Vector3d> path_W;
  for (TimeNs t = trajectory->start_ns(); t <= trajectory->end_ns(); t += kPathSampleNs)
    path_W.push_back(trajectory->At(t).p_W);
  StereoRoom room;
  room.min_W = Eigen::Vector3d(-1.5, -2.5, 0.0);
  room.max_W = Eigen::Vector3d(11.0, 2.5, 3.0);
  room.texture_seed = SplitMix64(seeds.other) % 1000000;
  for (const ObstacleSpec& spec : ObstacleSpecs())
    room.obstacles.push_back(PlaceObstacle(spec, *trajectory, path_W));
  StereoRoomToMapParameters(room, &d.map.parameters);

  std::vector<CameraSensor> cameras = {
      StereoObstaclesCamera(0, settings.camera_rate_hz, settings.cam1_misalignment_deg),
      StereoObstaclesCamera(1, settings.camera_rate_hz, settings.cam1_misalignment_deg)};
  std::vector<Pose> T_W_B_frames;
  for (const TimeNs t : CameraFrameTimes(*trajectory, settings.camera_rate_hz)) {
    for (auto& camera : cameras) camera.frames.push_back({t, ""});
    T_W_B_frames.push_back(trajectory->At(t).T_W_B());
  }
  if (options.render_images)
    RenderFrames(d, room, settings, options.seed, seeds.camera, T_W_B_frames, &cameras);
  d.cameras = std::move(cameras);

  std::string obstacles;
  for (size_t i = 0; i < ObstacleSpecs().size(); ++i) {
    const ObstacleSpec& spec = ObstacleSpecs()[i];
    obstacles += fmt::format("{}{}: {} {}, gap {} m", i == 0 ? "" : "; ", i, spec.what,
                             spec.side > 0 ? "left" : "right", spec.gap_m);
  }
  d.scenario_info = {
      {"seed", std::to_string(options.seed)},
      {"duration_s", fmt::format("{}", NsToSeconds(trajectory->end_ns() - trajectory->start_ns()))},
      {"imu_rate_hz", fmt::format("{}", kObstacleImuRateHz)},
      {"imu_noise", settings.imu_noise ? "ADIS16448 densities, bias random walk" : "none"},
      {"camera_rate_hz", fmt::format("{}", settings.camera_rate_hz)},
      {"stereo", fmt::format("640x480, f {} px, baseline {} m, cam1 toe-in {} deg", kFocalPx,
                             kBaselineM, settings.cam1_misalignment_deg)},
      {"path", "S-curve (0,0,1.2) -> (2.5,0.25,1.25) -> (5,-0.25,1.15) -> (7.5,0,1.2) m"},
      {"obstacles", obstacles},
      {"obstacle_truth",
       "map.yaml parameters obstacle_* (datasets/rendering/stereo_room_renderer.h)"},
      {"images", options.render_images
                     ? fmt::format("ray cast, noise {} grey levels", settings.image_noise_grey)
                     : "none (simulate with --render)"},
  };
  return d;
}

}  // namespace mavloc
