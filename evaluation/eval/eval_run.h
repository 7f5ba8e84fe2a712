// The runs of `mavloc eval`: each estimate file (or each run of a folder of runs) evaluated
// against the ground truth by the one trajectory-error engine (evaluation/trajectory_evaluation.h),
// KITTI files without stamps associated by index as evo does, and the estimate mapped into the
// truth's frame by the alignment for the figures. What is built depends on the outputs asked for
// (EvalOutputs): the per-pair series and the aligned estimates only for the report folder.
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
  double estimate_span_s = 0.0;  // first to last stamp of the estimate as read
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

// The outputs of one `mavloc eval`, and what they need built. The terminal table and report.json
// need each run's statistics alone; the report folder's files (the truth and each aligned estimate
// as TUM, errors_over_time.csv, relative_errors.csv) and its figures also need the per-pair and
// per-segment series and the aligned estimates, which on a million-pose truth take several times
// the time and memory of the statistics.
struct EvalOutputs {
  bool report_folder = false;  // --out DIR
  bool report_json = false;    // --json FILE
  bool NeedsSeries() const { return report_folder; }
};

// One --est as read: a file, or a folder of runs of one estimator.
struct EvalInput {
  std::string label, source;
  bool is_folder = false;
  std::vector<std::pair<std::string, LoadedTrajectory>> runs;  // file name, trajectory
};

// Every run of every input against the truth (EvaluateRun), with the series and aligned estimates
// that `outputs` need and no others (report.protocol.keep_series says whether they were built).
// rpg's default relative lengths, when protocol gives none, come from the first run and are used
// for every other one. The truth's poses are moved into the report.
EvalReport EvaluateInputs(LoadedTrajectory&& truth, const std::string& truth_path,
                          const std::vector<EvalInput>& inputs, EvaluationProtocol protocol,
                          const EvalOutputs& outputs);

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
