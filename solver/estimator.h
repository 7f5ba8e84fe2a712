// The estimator interface (DESIGN.md, "Estimators"): every estimator consumes the time-ordered
// dataset and returns named quantities over time. A registry maps names to factories so that the
// CLI and the reports list estimators without special cases.
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "core/dataset.h"
#include "core/estimate.h"

namespace mavloc {

struct EstimatorEntry;

// Estimator options as key=value text (from `--option key=value`), parsed by each estimator.
class EstimatorOptions {
 public:
  EstimatorOptions() = default;
  explicit EstimatorOptions(std::map<std::string, std::string> values)
      : values_(std::move(values)) {}
  void Set(const std::string& key, const std::string& value) { values_[key] = value; }
  bool Has(const std::string& key) const;
  // Typed getters; throw InputError naming the option when the text does not parse.
  double GetDouble(const std::string& key, double fallback) const;
  int GetInt(const std::string& key, int fallback) const;
  bool GetBool(const std::string& key, bool fallback) const;
  std::string GetString(const std::string& key, const std::string& fallback) const;
  const std::map<std::string, std::string>& values() const { return values_; }
  // Set by the registry's create (EstimatorEntry): Has and the getters then throw std::logic_error
  // for a key the entry does not declare, so that the declared list (which rejects unknown
  // `--option` keys up front) cannot silently fall behind the code.
  void DeclareFor(const EstimatorEntry* entry) { declared_for_ = entry; }

 private:
  void RequireDeclared(const std::string& key) const;
  std::map<std::string, std::string> values_;
  const EstimatorEntry* declared_for_ = nullptr;
};

// Whether an estimator can run on a dataset, and if not, why.
struct Applicability {
  bool applies = false;
  std::string reason;  // what is missing when !applies
  static Applicability Yes() { return {true, ""}; }
  static Applicability No(std::string why) { return {false, std::move(why)}; }
};

class Estimator {
 public:
  virtual ~Estimator() = default;
  virtual std::string name() const = 0;
  virtual Applicability AppliesTo(const Dataset& dataset) const = 0;
  // Runs on the whole dataset. Degenerate frames are counted in Estimate::failures, never thrown.
  virtual Estimate Run(const Dataset& dataset) = 0;
};

struct EstimatorEntry {
  std::string name;
  std::string description;  // one line: paper, equations, what it needs
  // Creates the estimator; throws InputError for an option the entry does not declare
  // (CheckEstimatorOptions) or a value the estimator refuses.
  std::function<std::unique_ptr<Estimator>(const EstimatorOptions&)> create;
  std::set<std::string> options;             // every option key the estimator reads
  std::vector<std::string> option_prefixes;  // "seed.": keys handed on to another estimator

  bool HasOption(const std::string& key) const;
};

// Throws InputError "--option KEY=VALUE: estimator NAME has no option 'KEY' (known: ...)" for the
// first option the entry does not declare.
void CheckEstimatorOptions(const EstimatorEntry& entry, const EstimatorOptions& options);

// All registered estimators, in a fixed order (solver/estimator_registry.cc lists them).
const std::vector<EstimatorEntry>& EstimatorRegistry();
const EstimatorEntry* FindEstimator(const std::string& name);

}  // namespace mavloc
