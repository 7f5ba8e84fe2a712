// The rotation of the body between two times from the gyro alone: R_B0_B1 = prod_i Exp((w_i - b_g)
// dt_i) over the samples between t0 and t1 (each sample's rate held until the next one; the
// intervals cut at t0 and t1). The frontend uses it to predict where a track goes (a KLT start)
// and to hand the rotation to the 2-point RANSAC, which is then left with the translation only.
#pragma once

#include <Eigen/Geometry>
#include <optional>
#include <vector>

#include "core/imu.h"
#include "core/time.h"

namespace mavloc {

// nullopt when the samples do not cover [t0_ns, t1_ns] (no sample at or before t0, or none at or
// after t1) or t1 < t0.
std::optional<Eigen::Quaterniond> GyroRotation(
    const std::vector<ImuSample>& samples, TimeNs t0_ns, TimeNs t1_ns,
    const Eigen::Vector3d& b_g = Eigen::Vector3d::Zero());

}  // namespace mavloc
