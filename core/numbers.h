// Numeric constants and small reductions used across the library (one definition each, so that
// files can be compiled together in a unity build).
#pragma once

#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

namespace mavloc {

inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
inline constexpr double kRadToDeg = 180.0 / std::numbers::pi;

// The mean of the finite values (NaN marks "no value" in per-run tables); NaN when there are none.
inline double MeanOfFinite(const std::vector<double>& values) {
  double sum = 0.0;
  int n = 0;
  for (const double v : values)
    if (std::isfinite(v)) sum += v, ++n;
  return n > 0 ? sum / n : kNaN;
}

}  // namespace mavloc
