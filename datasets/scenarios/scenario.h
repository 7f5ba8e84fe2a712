// Synthetic scenarios: named generators of complete datasets (IMU, camera streams, ground truth,
// map, scenario.yaml). A scenario is deterministic in its options: the same seed gives the same
// bytes. Each scenario documents its defaults in the scenario_info it writes.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "core/dataset.h"
#include "core/time.h"

namespace mavloc {

// Start time of every simulated scenario: 1000 s, positive EuRoC-like stamps.
inline constexpr TimeNs kScenarioStartNs = 1'000'000'000'000;

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
  // Throws InputError naming the scenario and the known keys when a setting is not in `known`.
  void RejectUnknownSettings(const std::string& scenario, const std::set<std::string>& known) const;
};

struct ScenarioEntry {
  std::string name;
  std::string description;
  std::function<Dataset(const ScenarioOptions&)> generate;
};

// All scenarios, in a fixed order (datasets/scenarios/scenario_registry.cc lists them).
const std::vector<ScenarioEntry>& ScenarioRegistry();
const ScenarioEntry* FindScenario(const std::string& name);
// The scenario `mavloc compare` runs with no arguments.
std::string DefaultScenarioName();

// The EuRoC MAV cam0 (752 x 480, its intrinsics and radial-tangential distortion), shared by the
// scenarios that simulate a EuRoC-like camera.
CameraModel EurocCam0Model();

}  // namespace mavloc
