// Unit kinds the sweep machinery runs besides its own (a scenario x the grid's estimators): a
// named function that runs one unit (a configuration and a seed) with the grid's settings and
// returns its JSON result. The reproductions register theirs (RegisterReproUnitKinds,
// evaluation/repro/repro.h) when the program starts, so that the sweep does not depend on them.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <string>

namespace mavloc {

using SweepUnitKind = std::function<nlohmann::json(
    const std::map<std::string, std::string>& settings, const std::string& unit, uint64_t seed)>;

// Registers (or replaces) the unit kind `name`.
void RegisterSweepUnitKind(const std::string& name, SweepUnitKind run);
// nullptr when no unit kind of that name is registered.
const SweepUnitKind* FindSweepUnitKind(const std::string& name);

}  // namespace mavloc
