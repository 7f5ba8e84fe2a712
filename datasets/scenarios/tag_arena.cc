#include "datasets/scenarios/tag_arena.h"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>

#include "core/atomic_file.h"
#include "core/errors.h"
#include "core/image_codec.h"
#include "core/interrupt.h"
#include "core/progress.h"
#include "core/random.h"
#include "core/rotation.h"
#include "core/tag_geometry.h"
#include "datasets/simulation/camera_simulator.h"
#include "datasets/simulation/imu_simulator.h"
#include "datasets/simulation/spline_trajectory.h"

namespace mavloc {

namespace {

constexpr double kTagSizeM = 0.20;
constexpr double kTagArenaImuRateHz = 100.0;
constexpr double kCameraRateHz = 10.0;

struct ArenaSettings {
  double processing_delay_s = 0.05;
  double corner_noise_px = 0.3;
  bool imu_noise = true;
  double camera_offset_s = 0.0;
  bool render = false;
  bool projected_tags = true;
  double exposure_s = 0.0;
  int blur_samples = 5;
  TagRenderOptions render_options;
  std::string image_dir;
};

ArenaSettings ReadSettings(const ScenarioOptions& options, const std::string& scenario) {
  ArenaSettings s;
  s.processing_delay_s = options.GetDouble("processing_delay_s", s.processing_delay_s);
  s.corner_noise_px = options.GetDouble("corner_noise_px", s.corner_noise_px);
  s.imu_noise = options.GetBool("imu_noise", s.imu_noise);
  s.camera_offset_s = options.GetDouble("camera_offset_s", s.camera_offset_s);
  s.render = options.render_images;
  s.projected_tags = options.GetBool("projected_tags", !s.render);
  s.exposure_s = options.GetDouble("exposure_s", 0.0);
  s.blur_samples = options.GetInt("blur_samples", 5);
  s.render_options.noise_sigma_grey = options.GetDouble("image_noise_grey", 2.0);
  s.render_options.supersampling = options.GetInt("supersampling", 4);
  s.image_dir = options.GetString("image_dir", options.image_dir);
  if (!(s.processing_delay_s >= 0.0 && s.corner_noise_px >= 0.0 && s.exposure_s >= 0.0 &&
        s.blur_samples >= 1 && s.render_options.noise_sigma_grey >= 0.0 &&
        s.render_options.supersampling >= 1 && s.camera_offset_s >= 0.0 &&
        s.camera_offset_s < 1.0 / kCameraRateHz))
    throw InputError("scenario " + scenario +
                     ": processing_delay_s, corner_noise_px, exposure_s, image_noise_grey must be "
                     ">= 0, blur_samples and supersampling >= 1, 0 <= camera_offset_s < 0.1");
  return s;
}

// A trajectory cut to [start, start + duration]: SplineTrajectory::FromWaypoints adds time at rest
// at both ends, and the scenario's duration is what the user asked for.
class TrimmedTrajectory : public Trajectory {
 public:
  TrimmedTrajectory(std::unique_ptr<Trajectory> inner, double duration_s)
      : inner_(std::move(inner)),
        end_ns_(std::min(inner_->end_ns(), inner_->start_ns() + SecondsToNs(duration_s))) {}
  TimeNs start_ns() const override { return inner_->start_ns(); }
  TimeNs end_ns() const override { return end_ns_; }
  TrajectorySample At(TimeNs t_ns) const override { return inner_->At(t_ns); }

 private:
  std::unique_ptr<Trajectory> inner_;
  TimeNs end_ns_;
};

// Renders every frame of cam0 into the image folder and points the frames at the files.
void RenderFrames(const Trajectory& trajectory, const std::map<int, TagInfo>& tags,
                  const ArenaSettings& settings, const std::string& scenario, uint64_t seed,
                  uint64_t camera_seed, CameraSensor* camera) {
  std::string folder = settings.image_dir;
  if (folder.empty()) {
    folder = (std::filesystem::temp_directory_path() /
              fmt::format("mavloc_render_{}_{}_{}", scenario, seed, static_cast<long>(getpid())))
                 .string();
  }
  std::error_code error;
  CreateOutputDirectories(folder, error);
  if (error) throw InputError(folder, 0, "image_dir", "cannot create folder: " + error.message());
  const TagRenderer renderer(camera->model, tags, settings.render_options);
  for (size_t i = 0; i < camera->frames.size(); ++i) {
    CameraFrame& frame = camera->frames[i];
    std::vector<Pose> poses;
    const int n = settings.exposure_s > 0.0 ? settings.blur_samples : 1;
    for (int k = 0; k < n; ++k) {
      // Exposure centred on the frame time, clamped to the trajectory.
      const double offset = n == 1 ? 0.0 : settings.exposure_s * ((k + 0.5) / n - 0.5);
      const TimeNs t =
          std::clamp(frame.t_ns + SecondsToNs(offset), trajectory.start_ns(), trajectory.end_ns());
      poses.push_back(trajectory.At(t).T_W_B() * camera->T_B_C);
    }
    const cv::Mat image = renderer.Render(poses, SplitMix64(camera_seed + 7919 * i));
    frame.image_path = (std::filesystem::path(folder) / fmt::format("{}.png", frame.t_ns)).string();
    WriteFileAtomically(frame.image_path, EncodePng(image));
    if (i % 50 == 0)
      ReportProgress("render",
                     fmt::format("{} frame {}/{}", scenario, i + 1, camera->frames.size()));
  }
}

Dataset BuildArena(const std::string& scenario, const ScenarioOptions& options,
                   const Trajectory& trajectory, const ArenaSettings& settings,
                   const std::string& motion_description, const std::string& filter_init) {
  const SimulationSeeds seeds = SimulationSeeds::FromMaster(options.seed);
  Dataset d;
  d.name = scenario;
  d.scenario = scenario;
  d.map.tags = TagArenaTags();

  ImuSimulationOptions imu_options;
  imu_options.rate_hz = kTagArenaImuRateHz;
  if (settings.imu_noise) {
    // RotorS ADIS16448 model (the simulator of the paper): gyro 3.3937e-4 rad/s/sqrt(Hz),
    // 3.8785e-5 rad/s^2/sqrt(Hz); accelerometer 4.0e-3 m/s^2/sqrt(Hz), 6.0e-3 m/s^3/sqrt(Hz).
    imu_options.noise = {3.3937e-4, 3.8785e-5, 4.0e-3, 6.0e-3};
    imu_options.bias_random_walk = true;
  }
  AddSimulatedImu(trajectory, imu_options, seeds.imu, &d);

  CameraSensor cam0 = TagArenaCamera(kCameraRateHz);
  for (const TimeNs t : CameraFrameTimes(trajectory, kCameraRateHz, settings.camera_offset_s))
    cam0.frames.push_back({t, ""});
  if (settings.projected_tags) {
    Rng rng(seeds.camera);
    for (const auto& frame : cam0.frames) {
      const Pose T_W_B = trajectory.At(frame.t_ns).T_W_B();
      for (auto& obs :
           ProjectTagCorners(cam0, T_W_B, d.map.tags, frame.t_ns, settings.corner_noise_px, rng))
        d.tags.push_back(obs);
    }
  }
  if (settings.render)
    RenderFrames(trajectory, d.map.tags, settings, scenario, options.seed, seeds.camera, &cam0);
  d.cameras.push_back(cam0);

  d.scenario_info = {
      {"seed", std::to_string(options.seed)},
      {"duration_s", fmt::format("{}", NsToSeconds(trajectory.end_ns() - trajectory.start_ns()))},
      {"imu_rate_hz", fmt::format("{}", kTagArenaImuRateHz)},
      {"camera_rate_hz", fmt::format("{}", kCameraRateHz)},
      {"camera_offset_s", fmt::format("{}", settings.camera_offset_s)},
      {"processing_delay_s", fmt::format("{}", settings.processing_delay_s)},
      {"imu_noise",
       settings.imu_noise ? "RotorS ADIS16448 densities, bias random walk from zero" : "none"},
      {"tags", "21 x tag36h11 (ids 0..20), 0.20 m, 7 x 3 grid 0.7 m apart on the floor"},
      {"tags0", settings.projected_tags
                    ? fmt::format("projected true corners + {} px noise", settings.corner_noise_px)
                    : "none (run mavloc detect-tags on the rendered cam0 images)"},
      {"images",
       settings.render
           ? fmt::format("rendered, noise {} grey levels, {}x{} supersampling, exposure {} s",
                         settings.render_options.noise_sigma_grey,
                         settings.render_options.supersampling,
                         settings.render_options.supersampling, settings.exposure_s)
           : "none"},
      {"motion", motion_description},
      {"filter_init", filter_init},
  };
  // The corner noise as a number, for the estimators that weight the corners by it (the smoother
  // and its Cramér–Rao bound read corner_noise_px; without it they assumed 1 px). Detected corners
  // of rendered images have no stated noise.
  if (settings.projected_tags)
    d.scenario_info["corner_noise_px"] = fmt::format("{}", settings.corner_noise_px);
  return d;
}

}  // namespace

std::map<int, TagInfo> TagArenaTags() {
  std::map<int, TagInfo> tags;
  int id = 0;
  for (int row = 0; row < 3; ++row) {
    for (int col = 0; col < 7; ++col) {
      TagInfo tag;
      tag.id = id;
      tag.size_m = kTagSizeM;
      // Each tag turned by its own quarter turns plus a few degrees ("specific orientations").
      const double yaw = (id % 4) * M_PI / 2.0 + ((id * 7) % 11 - 5) * M_PI / 180.0;
      tag.T_W_T =
          Pose(Eigen::Matrix3d(Rz(yaw)), Eigen::Vector3d(0.7 * (col - 3), 0.7 * (row - 1), 0.0));
      tags[id] = tag;
      ++id;
    }
  }
  return tags;
}

CameraSensor TagArenaCamera(double rate_hz) {
  CameraSensor cam0;
  cam0.name = "cam0";
  cam0.rate_hz = rate_hz;
  cam0.model = EurocCam0Model();
  // Down-looking: x_C = -y_B (image right = vehicle right), y_C = -x_B, z_C = -z_B.
  Eigen::Matrix3d R_B_C;
  R_B_C << 0, -1, 0, -1, 0, 0, 0, 0, -1;
  cam0.T_B_C = Pose(R_B_C, Eigen::Vector3d(0.05, 0.0, -0.03));
  return cam0;
}

std::vector<TagObservation> ProjectTagCorners(const CameraSensor& camera, const Pose& T_W_B,
                                              const std::map<int, TagInfo>& tags, TimeNs t_ns,
                                              double noise_px, Rng& rng) {
  std::vector<TagObservation> out;
  const Pose T_C_W = (T_W_B * camera.T_B_C).Inverse();
  for (const auto& [id, tag] : tags) {
    // The page (bitmap + 1 cell of paper) must be inside the image, as the detector needs it.
    TagInfo page = tag;
    page.size_m = tag.size_m * 12.0 / 8.0;
    bool visible = true;
    for (const auto& corner_W : TagCornersInWorld(page)) {
      const auto uv = camera.model.Project(T_C_W * corner_W, 0.05);
      if (!uv || !camera.model.IsInside(*uv, 2.0)) visible = false;
    }
    if (!visible) continue;
    TagObservation obs;
    obs.t_ns = t_ns;
    obs.tag_id = id;
    const auto corners_W = TagCornersInWorld(tag);
    for (int k = 0; k < 4; ++k) {
      const Eigen::Vector2d noise{rng.Gaussian(), rng.Gaussian()};
      obs.corners_px[k] = *camera.model.Project(T_C_W * corners_W[k], 0.05) + noise_px * noise;
    }
    out.push_back(obs);
  }
  return out;
}

Dataset GenerateTagArenaHover(const ScenarioOptions& options) {
  const std::string name = "tag-arena-hover";
  const double duration_s = options.duration_s.value_or(10.0);
  if (!(duration_s >= 1.0)) throw InputError("scenario " + name + ": --duration must be >= 1 s");
  const ArenaSettings settings = ReadSettings(options, name);
  const double height = options.GetDouble("hover_height_m", 1.0);
  if (!(height >= 0.4 && height <= 3.0))
    throw InputError("scenario " + name + ": hover_height_m must be in [0.4, 3]");
  Waypoint a;
  a.t_s = 0.0;
  a.p_W = Eigen::Vector3d(0.35, 0.35, height);
  a.yaw_rad = 0.3;
  Waypoint b = a;
  b.t_s = duration_s;
  const TrimmedTrajectory trajectory(
      SplineTrajectory::FromWaypoints(kScenarioStartNs, {a, b}, AttitudeMode::kQuadrotor),
      duration_s);
  return BuildArena(name, options, trajectory, settings,
                    fmt::format("stabilized hover at (0.35, 0.35, {}) m, yaw 0.3 rad", height),
                    "perturbed");
}

Dataset GenerateTagArenaDynamic(const ScenarioOptions& options) {
  const std::string name = "tag-arena-dynamic";
  const double duration_s = options.duration_s.value_or(40.0);
  if (!(duration_s >= 8.0)) throw InputError("scenario " + name + ": --duration must be >= 8 s");
  const ArenaSettings settings = ReadSettings(options, name);
  const double speed = 1.1;   // m/s along the loop
  const double height = 1.0;  // m
  std::vector<Waypoint> waypoints;
  auto add = [&](double t, double x, double y, double z, double yaw) {
    Waypoint w;
    w.t_s = t;
    w.p_W = Eigen::Vector3d(x, y, z);
    w.yaw_rad = yaw;
    waypoints.push_back(w);
  };
  add(0.0, 0.0, 0.0, 0.08, 0.0);  // on the ground: the paper's x0
  add(1.0, 0.0, 0.0, 0.08, 0.0);
  add(3.0, 0.0, 0.0, height, 0.0);  // take-off
  // The loop over the arena: at each corner the vehicle turns its heading to the next leg within
  // 0.3 m of travel (fast turns), the spline smoothing them to about 1.5 rad/s.
  const Eigen::Vector2d corners[4] = {{1.6, -0.5}, {1.6, 0.5}, {-1.6, 0.5}, {-1.6, -0.5}};
  Eigen::Vector2d p(0.0, 0.0);
  double t = 3.0;
  double yaw = 0.0;
  const double turn_s = 0.3 / speed;
  for (int leg = 0; t < duration_s - 2.0; ++leg) {
    const Eigen::Vector2d target = corners[leg % 4];
    const Eigen::Vector2d direction = (target - p).normalized();
    const double heading = yaw + WrapAngle(std::atan2(direction.y(), direction.x()) - yaw);
    const Eigen::Vector2d turned = p + 0.3 * direction;
    if (t + turn_s > duration_s - 2.0) break;
    t += turn_s;
    add(t, turned.x(), turned.y(), height, heading);
    t += ((target - turned).norm()) / speed;
    if (t > duration_s - 2.0) {
      t -= ((target - turned).norm()) / speed;
      break;
    }
    add(t, target.x(), target.y(), height, heading);
    p = target;
    yaw = heading;
  }
  const Waypoint last = waypoints.back();
  add(duration_s, last.p_W.x(), last.p_W.y(), height, last.yaw_rad);  // hold to the end
  const TrimmedTrajectory trajectory(
      SplineTrajectory::FromWaypoints(kScenarioStartNs, waypoints, AttitudeMode::kQuadrotor, 0.5),
      duration_s);
  return BuildArena(
      name, options, trajectory, settings,
      "rest at (0, 0, 0.08) m for 1 s, take-off to 1 m, loop over the arena at 1.1 m/s "
      "with fast turns",
      "zero");
}

}  // namespace mavloc
