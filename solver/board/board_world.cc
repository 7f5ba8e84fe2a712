#include "solver/board/board_world.h"

#include <algorithm>

#include "core/board_frame.h"
#include "core/errors.h"
#include "solver/board/board_gravity_from_positions.h"
#include "solver/board/frame_pnp.h"
#include "solver/pose/tags_camera.h"

namespace mavloc {

BoardInitOptions ParseBoardInitOptions(const EstimatorOptions& options) {
  BoardInitOptions out;
  out.gravity_init_s = options.GetDouble("gravity_init_s", out.gravity_init_s);
  out.min_tags = options.GetInt("gravity_min_tags", out.min_tags);
  if (out.min_tags < 1) throw InputError("", 0, "gravity_min_tags", "must be >= 1");
  if (!(out.gravity_init_s > 0.0))
    throw InputError("", 0, "gravity_init_s", "must be > 0 (seconds of the initial window)");
  return out;
}

std::string BoardWorldMissing(const Dataset& dataset) {
  if (dataset.map.frame != MapFrame::kBoard) return "";
  const std::string prefix = "board map: the gravity initialisation ";
  if (dataset.imu.samples.size() < 2) return prefix + "needs imu0 samples";
  if (dataset.tags.empty()) return prefix + "needs tags0 observations";
  const std::string camera = TagsCameraMissing(dataset);
  if (!camera.empty()) return prefix + camera;
  return "";
}

WorldMap MapInWorld(const WorldMap& map_M, const Pose& T_W_M) {
  WorldMap map_W = map_M;
  map_W.frame = MapFrame::kWorld;
  for (auto& [id, tag] : map_W.tags) tag.T_W_T = T_W_M * map_M.tags.at(id).T_W_T;
  for (auto& [id, p] : map_W.landmarks_W) p = T_W_M * map_M.landmarks_W.at(id);
  if (map_M.plane) {
    // n_M . p_M = d with p_M = R_M_W (p_W - p_W_M): (R_W_M n_M) . p_W = d + n_W . p_W_M.
    map_W.plane->n_W = T_W_M.R() * map_M.plane->n_W;
    map_W.plane->d_m = map_M.plane->d_m + map_W.plane->n_W.dot(T_W_M.p);
  }
  return map_W;
}

std::optional<BoardWorld> InitializeBoardWorld(const Dataset& dataset,
                                               const BoardInitOptions& options, std::string* why) {
  auto fail = [&](const std::string& reason) -> std::optional<BoardWorld> {
    if (why) *why = reason;
    return std::nullopt;
  };
  const std::string missing = BoardWorldMissing(dataset);
  if (!missing.empty()) return fail(missing);
  const int min_tags = ResolveMinTags(dataset, options.min_tags);
  const std::optional<TimeNs> t_first = FirstMapTagTime(dataset, min_tags);
  if (!t_first) return fail("no tags0 frame sees a tag of the map");
  // The first window [t_first, t_first + gravity_init_s]; when it fails (too few PnP poses, an
  // implausible gravity), the next one, and so on: the estimate then starts later.
  const std::vector<ImuSample>& imu = dataset.imu.samples;
  const TimeNs window_ns = SecondsToNs(options.gravity_init_s);
  std::string reason = "the tags are seen only after the IMU stream";
  std::string first_reason;
  std::vector<StampedPose> T_M_B;
  std::optional<Eigen::Vector3d> up_M;
  for (TimeNs t_begin = std::max(*t_first, imu.front().t_ns); !up_M && t_begin < imu.back().t_ns;
       t_begin += window_ns) {
    const TimeNs t_end = std::min(t_begin + window_ns, imu.back().t_ns);
    T_M_B = FramePnpPoses(dataset, t_begin, t_end, nullptr, min_tags);
    if (static_cast<int>(T_M_B.size()) < options.min_poses) {
      reason = std::to_string(T_M_B.size()) + " PnP poses in the window (need " +
               std::to_string(options.min_poses) + ")";
    } else {
      up_M = EstimateUpInBoardFromPositions(T_M_B, dataset.imu, T_M_B.front().t_ns,
                                            T_M_B.back().t_ns, &reason);
      if (up_M && (!up_M->allFinite() || up_M->norm() < 1e-9)) {
        up_M.reset();
        reason = "non-finite gravity direction";
      }
    }
    if (!up_M && first_reason.empty()) first_reason = reason;
  }
  if (!up_M) {
    return fail(first_reason.empty() ? reason
                                     : "first window: " + first_reason + "; no later one worked");
  }

  BoardWorld board;
  board.up_M = up_M->normalized();
  board.T_W_M = BoardToWorld(board.up_M);
  board.t_init_begin_ns = T_M_B.front().t_ns;
  board.t_init_end_ns = T_M_B.back().t_ns;
  board.num_init_poses = static_cast<int>(T_M_B.size());
  board.dataset = dataset;
  board.dataset.map = MapInWorld(dataset.map, board.T_W_M);
  return board;
}

void AddBoardFrameOutputs(const BoardWorld& board, Estimate* estimate) {
  estimate->T_W_M = board.T_W_M;
  const BoardTilt tilt = BoardTiltFromUp(board.up_M);
  QuantityTable& q = estimate->quantities;
  q.names.insert(q.names.end(), {"board_roll", "board_pitch"});
  q.units.insert(q.units.end(), {"rad", "rad"});
  for (auto& row : q.rows) row.insert(row.end(), {tilt.roll_rad, tilt.pitch_rad});
  estimate->parameters["board_roll"] = {tilt.roll_rad, std::nullopt, "rad"};
  estimate->parameters["board_pitch"] = {tilt.pitch_rad, std::nullopt, "rad"};
}

Estimate RunInWorldFrame(const Dataset& dataset, const BoardInitOptions& options,
                         const WorldFrameRun& run) {
  if (dataset.map.frame != MapFrame::kBoard) return run(dataset, nullptr);
  std::string why;
  const std::optional<BoardWorld> board = InitializeBoardWorld(dataset, options, &why);
  if (!board) {
    Estimate failed;
    failed.CountFailure("gravity initialisation: " + why);
    return failed;
  }
  Estimate estimate = run(board->dataset, &*board);
  AddBoardFrameOutputs(*board, &estimate);
  return estimate;
}

}  // namespace mavloc
