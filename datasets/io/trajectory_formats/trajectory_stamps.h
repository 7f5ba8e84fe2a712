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
// Why one of them refused `text` (in seconds or nanoseconds), for a message: "'1e20' is beyond
// 4611686018 s (limits::kMaxTimestampNs = 2^62 ns, year 2116)" for a positive number too large,
// else "'abc' is not a non-negative time in seconds".
std::string DescribeBadStamp(const std::string& text, bool seconds);

}  // namespace mavloc
