// Synthetic scenarios: named generators of complete datasets (IMU, camera streams, ground truth,
// map, scenario.yaml). A scenario is deterministic in its options: the same seed gives the same
// bytes. Each scenario documents its defaults in the scenario_info it writes.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "core/dataset.h"
#include "core/time.h"

namespace mavloc {

// Start time of every simulated scenario: 1000 s, positive EuRoC-like stamps.
inline constexpr TimeNs kScenarioStartNs = 1'000'000'000'000;

// Sanity limits of a simulated dataset, the one place they are stated. A
// dataset is generated in memory and then written as CSV: an IMU or ground-truth row takes ~100
// bytes in memory and ~120 bytes of text, so an hour at the fastest rate allowed (1000 Hz) is
// 3.6e6 rows per stream, ~0.4 GB of memory and ~0.4 GB of CSV each for IMU and ground truth, and
// a few minutes of CPU: the most a laptop simulates comfortably. Longer or faster requests are
// refused before any work (`--duration`, and every `--set *_rate_hz`).
inline constexpr double kMaxScenarioDurationS = 3600.0;
inline constexpr double kMaxScenarioRateHz = 1000.0;
// A slower stream holds too few samples to estimate anything over a scenario of minutes.
inline constexpr double kMinScenarioRateHz = 1.0;

// The range of a numeric `--set` value by the unit its name ends in (`pixel_noise_px`,
// `tilt_deg`, ...): wide enough for any study, narrow enough that the simulated data stays within
// what the dataset readers accept (core/physical_limits.h). The first matching suffix applies.
struct ScenarioSettingRange {
  const char* suffix;
  double lo, hi;
  const char* unit;
};
inline const std::vector<ScenarioSettingRange>& ScenarioSettingRanges() {
  static const std::vector<ScenarioSettingRange> kRanges = {
      {"_deg_s", -5000.0, 5000.0, "deg/s"},  // below 100 rad/s, the IMU reader's limit
      {"_deg", -360.0, 360.0, "deg"},       {"_px", 0.0, 10000.0, "px"},
      {"_m_s2", -200.0, 200.0, "m/s^2"},    {"_m_s", -1000.0, 1000.0, "m/s"},
      {"_ms", -60000.0, 60000.0, "ms"},     {"_m", -10000.0, 10000.0, "m"},
      {"_offset_s", -60.0, 60.0, "s"},      {"_s", 0.0, 3600.0, "s"},
      {"_fraction", 0.0, 1.0, ""},          {"_grey", 0.0, 255.0, "grey levels"},
  };
  return kRanges;
}
// Counts and sizes, refused above these before any work (`--set`): landmarks of mav-figure-eight
// (a feature row is ~50 bytes in memory; 1000 landmarks, a third in view, at 20 Hz for an hour are
// 2.2e7 rows, ~1 GB, against 4e6 for the default 200), and the tag renderer's samples per pixel
// (supersampling^2 x blur_samples renders per frame: 16 and 64 are far beyond the defaults 4, 5).
inline constexpr int kMaxScenarioLandmarks = 1000;
inline constexpr int kMaxScenarioSupersampling = 16;
inline constexpr int kMaxScenarioBlurSamples = 64;

struct ScenarioOptions {
  uint64_t seed = 1;
  std::optional<double> duration_s;  // scenario default when unset
  // Scenario-specific settings as key=value text (`--set key=value`), e.g. "D=0.1".
  std::map<std::string, std::string> settings;
  bool render_images = false;  // for scenarios that can render cam images (written by WriteDataset)
  // Where rendering scenarios put their images when the `image_dir` setting is not given (empty: a
  // fresh folder under the system temp dir). `mavloc simulate` points it inside the output folder
  // and removes it once WriteEurocDataset has copied the images into cam*/data.
  std::string image_dir;

  // Typed access to settings; throws InputError naming the key when the text does not parse.
  double GetDouble(const std::string& key, double fallback) const;
  int GetInt(const std::string& key, int fallback) const;
  bool GetBool(const std::string& key, bool fallback) const;
  std::string GetString(const std::string& key, const std::string& fallback) const;

  // Set by the registry's generate (ScenarioEntry): the settings the scenario declares. A getter
  // asked for an undeclared key then throws std::logic_error, so that the declared list (which
  // rejects unknown `--set` keys up front) cannot silently fall behind the code.
  std::shared_ptr<const std::set<std::string>> declared_settings;
};

struct ScenarioEntry {
  std::string name;
  std::string description;
  // Every `--set` key the scenario reads. The registry's generate rejects any other key, a
  // duration outside (0, kMaxScenarioDurationS], a `*_rate_hz` setting outside
  // (0, kMaxScenarioRateHz] and a count above its kMaxScenario* limit with an InputError before
  // generating anything.
  std::set<std::string> settings;
  std::function<Dataset(const ScenarioOptions&)> generate;
  // The scenario's visual measurements are its rendered images (no simulated feature or tag
  // stream): `compare --scenario` renders them, where other scenarios render with `simulate
  // --render` only.
  bool measures_by_images = false;
};

// The check ScenarioEntry::generate makes before generating (exposed for the CLI, which checks
// before it prepares any output): throws InputError naming the scenario and the offending key or
// value, with the list of known keys.
void CheckScenarioOptions(const ScenarioEntry& entry, const ScenarioOptions& options);
// The same check for a generator called directly (a reproduction, a test) rather than through its
// registry entry: the registry's list of the scenario's settings is the only one.
void CheckRegisteredScenarioOptions(const std::string& scenario, const ScenarioOptions& options);

// All scenarios, in a fixed order (datasets/scenarios/scenario_registry.cc lists them).
const std::vector<ScenarioEntry>& ScenarioRegistry();
const ScenarioEntry* FindScenario(const std::string& name);
// The scenario `mavloc compare` runs with no arguments.
std::string DefaultScenarioName();

// The EuRoC MAV cam0 (752 x 480, its intrinsics and radial-tangential distortion), shared by the
// scenarios that simulate a EuRoC-like camera.
CameraModel EurocCam0Model();

}  // namespace mavloc
