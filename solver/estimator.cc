#include "solver/estimator.h"

#include <stdexcept>

#include "core/errors.h"
#include "core/key_values.h"

namespace mavloc {

void EstimatorOptions::RequireDeclared(const std::string& key) const {
  if (declared_for_ && !declared_for_->HasOption(key))
    throw std::logic_error("estimator " + declared_for_->name + " reads option '" + key +
                           "' that its entry in solver/estimator_registry.cc does not declare");
}

bool EstimatorOptions::Has(const std::string& key) const {
  RequireDeclared(key);
  return values_.count(key) > 0;
}
double EstimatorOptions::GetDouble(const std::string& key, double fallback) const {
  RequireDeclared(key);
  return GetDoubleSetting(values_, key, fallback);
}
int EstimatorOptions::GetInt(const std::string& key, int fallback) const {
  RequireDeclared(key);
  return GetIntSetting(values_, key, fallback);
}
bool EstimatorOptions::GetBool(const std::string& key, bool fallback) const {
  RequireDeclared(key);
  return GetBoolSetting(values_, key, fallback);
}
std::string EstimatorOptions::GetString(const std::string& key, const std::string& fallback) const {
  RequireDeclared(key);
  return GetStringSetting(values_, key, fallback);
}

bool EstimatorEntry::HasOption(const std::string& key) const {
  if (options.count(key)) return true;
  for (const auto& prefix : option_prefixes)
    if (key.size() > prefix.size() && key.rfind(prefix, 0) == 0) return true;
  return false;
}

void CheckEstimatorOptions(const EstimatorEntry& entry, const EstimatorOptions& options) {
  for (const auto& [key, value] : options.values()) {
    if (entry.HasOption(key)) continue;
    std::string known;
    for (const auto& k : entry.options) known += (known.empty() ? "" : ", ") + k;
    for (const auto& p : entry.option_prefixes) known += (known.empty() ? "" : ", ") + p + "KEY";
    throw InputError("--option " + key + "=" + value + ": estimator " + entry.name +
                     " has no option '" + key + "' (known: " + (known.empty() ? "none" : known) +
                     ")");
  }
}

const EstimatorEntry* FindEstimator(const std::string& name) {
  for (const auto& entry : EstimatorRegistry()) {
    if (entry.name == name) return &entry;
  }
  return nullptr;
}

}  // namespace mavloc
