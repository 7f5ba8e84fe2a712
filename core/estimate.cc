#include "core/estimate.h"

namespace mavloc {

int Estimate::FailureCount() const {
  int total = 0;
  for (const auto& [reason, count] : failures) total += count;
  return total;
}

int Estimate::RejectionCount() const {
  int total = 0;
  for (const auto& [reason, count] : rejections) total += count;
  return total;
}

}  // namespace mavloc
