// The IMU gap policy of every estimator that integrates the IMU (core/imu_gaps.h). Option
// imu_gaps:
//   refuse (default)  a stream with gaps is not estimated; the reason names the gaps and the option
//   reset             the estimator restarts after each gap: it runs on each gap-free segment as on
//                     a dataset of its own, and the estimates are joined (the estimate's parameter
//                     "imu_gap_restarts" counts the restarts; segments it cannot run on are counted
//                     as failures with their reason)
// The registry wraps these estimators in an ImuGapGuard, so every command applies the same policy.
#pragma once

#include <functional>
#include <memory>
#include <string>

#include "solver/estimator.h"

namespace mavloc {

constexpr const char* kImuGapsOption = "imu_gaps";

class ImuGapGuard : public Estimator {
 public:
  using Factory = std::function<std::unique_ptr<Estimator>()>;
  // Throws InputError when the options' imu_gaps is neither refuse nor reset.
  ImuGapGuard(Factory create, const EstimatorOptions& options);

  std::string name() const override { return inner_->name(); }
  Applicability AppliesTo(const Dataset& dataset) const override;
  Estimate Run(const Dataset& dataset) override;

 private:
  Factory create_;
  std::unique_ptr<Estimator> inner_;
  bool reset_ = false;
};

}  // namespace mavloc
