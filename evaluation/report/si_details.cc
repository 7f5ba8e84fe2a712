#include "evaluation/report/si_details.h"

#include <array>
#include <numbers>
#include <set>
#include <string>

namespace mavloc {

namespace {

struct UnitSuffix {
  const char* display;
  const char* si;
  double scale;  // SI value = display value * scale
};

constexpr double kDegree = std::numbers::pi / 180.0;

// Longest first, so that _deg_per_m is not read as _m.
constexpr std::array<UnitSuffix, 7> kSuffixes = {{{"_deg_per_m", "_rad_per_m", kDegree},
                                                  {"_deg_per_s", "_rad_per_s", kDegree},
                                                  {"_deg_s", "_rad_s", kDegree},
                                                  {"_deg", "_rad", kDegree},
                                                  {"_mm", "_m", 1e-3},
                                                  {"_cm", "_m", 1e-2},
                                                  {"_ms", "_s", 1e-3}}};

struct UnitName {
  const char* display;
  const char* si;
  double scale;
};
constexpr std::array<UnitName, 5> kUnits = {{{"deg", "rad", kDegree},
                                             {"deg/s", "rad/s", kDegree},
                                             {"mm", "m", 1e-3},
                                             {"cm", "m", 1e-2},
                                             {"ms", "s", 1e-3}}};

bool EndsWith(const std::string& text, const std::string& suffix) {
  return text.size() > suffix.size() &&
         text.compare(text.size() - suffix.size(), suffix.size(), suffix) == 0;
}

bool HoldsNumber(const nlohmann::json& value) {
  if (value.is_number()) return true;
  if (value.is_array() || value.is_object())
    for (const auto& item : value)
      if (HoldsNumber(item)) return true;
  return false;
}

bool IsCount(const std::string& key) {
  static const std::set<std::string> kCounts = {"count",   "pairs",  "runs", "samples",
                                                "corners", "frames", "n"};
  return kCounts.count(key) > 0;
}

// Every number below value times scale (booleans and strings untouched); in objects, counts are
// kept and a sum of squared errors ("sse") is scaled by scale^2.
nlohmann::json Scaled(const nlohmann::json& value, double scale) {
  if (value.is_number()) return value.get<double>() * scale;
  if (value.is_array()) {
    nlohmann::json out = nlohmann::json::array();
    for (const auto& item : value) out.push_back(Scaled(item, scale));
    return out;
  }
  if (!value.is_object()) return value;
  nlohmann::json out = nlohmann::json::object();
  for (const auto& [key, item] : value.items())
    out[key] = IsCount(key) ? item : Scaled(item, key == "sse" ? scale * scale : scale);
  return out;
}

nlohmann::json Convert(const nlohmann::json& value);

// An object whose "unit" is a display unit: its numbers scaled, the unit made SI.
bool ConvertUnitObject(const nlohmann::json& object, nlohmann::json* out) {
  const auto unit = object.find("unit");
  if (unit == object.end() || !unit->is_string()) return false;
  for (const UnitName& u : kUnits) {
    if (unit->get<std::string>() != u.display) continue;
    *out = nlohmann::json::object();
    for (const auto& [key, item] : object.items())
      (*out)[key] =
          IsCount(key) ? item : Scaled(Convert(item), key == "sse" ? u.scale * u.scale : u.scale);
    (*out)["unit"] = u.si;
    return true;
  }
  return false;
}

nlohmann::json Convert(const nlohmann::json& value) {
  if (value.is_array()) {
    nlohmann::json out = nlohmann::json::array();
    for (const auto& item : value) out.push_back(Convert(item));
    return out;
  }
  if (!value.is_object()) return value;
  nlohmann::json out;
  if (ConvertUnitObject(value, &out)) return out;
  out = nlohmann::json::object();
  for (const auto& [key, item] : value.items()) {
    const UnitSuffix* suffix = nullptr;
    for (const UnitSuffix& s : kSuffixes) {
      if (EndsWith(key, s.display)) {
        suffix = &s;
        break;
      }
    }
    if (suffix == nullptr || !HoldsNumber(item)) {
      out[key] = Convert(item);
      continue;
    }
    const std::string si_key =
        key.substr(0, key.size() - std::string(suffix->display).size()) + suffix->si;
    out[si_key] = Scaled(Convert(item), suffix->scale);
  }
  return out;
}

}  // namespace

nlohmann::json DetailsInSi(const nlohmann::json& details) { return Convert(details); }

}  // namespace mavloc
