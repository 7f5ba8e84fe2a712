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

// The stamps of n frames at 6 Hz.
std::vector<double> Times(size_t n) {
  std::vector<double> times_s;
  for (size_t k = 0; k < n; ++k) times_s.push_back(static_cast<double>(k) / 6.0);
  return times_s;
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
  EXPECT_EQ(Refused(NeighbourGateRefusals(Times(positions_W.size()), positions_W, options)),
            outliers);
}

TEST(NeighbourGate, OffTooFewFramesOrAWideGateRefuseNothing) {
  Rng rng(11);
  std::vector<Eigen::Vector3d> positions_W = CircleWithNoise(rng);
  NeighbourGateOptions tight;
  tight.gate_m = 0.3;
  EXPECT_TRUE(Refused(NeighbourGateRefusals(Times(positions_W.size()), positions_W, tight))
                  .empty());  // ends included
  positions_W[40] += Eigen::Vector3d(0.5, 0.0, 0.0);
  NeighbourGateOptions off;
  off.gate_m = 0.0;
  EXPECT_TRUE(Refused(NeighbourGateRefusals(Times(positions_W.size()), positions_W, off)).empty());
  NeighbourGateOptions wide;
  wide.gate_m = 0.7;
  EXPECT_TRUE(Refused(NeighbourGateRefusals(Times(positions_W.size()), positions_W, wide)).empty());
  EXPECT_EQ(Refused(NeighbourGateRefusals(Times(positions_W.size()), positions_W, tight)),
            std::set<size_t>{40});
  // Two frames: each is an end.
  const std::vector<Eigen::Vector3d> two = {Eigen::Vector3d::Zero(), Eigen::Vector3d(5, 0, 0)};
  EXPECT_TRUE(Refused(NeighbourGateRefusals(Times(two.size()), two, tight)).empty());
  EXPECT_TRUE(NeighbourGateRefusals({}, {}, tight).empty());
}

// The median holds while fewer than half of the window is wrong: a run of 12 outliers (more than
// half of the 20 neighbours of the frames inside it) is not caught in its middle, which the header
// states; frames far from it are not touched.
TEST(NeighbourGate, ARunLongerThanHalfTheWindowIsNotCaught) {
  Rng rng(3);
  std::vector<Eigen::Vector3d> positions_W = CircleWithNoise(rng);
  for (size_t k = 100; k < 112; ++k) positions_W[k] += Eigen::Vector3d(0.0, 0.0, 1.0);
  NeighbourGateOptions options;
  options.window_s = 0.0;  // the 20 frames alone bound the window
  const std::set<size_t> refused =
      Refused(NeighbourGateRefusals(Times(positions_W.size()), positions_W, options));
  EXPECT_FALSE(refused.count(105));
  EXPECT_FALSE(refused.count(106));
  for (const size_t k : refused) EXPECT_TRUE(k >= 90 && k < 122) << k;
}

// Tags seen in short runs seconds apart: without a bound in time, the frames at the start of a run
// are compared with the previous run, metres away, and refused; with the window they have no
// neighbour on that side and are kept, while an outlier inside a run is still refused.
TEST(NeighbourGate, RunsSecondsApartAreNotComparedAcrossTheGap) {
  Rng rng(5);
  std::vector<double> times_s;
  std::vector<Eigen::Vector3d> positions_W;
  for (int run = 0; run < 3; ++run) {
    const Eigen::Vector3d start_W(4.0 * (run % 2), 0.0, 1.0);  // there and back
    for (int k = 0; k < 8; ++k) {  // 8 frames at 5 Hz, 0.2 m/s, then 20 s without tags
      times_s.push_back(20.0 * run + 0.2 * k);
      positions_W.push_back(start_W + Eigen::Vector3d(0.04 * k, 0.0, 0.0) +
                            0.01 * rng.GaussianVector<3>());
    }
  }
  positions_W[12] += Eigen::Vector3d(0.0, 1.0, 0.0);  // inside the second run
  NeighbourGateOptions unbounded;
  unbounded.window_s = 0.0;
  EXPECT_GT(Refused(NeighbourGateRefusals(times_s, positions_W, unbounded)).size(), 4u);
  const NeighbourGateOptions defaults;
  EXPECT_EQ(Refused(NeighbourGateRefusals(times_s, positions_W, defaults)), std::set<size_t>{12});
  EXPECT_THROW(NeighbourGateRefusals({0.0}, positions_W, defaults), std::invalid_argument);
}

}  // namespace
}  // namespace mavloc
