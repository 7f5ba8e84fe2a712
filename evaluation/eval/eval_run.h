// The runs of `mavloc eval`: each estimate file (or each run of a folder of runs) evaluated
// against the ground truth by the one trajectory-error engine (evaluation/trajectory_evaluation.h),
// KITTI files without stamps associated by index as evo does, and the estimate mapped into the
// truth's frame by the alignment for the figures.
#pragma once

#include <string>
#include <vector>

#include "datasets/io/trajectory_formats/trajectory_format.h"
#include "evaluation/trajectory_evaluation.h"

namespace mavloc {

struct EvalRun {
  int run = 0;  // 1..n in a runs folder, 0 for a single file
  std::string file;
  TrajectoryReadReport input;
  bool by_index = false;  // KITTI without times: associated by index (evo)
  TrajectoryEvaluation evaluation;
  std::vector<StampedPose>
      aligned_estimate;  // in the truth's frame, time offset applied (or empty)
};

struct EvalEstimate {
  std::string label;
  std::string source;  // the --est argument (file or folder)
  bool is_folder = false;
  std::vector<EvalRun> runs;
};

struct EvalReport {
  TrajectoryReadReport truth;
  std::vector<StampedPose> truth_poses;
  EvaluationProtocol protocol;  // as resolved (relative lengths filled in)
  bool relative_lengths_given = false;
  std::vector<EvalEstimate> estimates;
};

// Evaluates one run; throws InputError naming the estimate file when nothing can be computed (the
// ground truth was checked to have two poses), with the rows its reader dropped, if any. The
// aligned estimate (for the report's files) is kept only when asked for.
EvalRun EvaluateRun(const std::string& file, const LoadedTrajectory& estimate,
                    const LoadedTrajectory& truth, const EvaluationProtocol& protocol,
                    const std::string& truth_path, bool keep_aligned_estimate);

// The estimate mapped by the evaluation's alignment into the truth's frame, stamps shifted by the
// time offset.
std::vector<StampedPose> AlignedEstimate(const std::vector<StampedPose>& estimate,
                                         const TrajectoryEvaluation& e, double time_offset_s);

}  // namespace mavloc
