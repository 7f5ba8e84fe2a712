#include "frontends/features/gyro_rotation.h"

#include <algorithm>

#include "core/rotation.h"

namespace mavloc {

std::optional<Eigen::Quaterniond> GyroRotation(const std::vector<ImuSample>& samples, TimeNs t0_ns,
                                               TimeNs t1_ns, const Eigen::Vector3d& b_g) {
  if (samples.empty() || t1_ns < t0_ns || samples.front().t_ns > t0_ns ||
      samples.back().t_ns < t1_ns)
    return std::nullopt;
  // The last sample at or before t0.
  auto it = std::upper_bound(samples.begin(), samples.end(), t0_ns,
                             [](TimeNs t, const ImuSample& s) { return t < s.t_ns; });
  size_t i = static_cast<size_t>(std::distance(samples.begin(), it)) - 1;
  Eigen::Quaterniond q_B0_B = Eigen::Quaterniond::Identity();
  TimeNs t = t0_ns;
  while (t < t1_ns) {
    const TimeNs next = i + 1 < samples.size() ? std::min(samples[i + 1].t_ns, t1_ns) : t1_ns;
    const double dt_s = NsToSeconds(next - t);
    q_B0_B = q_B0_B * ExpQuaternion((samples[i].gyro_rad_s - b_g) * dt_s);
    t = next;
    ++i;
  }
  return q_B0_B.normalized();
}

}  // namespace mavloc
