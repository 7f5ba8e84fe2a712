// The list of paper reproductions (`mavloc repro NAME`). Adding one is one entry here.
#include <algorithm>

#include "core/errors.h"
#include "evaluation/repro/apriltag_repro.h"
#include "evaluation/repro/euroc_imu_april_repro.h"
#include "evaluation/repro/laser_repro.h"
#include "evaluation/repro/pixhawk_repro.h"
#include "evaluation/repro/repro.h"
#include "evaluation/repro/smoother_repro.h"
#include "evaluation/repro/three_point_repro.h"
#include "evaluation/sweep/unit_kinds.h"

namespace mavloc {

const std::vector<ReproDefinition>& ReproRegistry() {
  static const std::vector<ReproDefinition> kDefinitions = {
      ThreePointRepro(), PixhawkRepro(),  LaserRepro(),
      AprilTagRepro(),   SmootherRepro(), EurocImuAprilRepro(),
  };
  return kDefinitions;
}

void RejectUnknownReproSettings(const std::string& repro, const ReproSettings& settings,
                                const std::vector<std::string>& known) {
  for (const auto& [key, value] : settings) {
    if (std::find(known.begin(), known.end(), key) != known.end()) continue;
    std::string list;
    for (const auto& k : known) list += (list.empty() ? "" : ", ") + k;
    throw InputError("--set " + key + "=" + value + ": repro " + repro + " has no setting '" + key +
                     "' (known: " + list + ")");
  }
}

void RegisterReproUnitKinds() {
  for (const auto& repro : ReproRegistry())
    if (repro.unit) RegisterSweepUnitKind(repro.name, repro.unit);
}

const ReproDefinition* FindRepro(const std::string& name) {
  for (const auto& repro : ReproRegistry())
    if (repro.name == name) return &repro;
  return nullptr;
}

}  // namespace mavloc
