#include "datasets/scenarios/euroc_vision.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>

#include "core/errors.h"
#include "core/random.h"
#include "datasets/io/euroc_io.h"
#include "datasets/io/tum_io.h"
#include "datasets/scenarios/euroc_laser.h"
#include "datasets/scenarios/textured_room_frames.h"

namespace mavloc {
namespace {

constexpr const char* kEurocVision = "euroc-vision";

struct EurocVisionSettings {
  std::string data;
  bool stereo = true;
  double camera_rate_hz = 20.0;
  double image_scale = 1.0;
  double texel_m = 0.004;
  double start_s = 0.0;
  bool imu_from_ground_truth = false;
};

EurocVisionSettings ReadEurocVisionSettings(const ScenarioOptions& options,
                                            const std::string& prefix) {
  EurocVisionSettings s;
  s.data = options.GetString("data", "");
  if (s.data.empty()) {
    s.data = FindDefaultEurocLaserData();
    if (s.data.empty())
      throw InputError(prefix +
                       "EuRoC V1_01_easy data not found (set data=PATH, the folder with mav0/ and "
                       "groundtruth_full_tum.txt)");
  }
  const std::string cameras = options.GetString("cameras", "stereo");
  if (cameras != "stereo" && cameras != "mono")
    throw InputError(prefix + "cameras must be stereo or mono, not '" + cameras + "'");
  s.stereo = cameras == "stereo";
  s.camera_rate_hz = options.GetDouble("camera_rate_hz", s.camera_rate_hz);
  s.image_scale = options.GetDouble("image_scale", s.image_scale);
  s.texel_m = options.GetDouble("texel_m", s.texel_m);
  s.start_s = options.GetDouble("start_s", s.start_s);
  const std::string imu = options.GetString("imu", "real");
  if (imu != "real" && imu != "from_ground_truth")
    throw InputError(prefix + "imu must be real or from_ground_truth, not '" + imu + "'");
  s.imu_from_ground_truth = imu == "from_ground_truth";
  if (!(s.camera_rate_hz >= 1.0 && s.camera_rate_hz <= 100.0))
    throw InputError(prefix + "camera_rate_hz must be in [1, 100]");
  if (!(s.image_scale >= 0.1 && s.image_scale <= 1.0))
    throw InputError(prefix + "image_scale must be in [0.1, 1]");
  if (!(s.texel_m >= 0.0005 && s.texel_m <= 0.05))
    throw InputError(prefix + "texel_m must be in [0.0005, 0.05] m");
  return s;
}

// EuRoC's camera with its image scaled: sizes rounded, intrinsics scaled so that a pixel centre
// maps to the same ray (u' + 0.5 = s (u + 0.5)); distortion acts on normalized coordinates, so it
// is unchanged.
CameraSensor ScaledEurocCamera(const CameraSensor& real, double scale, double rate_hz) {
  const CameraModel& m = real.model;
  const int width = std::max(1, static_cast<int>(std::lround(m.width() * scale)));
  const int height = std::max(1, static_cast<int>(std::lround(m.height() * scale)));
  const double sx = static_cast<double>(width) / m.width();
  const double sy = static_cast<double>(height) / m.height();
  CameraSensor camera;
  camera.name = real.name;
  camera.T_B_C = real.T_B_C;
  camera.rate_hz = rate_hz;
  camera.model = CameraModel(width, height,
                             Eigen::Vector4d(m.fu() * sx, m.fv() * sy, (m.cu() + 0.5) * sx - 0.5,
                                             (m.cv() + 0.5) * sy - 0.5),
                             m.distortion_model(), m.distortion());
  return camera;
}

std::string DescribeRoom(const TexturedRoom& room) {
  std::string text =
      fmt::format("x {:g} .. {:g}, y {:g} .. {:g}, z {:g} .. {:g} m; boxes", room.min_W.x(),
                  room.max_W.x(), room.min_W.y(), room.max_W.y(), room.min_W.z(), room.max_W.z());
  for (const TexturedBox& b : room.boxes)
    text += fmt::format(" [{:g} {:g} {:g} .. {:g} {:g} {:g}]", b.min_W.x(), b.min_W.y(),
                        b.min_W.z(), b.max_W.x(), b.max_W.y(), b.max_W.z());
  return text;
}

std::string DescribeTextures(const RoomTextures& textures, const std::vector<TexturedFace>& faces) {
  static const char* kRoomFaceNames[6] = {"wall x-", "wall x+", "wall y-",
                                          "wall y+", "floor",   "ceiling"};
  std::string text;
  for (size_t k = 0; k < 6 && k < faces.size(); ++k)
    text += fmt::format(
        "{}{}: {}", k == 0 ? "" : "; ", kRoomFaceNames[k],
        std::filesystem::path(textures.textures[faces[k].texture].path).filename().string());
  return text + "; boxes: the others in turn";
}

// The scenario's scenario.yaml entries (settings and what was generated).
std::map<std::string, std::string> EurocVisionInfo(const ScenarioOptions& options,
                                                   const EurocVisionSettings& s,
                                                   const TexturedFrameSettings& image_settings,
                                                   const Dataset& d, const TexturedRoom& room,
                                                   const std::string& images) {
  const CameraModel& m0 = d.cameras.front().model;
  return {
      {"scenario", kEurocVision},
      {"seed", std::to_string(options.seed)},
      {"data", s.data},
      {"imu", s.imu_from_ground_truth
                  ? "derived from the ground truth (no bias, no noise; rates from attitude "
                    "differences, accelerations from second differences over +-50 ms)"
                  : "real EuRoC V1_01_easy imu0 (ADIS16448, 200 Hz)"},
      {"ground_truth",
       "groundtruth_full_tum.txt = T_W_B of the IMU frame (EuRoC state_groundtruth_estimate0); v "
       "by central differences; biases constant, the ASL estimate's first row"},
      {"duration_s", fmt::format("{:.3f}", NsToSeconds(d.ground_truth.back().t_ns -
                                                       d.ground_truth.front().t_ns))},
      {"start_s", fmt::format("{}", s.start_s)},
      {"cameras",
       fmt::format(
           "{}: EuRoC's calibration and T_BS (sensor.yaml of {}), {} x {} px{}",
           s.stereo ? "cam0 + cam1" : "cam0", s.data, m0.width(), m0.height(),
           s.image_scale == 1.0 ? std::string() : fmt::format(" (scaled by {})", s.image_scale))},
      {"camera_rate_hz", fmt::format("{}", s.camera_rate_hz)},
      {"room", DescribeRoom(room)},
      {"texel_m", fmt::format("{}", s.texel_m)},
      {"textures", image_settings.textures},
      {"exposure_s", fmt::format("{} (at most {} renders per image)", image_settings.exposure_s,
                                 image_settings.blur_samples)},
      {"gain", fmt::format("{}", image_settings.render.gain)},
      {"image_noise_grey", fmt::format("{}", image_settings.render.noise_sigma_grey)},
      {"images", images},
  };
}

}  // namespace

TexturedRoom EurocVisionRoom(double texel_m) {
  TexturedRoom room;
  room.min_W = Eigen::Vector3d(-4.0, -3.7, 0.0);
  room.max_W = Eigen::Vector3d(3.6, 4.5, 4.0);
  room.texel_m = texel_m;
  auto box = [](Eigen::Vector3d lo, Eigen::Vector3d hi) { return TexturedBox{lo, hi}; };
  room.boxes = {
      box({0.63, 1.89, 0.0}, {1.13, 2.39, 0.80}),  // take-off stand under (0.88, 2.14, 0.95)
      box({-3.6, -3.3, 0.0}, {-2.8, -2.5, 1.2}),   // corners
      box({2.4, -3.3, 0.0}, {3.2, -2.5, 0.7}),     //
      box({-3.6, 3.2, 0.0}, {-2.7, 4.1, 1.6}),     //
      box({2.5, 3.5, 0.0}, {3.3, 4.3, 1.0}),       //
      box({-1.3, 0.9, 0.0}, {-0.7, 1.5, 0.45}),    // low, mid-room
  };
  return room;
}

Dataset GenerateEurocVision(const ScenarioOptions& options) {
  CheckRegisteredScenarioOptions(kEurocVision, options);
  const std::string prefix = fmt::format("scenario {}: ", kEurocVision);
  const EurocVisionSettings s = ReadEurocVisionSettings(options, prefix);
  const TexturedFrameSettings image_settings = ReadTexturedFrameSettings(options, kEurocVision);
  const std::string tum_path = s.data + "/groundtruth_full_tum.txt";
  if (!std::filesystem::is_directory(s.data + "/mav0/imu0"))
    throw InputError(s.data, 0, "data", prefix + "no mav0/imu0 folder in this EuRoC dataset");
  if (!std::filesystem::is_regular_file(tum_path))
    throw InputError(tum_path, 0, "", prefix + "missing: the full ground truth in TUM format");
  // The photographs first: a bad texture folder is refused before the flight is read.
  std::vector<std::string> skipped;
  std::shared_ptr<const RoomTextures> textures;
  if (options.render_images || image_settings.textures_given)
    textures = LoadScenarioTextures(image_settings, kEurocVision, &skipped);

  const Dataset euroc = ReadEurocDataset(s.data);
  const std::vector<StampedPose> poses = ReadTumTrajectory(tum_path);
  if (poses.size() < 10 || euroc.imu.samples.empty())
    throw InputError(tum_path, 0, "", prefix + "too few poses or no IMU samples");
  std::vector<CameraSensor> cameras;
  for (const char* name : {"cam0", "cam1"}) {
    if (!s.stereo && std::string(name) == "cam1") continue;
    const CameraSensor* real = euroc.Camera(name);
    if (real == nullptr)
      throw InputError(s.data + "/mav0/" + name + "/sensor.yaml", 0, "",
                       prefix + "missing: the camera's calibration");
    cameras.push_back(ScaledEurocCamera(*real, s.image_scale, s.camera_rate_hz));
  }

  const TimeNs t_begin =
      std::max(poses.front().t_ns, euroc.imu.samples.front().t_ns) + SecondsToNs(s.start_s);
  TimeNs t_end = std::min(poses.back().t_ns, euroc.imu.samples.back().t_ns);
  if (options.duration_s) t_end = std::min(t_end, t_begin + SecondsToNs(*options.duration_s));
  if (!(t_end > t_begin))
    throw InputError(fmt::format("{}start_s = {} s leaves nothing of the {:.1f} s flight", prefix,
                                 s.start_s, NsToSeconds(poses.back().t_ns - poses.front().t_ns)));

  Dataset d;
  d.name = kEurocVision;
  d.scenario = kEurocVision;
  d.imu = euroc.imu;
  // The IMU from its last sample at or before t_begin to its first at or after t_end: the stream
  // covers the ground truth and every frame.
  d.imu.samples.clear();
  const auto& all = euroc.imu.samples;
  auto first = std::upper_bound(all.begin(), all.end(), t_begin,
                                [](TimeNs t, const ImuSample& sample) { return t < sample.t_ns; });
  if (first != all.begin()) --first;
  auto last = std::lower_bound(all.begin(), all.end(), t_end,
                               [](const ImuSample& sample, TimeNs t) { return sample.t_ns < t; });
  if (last != all.end()) ++last;
  d.imu.samples.assign(first, last);
  d.ground_truth = EurocGroundTruth(
      poses, euroc.ground_truth.empty() ? GroundTruthState{} : euroc.ground_truth.front(), t_begin,
      t_end);
  if (s.imu_from_ground_truth) {
    // The IMU derived from the same truth the images are rendered from: the real IMU's scale,
    // misalignment and bias changes, which the truth does not share, are left out.
    d.imu = ImuFromGroundTruth(EurocGroundTruth(
        poses, GroundTruthState{}, t_begin - SecondsToNs(0.1), t_end + SecondsToNs(0.1)));
    for (auto& row : d.ground_truth) row.b_g = row.b_a = Eigen::Vector3d::Zero();
    // The derivation needs +-50 ms of truth: at the ends of the flight the truth is cut to the
    // IMU's span.
    std::erase_if(d.ground_truth, [&](const GroundTruthState& row) {
      return row.t_ns < d.imu.samples.front().t_ns || row.t_ns > d.imu.samples.back().t_ns;
    });
  }
  const TexturedRoom room = EurocVisionRoom(s.texel_m);
  TexturedRoomToMapParameters(room, &d.map.parameters);

  const TimeNs period_ns = SecondsToNs(1.0 / s.camera_rate_hz);
  for (TimeNs t = d.ground_truth.front().t_ns; t <= d.ground_truth.back().t_ns; t += period_ns)
    for (CameraSensor& camera : cameras) camera.frames.push_back({t, ""});

  std::string images = "none (simulate with --render)";
  if (options.render_images) {
    const SimulationSeeds seeds = SimulationSeeds::FromMaster(options.seed);
    const auto T_W_B_at = [&](TimeNs t) { return InterpolatedTruth(d.ground_truth, t).T_W_B; };
    const TexturedFramesSummary summary = RenderTexturedFrames(
        room, textures, image_settings, T_W_B_at, d.ground_truth.front().t_ns,
        d.ground_truth.back().t_ns, seeds.camera, kEurocVision, options.seed, &cameras);
    images = fmt::format(
        "{} ray cast images, {:.2f} renders per image on average (motion blur), {} pixels per "
        "image without an undistorted ray (black)",
        summary.images, summary.mean_renders_per_image, summary.invalid_pixels);
  }
  d.cameras = std::move(cameras);
  d.scenario_info = EurocVisionInfo(options, s, image_settings, d, room, images);
  if (textures) {
    d.scenario_info["texture_faces"] =
        DescribeTextures(*textures, TexturedRoomFaces(room, *textures));
  }
  if (!skipped.empty()) {
    std::string text;
    for (const std::string& file : skipped) text += (text.empty() ? "" : "; ") + file;
    d.scenario_info["textures_skipped"] = text;
  }
  return d;
}

}  // namespace mavloc
