// Stamp fields of trajectory files converted to int64 nanoseconds without binary rounding where
// the text allows it: decimal seconds "S.F" exactly (fraction digits past 9 rounded half up),
// integer nanoseconds exactly; scientific notation through double (as evo/numpy read it). Every
// field is read whole by the strict parser of core/number_text.h.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "core/time.h"

namespace mavloc {

// false when the text is not a finite, non-negative number or lies beyond limits::kMaxTimestampNs
// (core/physical_limits.h).
bool ParseSecondsAsNs(std::string_view text, TimeNs* t_ns);
bool ParseNanoseconds(std::string_view text, TimeNs* t_ns);
// Why one of them refused `text` (in seconds or nanoseconds), for a message. `format` names the
// file's format ("TUM") for the hint given when stamps that must be seconds are nanoseconds,
// microseconds or milliseconds since 1970: "'1403636579763555584' is not a time in seconds: TUM
// stamps are seconds; these look like nanoseconds (divide by 1e9)". Otherwise "'1e20' is beyond
// 4611686018 s (limits::kMaxTimestampNs = 2^62 ns, year 2116)" for a positive number too large,
// else "'abc' is not a non-negative time in seconds" (with the parser's reason when it has one).
std::string DescribeBadStamp(const std::string& text, bool seconds, const std::string& format);

// Why stamps that a file's layout takes for nanoseconds (no header states the unit) must be
// seconds instead, or "" when they may be nanoseconds. Taken for seconds: stamps typically less
// than 10 ns apart (over 100 MHz: no pose source), and stamps before 1971 as nanoseconds that are
// a date (1971 .. 2116) as seconds, when they are typically less than a microsecond apart (over
// limits::kMaxRate_hz) or there is one row. Small stamps that are no date either way (simulated
// data counting from 0) stay nanoseconds. t_ns holds the stamps in file order.
std::string SecondsReadAsNanoseconds(const std::vector<TimeNs>& t_ns);

// Typical spacing of the stamps in file order (the median of |t[i] - t[i-1]|); 0 for fewer than 2.
TimeNs MedianStampSpacingNs(const std::vector<TimeNs>& t_ns);

}  // namespace mavloc
