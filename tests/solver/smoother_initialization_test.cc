// Smoother initialization from a seed estimator's poses: seeded keyframes take the seed, keyframes
// where the seed failed are bridged by the IMU, forwards from the previous keyframe and backwards
// before the first seed pose.
#include "solver/smoother/smoother_initialization.h"

#include <gtest/gtest.h>

#include "core/rotation.h"
#include "tests/analytic_motion.h"

namespace mavloc {
namespace {

using testing::AnalyticMotion;

Pose TruePose(double t) {
  return Pose(QuaternionFromEuler(AnalyticMotion::Angles(t)), AnalyticMotion::Position(t));
}

TEST(SmootherInitialization, BridgesSeedGapsForwardsAndBackwardsWithTheImu) {
  Dataset dataset;
  dataset.imu.samples = testing::SimulateAnalyticImu(200.0, 4.0, ImuBiases{});
  std::vector<TimeNs> times;
  for (int k = 0; k <= 30; ++k) times.push_back(SecondsToNs(0.1 * k));
  // The seed (exact here) starts at 1.0 s and misses 2.0 .. 2.5 s.
  std::vector<StampedPose> seed;
  for (int k = 10; k <= 30; ++k)
    if (k < 20 || k > 25) seed.push_back({times[k], TruePose(0.1 * k)});

  const SmootherInitialization init = InitializeFromSeed(dataset, times, seed);
  ASSERT_EQ(init.keyframes.size(), times.size());
  EXPECT_EQ(init.failures.at("keyframe before the first seed pose (bridged backwards)"), 10);
  EXPECT_EQ(init.failures.at("no seed pose (bridged by IMU prediction)"), 6);
  // With an exact IMU, a bridged keyframe inherits only the velocity error of the seeded keyframe
  // it starts from (finite differences of the seed positions), linearly in the elapsed time.
  auto velocity_error = [&](int k) {
    return (init.keyframes[k].state.v_W - AnalyticMotion::Velocity(0.1 * k)).norm();
  };
  for (int k = 0; k <= 30; ++k) {
    const double t = 0.1 * k;
    const ImuKeyframeState& s = init.keyframes[k].state;
    EXPECT_EQ(init.keyframes[k].t_ns, times[k]);
    EXPECT_EQ(init.seeded[k], k >= 10 && (k < 20 || k > 25)) << k;
    double tolerance_m = 1e-12;                                                   // the seed
    if (k < 10) tolerance_m = 1e-6 + velocity_error(10) * (1.0 - t);              // backwards
    if (k >= 20 && k <= 25) tolerance_m = 1e-6 + velocity_error(19) * (t - 1.9);  // forwards
    EXPECT_LT((s.p_W - AnalyticMotion::Position(t)).norm(), tolerance_m) << k;
    EXPECT_LT(RotationAngleBetween(s.q_W_B, TruePose(t).q), 1e-7) << k;
  }
  EXPECT_GT(velocity_error(10), 1e-3);  // the bound above is not vacuous
}

TEST(SmootherInitialization, BackwardPredictionFromTheTrueStateIsExact) {
  Dataset dataset;
  dataset.imu.samples = testing::SimulateAnalyticImu(200.0, 3.0, ImuBiases{});
  const std::vector<TimeNs> times = {SecondsToNs(0.5), SecondsToNs(1.0), SecondsToNs(2.5)};
  SmootherInitialization init;
  SmootherKeyframe last;
  last.t_ns = times.back();
  last.state.q_W_B = TruePose(2.5).q;
  last.state.p_W = AnalyticMotion::Position(2.5);
  last.state.v_W = AnalyticMotion::Velocity(2.5);
  init.keyframes.push_back(last);
  init.seeded.push_back(true);
  BridgeBackwards(dataset, times, &init);
  ASSERT_EQ(init.keyframes.size(), 3u);
  for (size_t k = 0; k < 2; ++k) {
    const double t = NsToSeconds(times[k]);
    const ImuKeyframeState& s = init.keyframes[k].state;
    EXPECT_LT((s.p_W - AnalyticMotion::Position(t)).norm(), 1e-6) << k;
    EXPECT_LT((s.v_W - AnalyticMotion::Velocity(t)).norm(), 1e-6) << k;
    EXPECT_LT(RotationAngleBetween(s.q_W_B, TruePose(t).q), 1e-8) << k;
  }
}

}  // namespace
}  // namespace mavloc
