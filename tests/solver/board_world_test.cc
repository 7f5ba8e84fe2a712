// The board-frame wrapper of the tag estimators (solver/board/board_world.h): a map in M moved
// into W (tags, landmarks, plane), the PnP-window initial state (solver/board/pnp_initial_state.h)
// on an exact quadratic motion, and RunInWorldFrame's two paths (a world map passes straight
// through; a board map without IMU fails with a reason instead of running in M).
#include "solver/board/board_world.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/board_frame.h"
#include "core/random.h"
#include "core/rotation.h"
#include "core/tag_geometry.h"
#include "solver/board/pnp_initial_state.h"

namespace mavloc {
namespace {

Pose RandomPose(Rng& rng) {
  const Eigen::Vector3d phi{rng.Uniform(-2, 2), rng.Uniform(-2, 2), rng.Uniform(-2, 2)};
  return Pose{Eigen::Matrix3d(ExpSO3(phi)),
              Eigen::Vector3d{rng.Uniform(-3, 3), rng.Uniform(-3, 3), rng.Uniform(-3, 3)}};
}

TEST(MapInWorld, MovesTagsLandmarksAndPlaneRigidly) {
  Rng rng(7);
  for (int trial = 0; trial < 20; ++trial) {
    WorldMap map_M;
    map_M.frame = MapFrame::kBoard;
    for (int id = 0; id < 4; ++id) map_M.tags[id] = {id, 0.1 + 0.05 * id, RandomPose(rng)};
    map_M.landmarks_W[3] = Eigen::Vector3d{rng.Uniform(-1, 1), rng.Uniform(-1, 1), 0.5};
    const Eigen::Vector3d n_M = Eigen::Vector3d(rng.Uniform(-1, 1), 0.3, 1.0).normalized();
    map_M.plane = Plane{n_M, 0.7};
    const Pose T_W_M = RandomPose(rng);

    const WorldMap map_W = MapInWorld(map_M, T_W_M);
    EXPECT_EQ(map_W.frame, MapFrame::kWorld);
    for (const auto& [id, tag] : map_M.tags) {
      const auto corners_M = TagCornersInWorld(tag);
      const auto corners_W = TagCornersInWorld(map_W.tags.at(id));
      for (int k = 0; k < 4; ++k) EXPECT_LT((corners_W[k] - T_W_M * corners_M[k]).norm(), 1e-12);
      EXPECT_EQ(map_W.tags.at(id).size_m, tag.size_m);
    }
    EXPECT_LT((map_W.landmarks_W.at(3) - T_W_M * map_M.landmarks_W.at(3)).norm(), 1e-12);
    // A point of the plane in M is on the plane in W.
    const Eigen::Vector3d p_M = n_M * 0.7 + n_M.unitOrthogonal() * 1.3;
    EXPECT_NEAR(map_W.plane->n_W.dot(T_W_M * p_M), map_W.plane->d_m, 1e-12);
    EXPECT_NEAR(map_W.plane->n_W.norm(), 1.0, 1e-12);
  }
}

TEST(PnpInitialState, QuadraticMotionGivesTheExactVelocityAtTheLastPose) {
  const Eigen::Vector3d a(0.4, -0.2, 1.1), b(0.3, 0.5, -0.7), c(-0.6, 0.2, 0.9);
  std::vector<StampedPose> poses;
  for (int k = 0; k <= 40; ++k) {  // 20 Hz over 2 s
    const double t = 0.05 * k;
    poses.push_back({SecondsToNs(t), Pose(Eigen::Quaterniond::Identity(), a + b * t + c * t * t)});
  }
  const auto state = InitialStateFromPoses(poses, 1.0);
  ASSERT_TRUE(state.has_value());
  EXPECT_EQ(state->t_ns, poses.back().t_ns);
  EXPECT_EQ(state->num_poses_fitted, 21);
  EXPECT_LT((state->v_W - (b + 2.0 * c * 2.0)).norm(), 1e-9);
  // One pose: zero velocity; two: the finite difference; none: nullopt.
  EXPECT_EQ(InitialStateFromPoses({poses[3]})->v_W, Eigen::Vector3d::Zero());
  EXPECT_LT((InitialStateFromPoses({poses[3], poses[4]})->v_W -
             (poses[4].T_W_B.p - poses[3].T_W_B.p) / 0.05)
                .norm(),
            1e-9);
  EXPECT_FALSE(InitialStateFromPoses({}).has_value());
}

TEST(RunInWorldFrame, WorldMapPassesThroughAndBoardMapWithoutImuFails) {
  Dataset dataset;
  dataset.map.tags[0] = {0, 0.2, Pose()};
  bool called = false;
  const Estimate world =
      RunInWorldFrame(dataset, BoardInitOptions(), [&](const Dataset& d, const BoardWorld* board) {
        called = true;
        EXPECT_EQ(&d, &dataset);
        EXPECT_EQ(board, nullptr);
        Estimate e;
        e.CountFailure("ran");
        return e;
      });
  EXPECT_TRUE(called);
  EXPECT_FALSE(world.T_W_M.has_value());
  EXPECT_EQ(world.failures.at("ran"), 1);

  dataset.map.frame = MapFrame::kBoard;
  called = false;
  const Estimate board =
      RunInWorldFrame(dataset, BoardInitOptions(), [&](const Dataset&, const BoardWorld*) {
        called = true;
        return Estimate();
      });
  EXPECT_FALSE(called);
  ASSERT_EQ(board.failures.size(), 1u);
  EXPECT_NE(board.failures.begin()->first.find("gravity initialisation"), std::string::npos);
  EXPECT_NE(board.failures.begin()->first.find("imu0"), std::string::npos);
  EXPECT_NE(BoardWorldMissing(dataset), "");
}

TEST(BoardFrameOutputs, ConstantTiltColumnsAndParameters) {
  BoardWorld board;
  board.up_M = Eigen::Vector3d(0.2, -0.9, 0.3).normalized();
  board.T_W_M = BoardToWorld(board.up_M);
  Estimate estimate;
  estimate.quantities = MakeQuantityTable({"x", "yaw"});
  estimate.quantities.Append(1, {0.5, 0.1});
  estimate.quantities.Append(2, {0.6, 0.2});
  AddBoardFrameOutputs(board, &estimate);
  const BoardTilt tilt = BoardTiltFromUp(board.up_M);
  ASSERT_TRUE(estimate.quantities.Has("board_roll"));
  EXPECT_EQ(estimate.quantities.units[estimate.quantities.Index("board_pitch")], "rad");
  for (double v : estimate.quantities.Column("board_roll")) EXPECT_EQ(v, tilt.roll_rad);
  for (double v : estimate.quantities.Column("board_pitch")) EXPECT_EQ(v, tilt.pitch_rad);
  EXPECT_EQ(estimate.quantities.Column("x")[1], 0.6);
  EXPECT_EQ(estimate.parameters.at("board_roll").value, tilt.roll_rad);
  EXPECT_EQ(estimate.parameters.at("board_pitch").unit, "rad");
  ASSERT_TRUE(estimate.T_W_M.has_value());
  EXPECT_LT((UpInBoard(estimate.T_W_M->R()) - board.up_M).norm(), 1e-12);
}

}  // namespace
}  // namespace mavloc
