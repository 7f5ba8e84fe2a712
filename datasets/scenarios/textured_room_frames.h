// Camera images of a room painted with photographs (datasets/rendering/textured_room_renderer.h)
// along a trajectory, for the scenarios that render natural-feature images (euroc-vision). Each
// frame is rendered, written as cam<i>/<t>.png into the image folder and dropped: memory does not
// grow with the log. WriteEurocDataset then copies the files into mav0/cam<i>/data.
//
// Exposure: a frame stamped t integrates over [t - exposure_s / 2, t + exposure_s / 2]. The image
// is the average of n renders at poses spread evenly over that interval, n chosen per frame from
// the motion: about one render per pixel the image moves (rotation angle x focal length plus
// translation x focal length / 1 m, a near wall's parallax), at least 1, at most blur_samples. A
// hover costs one render, a fast turn up to blur_samples.
//
// Settings (`--set`, TexturedFrameSettingKeys): textures (folder of PNG/JPEG photographs; default
// ../shared/data/textures, found relative to the current folder and then the executable's folder
// and its parents), exposure_s (0.004), blur_samples (8), gain (1), image_noise_grey (2),
// image_dir (default: the simulate command's scratch folder, else a fresh temp folder).
#pragma once

#include <functional>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "core/dataset.h"
#include "datasets/rendering/textured_room_renderer.h"
#include "datasets/scenarios/scenario.h"

namespace mavloc {

struct TexturedFrameSettings {
  std::string textures;  // folder of photographs ("" until resolved)
  bool textures_given = false;
  double exposure_s = 0.004;
  int blur_samples = 8;
  TexturedRenderOptions render;
  std::string image_dir;
};

// The `--set` keys ReadTexturedFrameSettings reads (for a scenario's registry entry).
const std::set<std::string>& TexturedFrameSettingKeys();

// Reads and checks the settings; throws InputError naming the scenario and the setting. The
// texture folder defaults to FindDefaultTextureFolder() (left empty when there is none).
TexturedFrameSettings ReadTexturedFrameSettings(const ScenarioOptions& options,
                                                const std::string& scenario);

// ../shared/data/textures as described above, or "" when absent.
std::string FindDefaultTextureFolder();

// The photographs of settings.textures (InputError naming the folder and the setting `textures`
// when it is missing or has no usable image). Each skipped file is printed as a warning on stderr
// ("mavloc: warning: scenario S: texture skipped: PATH: reason") and returned in *skipped.
std::shared_ptr<const RoomTextures> LoadScenarioTextures(const TexturedFrameSettings& settings,
                                                         const std::string& scenario,
                                                         std::vector<std::string>* skipped);

// The camera poses T_W_C of one exposure (see the top of the file), clamped to [t_min, t_max].
std::vector<Pose> ExposurePoses(const std::function<Pose(TimeNs)>& T_W_B_at, const Pose& T_B_C,
                                TimeNs t_ns, TimeNs t_min, TimeNs t_max, double exposure_s,
                                int blur_samples, double focal_px);

struct TexturedFramesSummary {
  size_t images = 0;
  double mean_renders_per_image = 0.0;
  int invalid_pixels = 0;  // per image of cam0: rays the camera model could not undistort
  std::string folder;
};

// Renders every frame of every camera (frames already listed), writes the PNGs and sets each
// frame's image_path. The noise of camera c's frame i is drawn from SplitMix64(camera_seed +
// 2 i + c). T_W_B_at must cover [t_min, t_max].
TexturedFramesSummary RenderTexturedFrames(const TexturedRoom& room,
                                           std::shared_ptr<const RoomTextures> textures,
                                           const TexturedFrameSettings& settings,
                                           const std::function<Pose(TimeNs)>& T_W_B_at,
                                           TimeNs t_min, TimeNs t_max, uint64_t camera_seed,
                                           const std::string& scenario, uint64_t seed,
                                           std::vector<CameraSensor>* cameras);

}  // namespace mavloc
