// NEES accumulation (evaluation/crlb/consistency.h) when the estimate's stamps are not on the
// ground-truth rows (marker-board-flight: 30 Hz frames, 200 Hz truth): the truth is interpolated,
// so a known error gives its exact NEES at every frame and no frame is left out. Before the fix the
// next truth row (up to 3.3 ms later) was taken or the frame dropped: the smoother's ANEES on
// marker-board-flight was 5.5 with 1111 of 1666 frames.
#include <gtest/gtest.h>

#include "core/dataset.h"
#include "core/estimate.h"
#include "core/quantities.h"
#include "evaluation/crlb/consistency.h"

namespace mavloc {
namespace {

TEST(CrlbConsistency, TruthIsInterpolatedBetweenRows) {
  // Truth at 200 Hz: moving along x at 0.5 m/s, turning about z at 0.3 rad/s.
  Dataset dataset;
  const TimeNs start = SecondsToNs(1000.0);
  for (int i = 0; i <= 400; ++i) {
    GroundTruthState s;
    s.t_ns = start + i * 5'000'000;
    const double t = 0.005 * i;
    s.T_W_B = Pose(Eigen::Quaterniond(Eigen::AngleAxisd(0.3 * t, Eigen::Vector3d::UnitZ())),
                   Eigen::Vector3d(0.5 * t, 0.0, 1.0));
    dataset.ground_truth.push_back(s);
  }
  // Estimate at 30 Hz with a 1 mm error along y and sigma 1 mm on every axis: NEES = 1.
  Estimate estimate;
  estimate.covariance_names = PoseQuantityNames(false);
  int frames = 0;
  for (int k = 0; k < 60; ++k) {
    const TimeNs t_ns = start + k * 1'000'000'000LL / 30;
    const double t = NsToSeconds(t_ns - start);
    const Pose truth(Eigen::Quaterniond(Eigen::AngleAxisd(0.3 * t, Eigen::Vector3d::UnitZ())),
                     Eigen::Vector3d(0.5 * t, 0.0, 1.0));
    estimate.poses.push_back({t_ns, Pose(truth.q, truth.p + Eigen::Vector3d(0.0, 1e-3, 0.0))});
    Eigen::MatrixXd P = Eigen::MatrixXd::Identity(6, 6) * 1e-6;
    estimate.covariances.push_back({t_ns, P});
    ++frames;
  }
  NeesAccumulator nees;
  ASSERT_TRUE(AccumulateNees(dataset, estimate, &nees));
  EXPECT_EQ(static_cast<int>(nees.position.size()), frames);
  EXPECT_EQ(static_cast<int>(nees.attitude.size()), frames);
  for (const auto& [t, cell] : nees.position) EXPECT_NEAR(cell.first, 1.0, 1e-6) << t;
  // Attitude: no error up to the slerp's interpolation of a constant-rate turn (exact).
  for (const auto& [t, cell] : nees.attitude) EXPECT_NEAR(cell.first, 0.0, 1e-6) << t;
}

}  // namespace
}  // namespace mavloc
