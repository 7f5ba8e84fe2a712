#include "datasets/scenarios/scenario.h"

#include <fmt/format.h>

#include <cmath>
#include <map>
#include <optional>
#include <stdexcept>

#include "core/errors.h"
#include "core/key_values.h"
#include "core/text.h"

namespace mavloc {

namespace {

void RequireDeclared(const ScenarioOptions& options, const std::string& key) {
  if (options.declared_settings && !options.declared_settings->count(key))
    throw std::logic_error("a scenario reads setting '" + key +
                           "' that its entry in datasets/scenarios/scenario_registry.cc does not "
                           "declare");
}

std::string JoinKeys(const std::set<std::string>& keys) {
  std::string names;
  for (const auto& k : keys) names += (names.empty() ? "" : ", ") + k;
  return names.empty() ? "none" : names;
}

}  // namespace

double ScenarioOptions::GetDouble(const std::string& key, double fallback) const {
  RequireDeclared(*this, key);
  return GetDoubleSetting(settings, key, fallback);
}
int ScenarioOptions::GetInt(const std::string& key, int fallback) const {
  RequireDeclared(*this, key);
  return GetIntSetting(settings, key, fallback);
}
bool ScenarioOptions::GetBool(const std::string& key, bool fallback) const {
  RequireDeclared(*this, key);
  return GetBoolSetting(settings, key, fallback);
}
std::string ScenarioOptions::GetString(const std::string& key, const std::string& fallback) const {
  RequireDeclared(*this, key);
  return GetStringSetting(settings, key, fallback);
}

namespace {

// A numeric setting's value, or nullopt for settings that are words (imu=..., bias=on).
std::optional<double> GetDoubleSettingIfNumeric(const std::map<std::string, std::string>& settings,
                                                const std::string& key) {
  for (const auto& range : ScenarioSettingRanges())
    if (EndsWith(key, range.suffix)) return GetDoubleSetting(settings, key, 0.0);
  return std::nullopt;
}

// The magnitude of a setting against the range of its unit (ScenarioSettingRanges): a value the
// simulator would turn into data that no reader accepts (a pixel noise of 1e308 px) is refused
// here, naming the setting, before anything is generated.
void CheckSettingMagnitude(const std::string& key, const std::string& text,
                           std::optional<double> value) {
  if (!value) return;
  for (const auto& range : ScenarioSettingRanges()) {
    if (!EndsWith(key, range.suffix)) continue;
    if (!(*value >= range.lo && *value <= range.hi))
      throw InputError(
          fmt::format("--set {}={}: outside [{:g}, {:g}] {}, the simulator's limits "
                      "for a setting in {} (datasets/scenarios/scenario.h)",
                      key, text, range.lo, range.hi, range.unit, range.unit));
    return;
  }
}

}  // namespace

void CheckScenarioOptions(const ScenarioEntry& entry, const ScenarioOptions& options) {
  for (const auto& [key, value] : options.settings) {
    if (!entry.settings.count(key))
      throw InputError("--set " + key + "=" + value + ": scenario " + entry.name +
                       " has no setting '" + key + "' (known: " + JoinKeys(entry.settings) + ")");
    if (EndsWith(key, "_rate_hz")) {
      const double rate_hz = GetDoubleSetting(options.settings, key, 0.0);
      if (!(rate_hz >= kMinScenarioRateHz && rate_hz <= kMaxScenarioRateHz))
        throw InputError(
            fmt::format("--set {}={}: outside [{}, {}] Hz, the simulator's limits "
                        "(datasets/scenarios/scenario.h)",
                        key, value, kMinScenarioRateHz, kMaxScenarioRateHz));
      continue;
    }
    CheckSettingMagnitude(key, value, GetDoubleSettingIfNumeric(options.settings, key));
  }
  // Counts and sizes (datasets/scenarios/scenario.h): a huge value would only end in an
  // allocation failure after minutes of work.
  const std::map<std::string, int> max_counts = {{"landmarks", kMaxScenarioLandmarks},
                                                 {"supersampling", kMaxScenarioSupersampling},
                                                 {"blur_samples", kMaxScenarioBlurSamples}};
  for (const auto& [key, limit] : max_counts) {
    const auto it = options.settings.find(key);
    if (it == options.settings.end() || !entry.settings.count(key)) continue;
    const int count = GetIntSetting(options.settings, key, 0);  // throws for a non-integer
    if (count > limit)
      throw InputError(
          fmt::format("--set {}={}: above {}, the simulator's limit (datasets/"
                      "scenarios/scenario.h)",
                      key, it->second, limit));
  }
  if (options.duration_s) {
    const double d = *options.duration_s;
    if (!(std::isfinite(d) && d > 0.0 && d <= kMaxScenarioDurationS))
      throw InputError(
          fmt::format("--duration {}: outside (0, {}] s, the simulator's limit "
                      "(kMaxScenarioDurationS, datasets/scenarios/scenario.h)",
                      d, kMaxScenarioDurationS));
  }
}

void CheckRegisteredScenarioOptions(const std::string& scenario, const ScenarioOptions& options) {
  const ScenarioEntry* entry = FindScenario(scenario);
  if (entry == nullptr) throw std::logic_error("scenario " + scenario + " is not registered");
  CheckScenarioOptions(*entry, options);
}

const ScenarioEntry* FindScenario(const std::string& name) {
  for (const auto& entry : ScenarioRegistry()) {
    if (entry.name == name) return &entry;
  }
  return nullptr;
}

std::string DefaultScenarioName() { return "mav-figure-eight"; }

CameraModel EurocCam0Model() {
  return CameraModel(752, 480, Eigen::Vector4d(458.654, 457.296, 367.215, 248.375),
                     DistortionModel::kRadialTangential,
                     {-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05});
}

}  // namespace mavloc
