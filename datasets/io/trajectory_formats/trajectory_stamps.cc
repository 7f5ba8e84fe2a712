#include "datasets/io/trajectory_formats/trajectory_stamps.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "core/number_text.h"
#include "core/physical_limits.h"

namespace mavloc {

namespace {

// 1971-01-01T00:00:00Z: a stamp since 1970 earlier than this is no log of a real sensor (365 days).
constexpr long long kSeconds1971 = 365LL * 86400;
constexpr TimeNs kNs1971 = kSeconds1971 * kNsPerSecond;
// Stamps closer than this are no pose source's (100 MHz); nanosecond stamps this close are seconds
// or smaller units written without a decimal point.
constexpr TimeNs kMinNanosecondSpacing_ns = 10;
// Below this spacing (1 MHz, limits::kMaxRate_hz) stamps before 1971 as nanoseconds that are a date
// as seconds are taken for seconds.
constexpr TimeNs kMinDatedSpacing_ns = 1000;

bool Digits(std::string_view s) {
  return s.find_first_not_of("0123456789") == std::string_view::npos;
}

double MaxTimestampSeconds() { return static_cast<double>(limits::kMaxTimestampNs) * 1e-9; }

// Calendar year of a time in seconds since 1970 (approximate: 365.25-day years).
int YearOf(double seconds) { return 1970 + static_cast<int>(seconds / (365.25 * 86400.0)); }

// "nanoseconds (divide by 1e9)" when value / 1e9 is a time since 1971 in range; likewise for
// microseconds and milliseconds; "" when no unit fits.
std::string SmallerUnitHint(double value) {
  struct Unit {
    double divisor;
    const char* name;
    const char* divide;
  };
  constexpr Unit kUnits[] = {
      {1e9, "nanoseconds", "1e9"}, {1e6, "microseconds", "1e6"}, {1e3, "milliseconds", "1e3"}};
  for (const Unit& unit : kUnits) {
    const double seconds = value / unit.divisor;
    if (seconds >= static_cast<double>(kSeconds1971) && seconds <= MaxTimestampSeconds())
      return fmt::format("{} (divide by {})", unit.name, unit.divide);
  }
  return "";
}

std::string Beyond(const std::string& text, bool seconds) {
  return fmt::format("'{}' is beyond {} {} (limits::kMaxTimestampNs = 2^62 ns, year 2116)", text,
                     seconds ? limits::kMaxTimestampNs / kNsPerSecond : limits::kMaxTimestampNs,
                     seconds ? "s" : "ns");
}

}  // namespace

bool ParseSecondsAsNs(std::string_view text, TimeNs* t_ns) {
  const std::string_view body = !text.empty() && text[0] == '+' ? text.substr(1) : text;
  const size_t dot = body.find('.');
  const std::string_view integer = body.substr(0, dot);
  const std::string_view fraction =
      dot == std::string_view::npos ? std::string_view() : body.substr(dot + 1);
  if (!integer.empty() && Digits(integer) && Digits(fraction) && integer.size() < 11) {
    const long long whole_s = ParseIntegerText(integer).value;  // at most 10 digits: no overflow
    if (whole_s >= limits::kMaxTimestampNs / kNsPerSecond) return false;
    // The first 9 fraction digits as nanoseconds (missing digits are zeros).
    TimeNs nanos = 0;
    for (size_t k = 0; k < 9; ++k)
      nanos = 10 * nanos + (k < fraction.size() ? fraction[k] - '0' : 0);
    TimeNs t = whole_s * kNsPerSecond + nanos;
    if (fraction.size() > 9 && fraction[9] >= '5') ++t;
    *t_ns = t;
    return true;
  }
  const ParsedNumber<double> seconds = ParseDoubleText(text);
  if (!seconds.ok() || seconds.value < 0.0 ||
      !(seconds.value * 1e9 <= static_cast<double>(limits::kMaxTimestampNs)))
    return false;
  *t_ns = SecondsToNs(seconds.value);
  return true;
}

bool ParseNanoseconds(std::string_view text, TimeNs* t_ns) {
  if (!text.empty() && Digits(text) && text.size() <= 18) {
    *t_ns = ParseIntegerText(text).value;  // at most 18 digits: no overflow
    return *t_ns <= limits::kMaxTimestampNs;
  }
  const ParsedNumber<double> ns = ParseDoubleText(text);
  if (!ns.ok() || ns.value < 0.0 || !(ns.value <= static_cast<double>(limits::kMaxTimestampNs)))
    return false;
  *t_ns = static_cast<TimeNs>(std::llround(ns.value));
  return true;
}

std::string DescribeBadStamp(const std::string& text, bool seconds, const std::string& format) {
  const std::string unit_name = seconds ? "seconds" : "nanoseconds";
  const ParsedNumber<double> parsed = ParseDoubleText(text);
  const bool negative = !text.empty() && text.front() == '-';
  if (parsed.ok() && !negative) {
    const std::string hint = seconds ? SmallerUnitHint(parsed.value) : "";
    if (!hint.empty())
      return fmt::format("'{}' is not a time in seconds: {} stamps are seconds; these look like {}",
                         text, format, hint);
    return Beyond(text, seconds);
  }
  // A number too large even for a double ("1" and 400 zeros) is beyond the range as well.
  if (parsed.status == NumberTextStatus::kOverflow && !negative) return Beyond(text, seconds);
  if (parsed.ok() || parsed.status == NumberTextStatus::kOverflow)
    return fmt::format("'{}' is not a non-negative time in {}", text, unit_name);
  return DescribeNumberText(text, parsed, "a non-negative time in " + unit_name);
}

TimeNs MedianStampSpacingNs(const std::vector<TimeNs>& t_ns) {
  if (t_ns.size() < 2) return 0;
  std::vector<TimeNs> spacing;
  spacing.reserve(t_ns.size() - 1);
  for (size_t i = 1; i < t_ns.size(); ++i) spacing.push_back(std::llabs(t_ns[i] - t_ns[i - 1]));
  const auto middle = spacing.begin() + static_cast<std::ptrdiff_t>(spacing.size() / 2);
  std::nth_element(spacing.begin(), middle, spacing.end());
  return *middle;
}

std::string SecondsReadAsNanoseconds(const std::vector<TimeNs>& t_ns) {
  if (t_ns.empty()) return "";
  const std::string advice =
      "they look like seconds: write them with a decimal point (a TUM row in seconds), or name "
      "the columns and the stamp's unit in a header line ('#timestamp [s],...' or "
      "'#timestamp [ns],...')";
  const TimeNs spacing_ns = MedianStampSpacingNs(t_ns);
  if (t_ns.size() >= 2 && spacing_ns < kMinNanosecondSpacing_ns) {
    const std::string spacing =
        spacing_ns == 0 ? "most stamps repeat the one before"
                        : fmt::format(
                              "the stamps are typically {} ns apart (a rate of {:.3g} Hz, "
                              "beyond any pose source)",
                              spacing_ns, 1e9 / static_cast<double>(spacing_ns));
    return "read as nanoseconds, " + spacing + "; " + advice;
  }
  const TimeNs first = t_ns.front();
  const bool before_1971 = first < kNs1971;
  const bool dated_as_seconds = first >= kSeconds1971;
  if (before_1971 && dated_as_seconds && (t_ns.size() == 1 || spacing_ns < kMinDatedSpacing_ns))
    return fmt::format(
        "read as nanoseconds, the first stamp {} is {:.3f} s after 1 January 1970 (before 1971), "
        "while as seconds it is in {}; {}",
        first, NsToSeconds(first), YearOf(static_cast<double>(first)), advice);
  return "";
}

}  // namespace mavloc
