// The producer-specific `details` of a report in SI units, as report.json stores them: Values in
// JSON are SI; degrees and millimetres are for the tables people read. Producers that still build
// their details in display units (a reproduction's "position_rmse_cm", compare's per-quantity
// errors with "unit": "deg") are converted here, once, by two rules:
// - a key ending in a display unit (_deg, _deg_s, _deg_per_s, _deg_per_m, _mm, _cm, _ms) whose
//   value holds numbers gets the SI suffix (_rad, _rad_s, _rad_per_s, _rad_per_m, _m, _m, _s) and
//   every number below it is scaled; a key whose value holds no number (an echoed setting such as
//   "bearing_noise_deg": "0.5") is left as it is;
// - an object with "unit": "deg", "deg/s", "mm", "cm" or "ms" gets the SI unit and its numbers
//   are scaled;
// in both, counts (count, pairs, runs, samples, corners, frames, n) are kept and a sum of squared
// errors (sse) is scaled by the square of the factor.
#pragma once

#include <nlohmann/json.hpp>

namespace mavloc {

nlohmann::json DetailsInSi(const nlohmann::json& details);

}  // namespace mavloc
