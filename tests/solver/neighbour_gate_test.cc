// The check across frames (solver/pose/neighbour_gate.h): on a moving trajectory with centimetre
// noise, isolated outliers and a short run of them are refused and nothing else, next to the ends
// too; the clean trajectory, the gate off, too few frames and a gate wider than the outliers
// refuse nothing.
#include "solver/pose/neighbour_gate.h"

#include <gtest/gtest.h>

#include <set>

#include "core/random.h"

namespace mavloc {
namespace {

// 200 frames at 6 Hz of a vehicle at 1 m/s along a circle of 3 m radius, 1 cm noise per axis.
std::vector<Eigen::Vector3d> CircleWithNoise(Rng& rng) {
  std::vector<Eigen::Vector3d> positions_W;
  for (int k = 0; k < 200; ++k) {
    const double angle = (1.0 / 3.0) * (k / 6.0);  // speed / radius * time
    const Eigen::Vector3d noise = 0.01 * rng.GaussianVector<3>();
    positions_W.push_back(Eigen::Vector3d(3.0 * std::cos(angle), 3.0 * std::sin(angle), 1.5) +
                          noise);
  }
  return positions_W;
}

std::set<size_t> Refused(const std::vector<bool>& refused) {
  std::set<size_t> out;
  for (size_t k = 0; k < refused.size(); ++k)
    if (refused[k]) out.insert(k);
  return out;
}

TEST(NeighbourGate, RefusesIsolatedOutliersAndShortRunsOnly) {
  Rng rng(7);
  std::vector<Eigen::Vector3d> positions_W = CircleWithNoise(rng);
  const std::set<size_t> outliers = {1, 17, 60, 61, 62, 130, 198};  // near the ends, a run of 3
  for (const size_t k : outliers)
    positions_W[k] += Eigen::Vector3d(0.0, 0.6, -0.8) * (k % 2 == 0 ? 1.0 : -1.0);  // 1 m away
  NeighbourGateOptions options;
  options.gate_m = 0.3;
  EXPECT_EQ(Refused(NeighbourGateRefusals(positions_W, options)), outliers);
}

TEST(NeighbourGate, OffTooFewFramesOrAWideGateRefuseNothing) {
  Rng rng(11);
  std::vector<Eigen::Vector3d> positions_W = CircleWithNoise(rng);
  NeighbourGateOptions tight;
  tight.gate_m = 0.3;
  EXPECT_TRUE(Refused(NeighbourGateRefusals(positions_W, tight)).empty());  // ends included
  positions_W[40] += Eigen::Vector3d(0.5, 0.0, 0.0);
  NeighbourGateOptions off;
  EXPECT_TRUE(Refused(NeighbourGateRefusals(positions_W, off)).empty());
  NeighbourGateOptions wide;
  wide.gate_m = 0.7;
  EXPECT_TRUE(Refused(NeighbourGateRefusals(positions_W, wide)).empty());
  EXPECT_EQ(Refused(NeighbourGateRefusals(positions_W, tight)), std::set<size_t>{40});
  // Two frames: each is an end.
  const std::vector<Eigen::Vector3d> two = {Eigen::Vector3d::Zero(), Eigen::Vector3d(5, 0, 0)};
  EXPECT_TRUE(Refused(NeighbourGateRefusals(two, tight)).empty());
  EXPECT_TRUE(NeighbourGateRefusals({}, tight).empty());
}

// The median holds while fewer than half of the window is wrong: a run of 12 outliers (more than
// half of the 20 neighbours of the frames inside it) is not caught, which the header states.
TEST(NeighbourGate, ARunLongerThanHalfTheWindowIsNotCaught) {
  Rng rng(3);
  std::vector<Eigen::Vector3d> positions_W = CircleWithNoise(rng);
  for (size_t k = 100; k < 112; ++k) positions_W[k] += Eigen::Vector3d(0.0, 0.0, 1.0);
  NeighbourGateOptions options;
  options.gate_m = 0.3;
  const std::set<size_t> refused = Refused(NeighbourGateRefusals(positions_W, options));
  EXPECT_FALSE(refused.count(105));
  EXPECT_FALSE(refused.count(106));
}

}  // namespace
}  // namespace mavloc
