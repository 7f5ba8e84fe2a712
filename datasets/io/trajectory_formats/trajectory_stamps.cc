#include "datasets/io/trajectory_formats/trajectory_stamps.h"

#include <fmt/format.h>

#include <cmath>

#include "core/physical_limits.h"
#include "datasets/io/trajectory_formats/trajectory_text.h"

namespace mavloc {

namespace {

bool Digits(const std::string& s) { return s.find_first_not_of("0123456789") == std::string::npos; }

}  // namespace

bool ParseSecondsAsNs(const std::string& text, TimeNs* t_ns) {
  const std::string body = !text.empty() && text[0] == '+' ? text.substr(1) : text;
  const auto dot = body.find('.');
  const std::string integer = body.substr(0, dot);
  const std::string fraction = dot == std::string::npos ? "" : body.substr(dot + 1);
  if (!integer.empty() && Digits(integer) && Digits(fraction) && integer.size() < 11) {
    const long long whole_s = std::stoll(integer);  // at most 10 digits: no overflow
    if (whole_s >= limits::kMaxTimestampNs / kNsPerSecond) return false;
    std::string nanos = fraction.substr(0, 9);
    nanos.resize(9, '0');
    TimeNs t = whole_s * kNsPerSecond + std::stoll(nanos);
    if (fraction.size() > 9 && fraction[9] >= '5') ++t;
    *t_ns = t;
    return true;
  }
  double seconds = 0.0;
  if (!ParseFiniteDouble(text, &seconds) || seconds < 0.0 ||
      !(seconds * 1e9 <= static_cast<double>(limits::kMaxTimestampNs)))
    return false;
  *t_ns = SecondsToNs(seconds);
  return true;
}

bool ParseNanoseconds(const std::string& text, TimeNs* t_ns) {
  if (!text.empty() && Digits(text) && text.size() <= 18) {
    *t_ns = std::stoll(text);
    return *t_ns <= limits::kMaxTimestampNs;
  }
  double ns = 0.0;
  if (!ParseFiniteDouble(text, &ns) || ns < 0.0 ||
      !(ns <= static_cast<double>(limits::kMaxTimestampNs)))
    return false;
  *t_ns = static_cast<TimeNs>(std::llround(ns));
  return true;
}

std::string DescribeBadStamp(const std::string& text, bool seconds) {
  const std::string unit = seconds ? "s" : "ns";
  // A number too large even for a double ("1" and 400 zeros) is beyond the range as well.
  const std::string body = !text.empty() && text[0] == '+' ? text.substr(1) : text;
  const bool decimal =
      !body.empty() && body.find_first_not_of("0123456789.") == std::string::npos &&
      body.find_first_of("0123456789") != std::string::npos && body.find('.') == body.rfind('.');
  double value = 0.0;
  if (decimal || (ParseFiniteDouble(text, &value) && value > 0.0)) {
    return fmt::format("'{}' is beyond {} {} (limits::kMaxTimestampNs = 2^62 ns, year 2116)", text,
                       seconds ? limits::kMaxTimestampNs / kNsPerSecond : limits::kMaxTimestampNs,
                       unit);
  }
  return fmt::format("'{}' is not a non-negative time in {}", text,
                     seconds ? "seconds" : "nanoseconds");
}

}  // namespace mavloc
