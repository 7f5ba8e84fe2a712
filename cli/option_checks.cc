#include "cli/option_checks.h"

#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <optional>
#include <set>

#include "cli/commands.h"
#include "core/errors.h"
#include "core/number_text.h"
#include "datasets/scenarios/scenario.h"
#include "evaluation/estimator_option_ranges.h"

namespace mavloc::cli {

namespace {

std::string Short(const std::string& text) { return PrintableMessage(text, 60); }

// The whole text as a double (core/number_text.h: "1.5x", "", "0x10", " 1" and a NUL byte are
// refused; "inf", "nan" and "1e999" are numbers that are not finite), or nullopt.
std::optional<double> ParseDouble(const std::string& text) {
  const ParsedNumber<double> value = ParseDoubleText(text, NonFinite::kAllow);
  if (value.status == NumberTextStatus::kOverflow) return text[0] == '-' ? -HUGE_VAL : HUGE_VAL;
  if (!value.ok()) return std::nullopt;
  return value.value;
}

std::string Bounds(double min, bool min_open, double max, const std::string& unit) {
  return fmt::format("{}{}, {}]{}", min_open ? "(" : "[", min, max, unit.empty() ? "" : " " + unit);
}

CLI::Validator NumberValidator(double min, bool min_open, double max, const std::string& unit,
                               const std::string& description) {
  return CLI::Validator(
      [=](std::string& text) -> std::string {
        const auto value = ParseDouble(text);
        if (!value) return "'" + Short(text) + "' is not a number";
        if (!std::isfinite(*value)) return "'" + Short(text) + "' is not a finite number";
        if ((min_open ? !(*value > min) : !(*value >= min)) || !(*value <= max))
          return "'" + Short(text) + "' is outside " + Bounds(min, min_open, max, unit);
        return "";
      },
      description);
}

}  // namespace

CLI::Validator FiniteNumber() {
  const double inf = std::numeric_limits<double>::max();
  return NumberValidator(-inf, false, inf, "", "FINITE");
}

CLI::Validator PositiveFinite() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        const auto value = ParseDouble(text);
        if (!value) return "'" + Short(text) + "' is not a number";
        if (!std::isfinite(*value)) return "'" + Short(text) + "' is not a finite number";
        if (!(*value > 0.0)) return "'" + Short(text) + "' must be > 0";
        return "";
      },
      "POSITIVE");
}

CLI::Validator FiniteRange(double min, double max, const std::string& unit) {
  return NumberValidator(min, false, max, unit, "in " + Bounds(min, false, max, unit));
}

CLI::Validator PositiveAtMost(double max, const std::string& unit) {
  return NumberValidator(0.0, true, max, unit, "in " + Bounds(0.0, true, max, unit));
}

CLI::Validator WholeNumber(long long min, long long max) {
  return CLI::Validator(
      [=](std::string& text) -> std::string {
        const bool negative = !text.empty() && text[0] == '-';
        const std::string digits = negative ? text.substr(1) : text;
        if (digits.empty() || digits.find_first_not_of("0123456789") != std::string::npos)
          return "'" + Short(text) + "' is not a whole number";
        const ParsedNumber<long long> value = ParseIntegerText(text);
        if (!value.ok() || value.value < min || value.value > max)
          return fmt::format("'{}' is outside [{}, {}]", Short(text), min, max);
        return "";
      },
      fmt::format("in [{}, {}]", min, max));
}

CLI::Validator SeedNumber() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        if (text.empty() || text.find_first_not_of("0123456789") != std::string::npos)
          return "'" + Short(text) + "' is not a seed (a whole number 0 .. 18446744073709551615)";
        if (!ParseUnsignedText(text).ok())
          return "'" + Short(text) + "' is larger than the largest seed, 18446744073709551615";
        return "";
      },
      "SEED");
}

CLI::Validator OutputFile(bool parent_must_exist) {
  return CLI::Validator(
      [parent_must_exist](std::string& text) -> std::string {
        namespace fs = std::filesystem;
        if (text.empty()) return "an empty file name";
        if (text.back() == '/') return "'" + Short(text) + "' names a folder, not a file";
        std::error_code error;
        if (fs::is_directory(text, error)) return "'" + Short(text) + "' is a folder, not a file";
        const fs::path parent = fs::path(text).parent_path();
        if (parent_must_exist && !parent.empty() && !fs::is_directory(parent, error))
          return "'" + Short(text) + "': the folder '" + Short(parent.string()) +
                 "' does not exist";
        return "";
      },
      "FILE");
}

CLI::Validator OutputFolder() {
  return CLI::Validator(
      [](std::string& text) -> std::string { return text.empty() ? "an empty folder name" : ""; },
      "DIR");
}

CLI::Option* AddSeedOption(CLI::App* command, uint64_t* seed, const std::string& description) {
  return command->add_option("--seed", *seed, description)
      ->check(SeedNumber())
      ->capture_default_str();
}

CLI::Option* AddScenarioDurationOption(CLI::App* command, double* duration_s,
                                       const std::string& description) {
  return command
      ->add_option("--duration", *duration_s,
                   description + fmt::format(" (at most {} s)", kMaxScenarioDurationS))
      ->check(PositiveAtMost(kMaxScenarioDurationS, "s"));
}

std::map<std::string, EstimatorOptions> EstimatorOptionsFor(const std::vector<std::string>& items,
                                                            const std::vector<std::string>& names) {
  const std::set<std::string> run(names.begin(), names.end());
  std::map<std::string, EstimatorOptions> options;
  for (const auto& name : names) options[name];
  std::vector<std::string> global;
  for (const auto& item : items) {
    const auto colon = item.find(':');
    const auto eq = item.find('=');
    if (colon == std::string::npos || (eq != std::string::npos && eq < colon)) {
      global.push_back(item);
      continue;
    }
    const std::string name = item.substr(0, colon);
    const EstimatorEntry* entry = FindEstimator(name);
    if (!entry) {
      std::string known;
      for (const auto& e : EstimatorRegistry()) known += (known.empty() ? "" : ", ") + e.name;
      throw InputError("--option " + item + ": '" + name +
                       "' is not an estimator (known: " + known + ")");
    }
    if (!run.count(name)) {
      std::string listed;
      for (const auto& n : names) listed += (listed.empty() ? "" : ", ") + n;
      throw InputError("--option " + item + ": estimator " + name +
                       " is not part of this run (estimators: " + listed + ")");
    }
    for (const auto& [key, value] : ParseKeyValues({item.substr(colon + 1)}, "--option")) {
      EstimatorOptions one;
      one.Set(key, value);
      CheckEstimatorOptions(*entry, one);
      options[name].Set(key, value);
    }
  }
  for (const auto& [key, value] : ParseKeyValues(global, "--option")) {
    bool used = false;
    std::set<std::string> known;
    for (const auto& name : names) {
      const EstimatorEntry* entry = FindEstimator(name);
      if (!entry) continue;
      known.insert(entry->options.begin(), entry->options.end());
      if (!entry->HasOption(key)) continue;
      used = true;
      if (!options[name].Has(key)) options[name].Set(key, value);  // name:key=value wins
    }
    if (!used) {
      std::string list;
      for (const auto& k : known) list += (list.empty() ? "" : ", ") + k;
      if (list.size() > 600)
        list = fmt::format("{} options: `mavloc list --options`", known.size());
      throw InputError("--option " + key + "=" + value + ": no estimator of this run has option '" +
                       key + "' (known: " + list + ")");
    }
  }
  for (const auto& [name, given] : options)
    if (const EstimatorEntry* entry = FindEstimator(name))
      CheckEstimatorOptionValues(*entry, given);
  return options;
}

}  // namespace mavloc::cli
