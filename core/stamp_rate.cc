#include "core/stamp_rate.h"

#include <algorithm>

namespace mavloc {

double MedianRateHz(const std::vector<TimeNs>& t_ns) {
  if (t_ns.size() < 2) return 0.0;
  std::vector<TimeNs> dt;
  dt.reserve(t_ns.size() - 1);
  for (size_t i = 1; i < t_ns.size(); ++i) dt.push_back(t_ns[i] - t_ns[i - 1]);
  std::nth_element(dt.begin(), dt.begin() + dt.size() / 2, dt.end());
  const TimeNs median = dt[dt.size() / 2];
  return median > 0 ? 1e9 / static_cast<double>(median) : 0.0;
}

}  // namespace mavloc
