// Doubles in JSON that survive a round trip: nlohmann writes a finite double with all the digits
// needed to read back the same bits, but writes NaN and infinities as null, which it then refuses
// to read as a number. Non-finite values are written as null on purpose and read back as NaN.
#pragma once

#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>
#include <vector>

namespace mavloc {

inline nlohmann::json JsonNumber(double value) {
  return std::isfinite(value) ? nlohmann::json(value) : nlohmann::json(nullptr);
}

// NaN for null; throws nlohmann::json::type_error for anything else that is not a number.
inline double NumberFromJson(const nlohmann::json& json) {
  return json.is_null() ? std::numeric_limits<double>::quiet_NaN() : json.get<double>();
}

// A list of doubles, each as JsonNumber, and back.
inline nlohmann::json JsonNumbers(const std::vector<double>& values) {
  nlohmann::json list = nlohmann::json::array();
  for (const double v : values) list.push_back(JsonNumber(v));
  return list;
}
inline std::vector<double> NumbersFromJson(const nlohmann::json& json) {
  std::vector<double> values;
  for (const auto& v : json) values.push_back(NumberFromJson(v));
  return values;
}

}  // namespace mavloc
