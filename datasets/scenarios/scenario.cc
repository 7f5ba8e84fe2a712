#include "datasets/scenarios/scenario.h"

#include "core/errors.h"
#include "core/key_values.h"

namespace mavloc {

double ScenarioOptions::GetDouble(const std::string& key, double fallback) const {
  return GetDoubleSetting(settings, key, fallback);
}
int ScenarioOptions::GetInt(const std::string& key, int fallback) const {
  return GetIntSetting(settings, key, fallback);
}
bool ScenarioOptions::GetBool(const std::string& key, bool fallback) const {
  return GetBoolSetting(settings, key, fallback);
}
std::string ScenarioOptions::GetString(const std::string& key, const std::string& fallback) const {
  return GetStringSetting(settings, key, fallback);
}

void ScenarioOptions::RejectUnknownSettings(const std::string& scenario,
                                            const std::set<std::string>& known) const {
  for (const auto& [key, value] : settings) {
    if (known.count(key)) continue;
    std::string names;
    for (const auto& k : known) names += (names.empty() ? "" : ", ") + k;
    throw InputError("scenario " + scenario + ": unknown setting '" + key + "' (known: " + names +
                     ")");
  }
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
