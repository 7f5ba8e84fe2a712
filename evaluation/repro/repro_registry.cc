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

const std::vector<ReproEntry>& ReproRegistry() {
  static const std::vector<ReproEntry> kEntries = {
      {"three-point", "three-point paper Table I (2p vs 3p) and a noise x height sweep",
       RunThreePointRepro, RunThreePointReproUnit},
      {"pixhawk", "PIXHAWK fig. 15 (pnp vs upright-2p), sweep, 4 x 1-D KF, time stamps",
       RunPixhawkRepro, RunPixhawkReproUnit},
      {"laser", "laser-spot paper 5.1 (laser-plane, with/without bias) and 5.2 (euroc-laser)",
       RunLaserRepro, RunLaserReproUnit},
      {"apriltag", "AprilTag paper V: render -> detect -> EKF; hover Monte-Carlo, dynamic, NEES",
       RunAprilTagRepro, RunAprilTagReproUnit},
      {"smoother", "smoother vs its seed and the papers' filter, every visual scenario",
       RunSmootherRepro, RunSmootherReproUnit},
      {"euroc-imu-april",
       "smoother calibration (T_B_C, t_d, gravity) and the papers' tag estimators on "
       "EuRoC's real imu_april log, against EuRoC's official calibration",
       RunEurocImuAprilRepro, nullptr},
  };
  return kEntries;
}

void RejectUnknownReproSettings(const std::string& repro,
                                const std::map<std::string, std::string>& settings,
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
  for (const auto& entry : ReproRegistry())
    if (entry.unit) RegisterSweepUnitKind(entry.name, entry.unit);
}

const ReproEntry* FindRepro(const std::string& name) {
  for (const auto& entry : ReproRegistry()) {
    if (entry.name == name) return &entry;
  }
  return nullptr;
}

}  // namespace mavloc
