// Stamp fields of trajectory files converted to int64 nanoseconds without binary rounding where
// the text allows it: decimal seconds "S.F" exactly (fraction digits past 9 rounded half up),
// integer nanoseconds exactly; scientific notation through double (as evo/numpy read it).
#pragma once

#include <string>

#include "core/time.h"

namespace mavloc {

// false when the text is not a finite, non-negative number or lies beyond limits::kMaxTimestampNs
// (core/physical_limits.h).
bool ParseSecondsAsNs(const std::string& text, TimeNs* t_ns);
bool ParseNanoseconds(const std::string& text, TimeNs* t_ns);

}  // namespace mavloc
