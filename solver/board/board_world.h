// The papers' tag estimators on a board log (MapFrame::kBoard: the map is in the board frame M and
// the gravity direction in M is unknown, DESIGN.md). Their papers assume a gravity-aligned world
// W, so each of them (tag-pnp, tag-ekf, pnp, upright-2p, pixhawk-kf) runs through the same steps:
//   1. per-frame PnP of tags0 on the map as given, T_M_B (solver/board/frame_pnp.h), over an
//      initial window: the first gravity_init_s seconds (default 2) from the first frame that sees
//      gravity_min_tags (2) tags of the map, using only such frames; when that window fails, the
//      next one;
//   2. the up direction in M from those poses and the IMU over the window, by a least-squares fit
//      of the positions p_0 + v_0 t + g_M t^2 / 2 + double integral of R_M_B a_m
//      (board_gravity_from_positions.h), and from it T_W_M in the convention of
//      core/board_frame.h (origin of M, z up, x = board x projected);
//   3. a copy of the dataset whose map is expressed in W (TagInfo::T_W_T = T_W_M T_M_T, landmarks
//      and plane likewise; frame = kWorld);
//   4. the estimator's own algorithm, unchanged, on that copy;
//   5. its estimate (T_W_B in that W) with T_W_M, the quantities board_roll, board_pitch (constant
//      columns, rad) and Estimate::parameters["board_roll"], ["board_pitch"].
// Only the window's data enter T_W_M, so a causal filter that starts at the window's end
// (tag-ekf, pixhawk-kf) stays causal. On a world map (kWorld) RunInWorldFrame runs the estimator
// directly on the dataset, and nothing is added.
#pragma once

#include <Eigen/Core>
#include <functional>
#include <optional>
#include <string>

#include "core/dataset.h"
#include "core/estimate.h"
#include "core/pose.h"
#include "solver/estimator.h"

namespace mavloc {

struct BoardInitOptions {
  double gravity_init_s = 2.0;  // length of the initialisation window (option gravity_init_s)
  int min_poses = 5;            // PnP poses needed inside the window
  // Frames used: those that see at least this many map tags (option gravity_min_tags; fewer when
  // no frame sees that many, frame_pnp.h ResolveMinTags). A single small marker gives PnP tilts
  // off by several degrees (1 px on a 90 px marker), and the tilt of the poses is what the
  // gravity direction is measured against.
  int min_tags = 2;
};
// Reads the option gravity_init_s (> 0); throws InputError when malformed.
BoardInitOptions ParseBoardInitOptions(const EstimatorOptions& options);

// Why the board initialisation cannot run on a dataset (imu0, tags0, a camera), or empty when it
// can or when the map is already in W.
std::string BoardWorldMissing(const Dataset& dataset);

// A map given in M, expressed in W: tags T_W_T = T_W_M T_M_T, landmarks p_W = T_W_M p_M, the
// plane's normal rotated and its offset moved; frame = kWorld.
WorldMap MapInWorld(const WorldMap& map_M, const Pose& T_W_M);

struct BoardWorld {
  Dataset dataset;  // the input with its map in W (frame = kWorld)
  Pose T_W_M;
  Eigen::Vector3d up_M = Eigen::Vector3d::UnitZ();  // unit
  TimeNs t_init_begin_ns = 0;  // the window the gravity direction was estimated over
  TimeNs t_init_end_ns = 0;
  int num_init_poses = 0;  // PnP poses inside the window
};

// Steps 1-3 above. nullopt (with *why) when the window has too few PnP poses or the gravity
// estimate fails.
std::optional<BoardWorld> InitializeBoardWorld(const Dataset& dataset,
                                               const BoardInitOptions& options, std::string* why);

// Step 5: sets estimate->T_W_M, appends the constant columns board_roll and board_pitch to its
// quantities and the parameters board_roll, board_pitch (rad).
void AddBoardFrameOutputs(const BoardWorld& board, Estimate* estimate);

// The whole wrapper: on a world map, run(dataset, nullptr); on a board map, InitializeBoardWorld,
// run(world copy, &board) and AddBoardFrameOutputs. A failed initialisation gives an empty
// estimate whose failures say why ("gravity initialisation: ...").
using WorldFrameRun = std::function<Estimate(const Dataset& dataset_W, const BoardWorld* board)>;
Estimate RunInWorldFrame(const Dataset& dataset, const BoardInitOptions& options,
                         const WorldFrameRun& run);

}  // namespace mavloc
