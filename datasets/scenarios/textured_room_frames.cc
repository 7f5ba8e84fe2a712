#include "datasets/scenarios/textured_room_frames.h"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "core/atomic_file.h"
#include "core/errors.h"
#include "core/image_codec.h"
#include "core/progress.h"
#include "core/random.h"

namespace mavloc {
namespace {

constexpr const char* kRelativeTextures = "../shared/data/textures";
// The translation part of the motion estimate: parallax of a wall this far away.
constexpr double kBlurNearDepthM = 1.0;

std::vector<std::filesystem::path> TextureFolderCandidates() {
  namespace fs = std::filesystem;
  std::vector<fs::path> candidates = {fs::current_path() / kRelativeTextures};
  std::error_code error;
  const fs::path exe = fs::read_symlink("/proc/self/exe", error);
  if (!error) {
    for (fs::path dir = exe.parent_path(); !dir.empty(); dir = dir.parent_path()) {
      candidates.push_back(dir / kRelativeTextures);
      if (dir == dir.root_path()) break;
    }
  }
  return candidates;
}

std::string FreshRenderFolder(const std::string& scenario, uint64_t seed) {
  return (std::filesystem::temp_directory_path() /
          fmt::format("mavloc_render_{}_{}_{}", scenario, seed, static_cast<long>(getpid())))
      .string();
}

}  // namespace

const std::set<std::string>& TexturedFrameSettingKeys() {
  static const std::set<std::string> kKeys = {"textures",         "exposure_s", "blur_samples",
                                              "image_noise_grey", "gain",       "image_dir"};
  return kKeys;
}

std::string FindDefaultTextureFolder() {
  for (const auto& candidate : TextureFolderCandidates()) {
    if (std::filesystem::is_directory(candidate))
      return std::filesystem::weakly_canonical(candidate).string();
  }
  return "";
}

TexturedFrameSettings ReadTexturedFrameSettings(const ScenarioOptions& options,
                                                const std::string& scenario) {
  const std::string prefix = "scenario " + scenario + ": ";
  TexturedFrameSettings s;
  s.textures = options.GetString("textures", "");
  s.textures_given = !s.textures.empty();
  if (!s.textures_given) s.textures = FindDefaultTextureFolder();
  s.exposure_s = options.GetDouble("exposure_s", s.exposure_s);
  s.blur_samples = options.GetInt("blur_samples", s.blur_samples);
  s.render.gain = options.GetDouble("gain", s.render.gain);
  s.render.noise_sigma_grey = options.GetDouble("image_noise_grey", s.render.noise_sigma_grey);
  s.image_dir = options.GetString("image_dir", options.image_dir);
  if (!(s.exposure_s >= 0.0 && s.exposure_s <= 0.1))
    throw InputError(prefix + "exposure_s must be in [0, 0.1] s");
  if (!(s.blur_samples >= 1 && s.blur_samples <= kMaxScenarioBlurSamples))
    throw InputError(
        fmt::format("{}blur_samples must be in [1, {}]", prefix, kMaxScenarioBlurSamples));
  if (!(s.render.gain > 0.0 && s.render.gain <= 10.0))
    throw InputError(prefix + "gain must be in (0, 10]");
  if (!(s.render.noise_sigma_grey >= 0.0 && s.render.noise_sigma_grey <= 50.0))
    throw InputError(prefix + "image_noise_grey must be in [0, 50]");
  return s;
}

std::shared_ptr<const RoomTextures> LoadScenarioTextures(const TexturedFrameSettings& settings,
                                                         const std::string& scenario,
                                                         std::vector<std::string>* skipped) {
  if (settings.textures.empty()) {
    std::string tried;
    for (const auto& c : TextureFolderCandidates())
      tried += (tried.empty() ? "" : ", ") + c.string();
    throw InputError("scenario " + scenario +
                     ": no texture folder (set textures=DIR, a folder of PNG or JPEG "
                     "photographs); tried " +
                     tried);
  }
  auto textures =
      std::make_shared<const RoomTextures>(LoadRoomTextures(settings.textures, "textures"));
  for (const std::string& file : textures->skipped) {
    std::fprintf(stderr, "mavloc: warning: scenario %s: texture skipped: %s\n", scenario.c_str(),
                 PrintableMessage(file).c_str());
    if (skipped != nullptr) skipped->push_back(file);
  }
  return textures;
}

std::vector<Pose> ExposurePoses(const std::function<Pose(TimeNs)>& T_W_B_at, const Pose& T_B_C,
                                TimeNs t_ns, TimeNs t_min, TimeNs t_max, double exposure_s,
                                int blur_samples, double focal_px) {
  auto camera_at = [&](double offset_s) {
    return T_W_B_at(std::clamp(t_ns + SecondsToNs(offset_s), t_min, t_max)) * T_B_C;
  };
  if (exposure_s <= 0.0 || blur_samples <= 1) return {camera_at(0.0)};
  const Pose first = camera_at(-0.5 * exposure_s), last = camera_at(0.5 * exposure_s);
  const double motion_px = focal_px * (RotationAngleBetween(first.q, last.q) +
                                       (last.p - first.p).norm() / kBlurNearDepthM);
  const int n = std::clamp(static_cast<int>(std::ceil(motion_px)), 1, blur_samples);
  if (n == 1) return {camera_at(0.0)};
  std::vector<Pose> poses;
  for (int k = 0; k < n; ++k) poses.push_back(camera_at(exposure_s * ((k + 0.5) / n - 0.5)));
  return poses;
}

TexturedFramesSummary RenderTexturedFrames(const TexturedRoom& room,
                                           std::shared_ptr<const RoomTextures> textures,
                                           const TexturedFrameSettings& settings,
                                           const std::function<Pose(TimeNs)>& T_W_B_at,
                                           TimeNs t_min, TimeNs t_max, uint64_t camera_seed,
                                           const std::string& scenario, uint64_t seed,
                                           std::vector<CameraSensor>* cameras) {
  TexturedFramesSummary summary;
  summary.folder =
      settings.image_dir.empty() ? FreshRenderFolder(scenario, seed) : settings.image_dir;
  std::vector<TexturedRoomRenderer> renderers;
  std::vector<std::filesystem::path> folders;
  for (const CameraSensor& camera : *cameras) {
    renderers.emplace_back(camera.model, room, textures, settings.render);
    folders.push_back(std::filesystem::path(summary.folder) / camera.name);
    std::error_code error;
    CreateOutputDirectories(folders.back(), error);
    if (error)
      throw InputError(folders.back().string(), 0, "image_dir",
                       "cannot create folder: " + error.message());
  }
  if (!renderers.empty()) summary.invalid_pixels = renderers.front().invalid_pixels();
  size_t renders = 0;
  for (size_t c = 0; c < cameras->size(); ++c) {
    CameraSensor& camera = (*cameras)[c];
    const double focal_px = std::max(camera.model.fu(), camera.model.fv());
    for (size_t i = 0; i < camera.frames.size(); ++i) {
      CameraFrame& frame = camera.frames[i];
      const std::vector<Pose> poses =
          ExposurePoses(T_W_B_at, camera.T_B_C, frame.t_ns, t_min, t_max, settings.exposure_s,
                        settings.blur_samples, focal_px);
      renders += poses.size();
      const cv::Mat image = renderers[c].Render(poses, SplitMix64(camera_seed + 2 * i + c));
      frame.image_path = (folders[c] / fmt::format("{}.png", frame.t_ns)).string();
      WriteFileAtomically(frame.image_path, EncodePng(image));
      ++summary.images;
      if (i % 100 == 0)
        ReportProgress("render", fmt::format("{} {} frame {}/{}", scenario, camera.name, i + 1,
                                             camera.frames.size()));
    }
  }
  if (summary.images > 0)
    summary.mean_renders_per_image =
        static_cast<double>(renders) / static_cast<double>(summary.images);
  return summary;
}

}  // namespace mavloc
