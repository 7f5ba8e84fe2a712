#include "evaluation/estimator_option_ranges.h"

namespace mavloc {

void CheckEstimatorOptionValues(const EstimatorEntry& entry, const EstimatorOptions& given) {
  entry.create(given);  // the estimator is dropped: only its checks are wanted
}

}  // namespace mavloc
