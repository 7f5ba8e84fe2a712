// The rate of a logged stream from its stamps.
#pragma once

#include <vector>

#include "core/time.h"

namespace mavloc {

// The rate [Hz] from the median interval between consecutive stamps (robust to dropped samples);
// 0 for fewer than two stamps or a zero median.
double MedianRateHz(const std::vector<TimeNs>& t_ns);

}  // namespace mavloc
