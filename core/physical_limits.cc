#include "core/physical_limits.h"

#include <fmt/format.h>

namespace mavloc::limits {

std::string RangeText(double lo, double hi, const std::string& unit) {
  return fmt::format("[{:g}, {:g}]{}{} (sanity range, core/physical_limits.h)", lo, hi,
                     unit.empty() ? "" : " ", unit);
}

}  // namespace mavloc::limits
