#include "evaluation/eval/eval_run.h"

#include <fmt/format.h>

#include "core/errors.h"

namespace mavloc {

namespace {

std::string StampSeconds(TimeNs t_ns) { return fmt::format("{:.3f}", NsToSeconds(t_ns)); }

}  // namespace

std::vector<StampedPose> AlignedEstimate(const std::vector<StampedPose>& estimate,
                                         const TrajectoryEvaluation& e, double time_offset_s) {
  std::vector<StampedPose> out;
  out.reserve(estimate.size());
  const Eigen::Quaterniond q_align(e.alignment.R);
  for (const auto& pose : estimate) {
    StampedPose aligned;
    aligned.t_ns = pose.t_ns + SecondsToNs(time_offset_s);
    aligned.T_W_B.p = e.alignment.Apply(pose.T_W_B.p);
    aligned.T_W_B.q = (q_align * pose.T_W_B.q).normalized();
    out.push_back(aligned);
  }
  return out;
}

EvalRun EvaluateRun(const std::string& file, const LoadedTrajectory& estimate,
                    const LoadedTrajectory& truth, const EvaluationProtocol& protocol,
                    const std::string& truth_path, bool keep_aligned_estimate) {
  EvalRun run;
  run.file = file;
  run.input = estimate.report;
  EvaluationProtocol p = protocol;
  if (!estimate.report.has_stamps || !truth.report.has_stamps) {
    // evo_ape/evo_rpe on KITTI pose files: no stamps, the i-th poses are compared.
    if (estimate.report.has_stamps != truth.report.has_stamps)
      throw InputError(file, 0, "",
                       fmt::format("{} has no stamps (KITTI without a times file) and {} has: give "
                                   "--gt-times/--est-times, or KITTI files for both (then "
                                   "associated by index, as evo does)",
                                   estimate.report.has_stamps ? truth_path : file,
                                   estimate.report.has_stamps ? file : truth_path));
    if (estimate.poses.size() != truth.poses.size())
      throw InputError(file, 0, "",
                       fmt::format("KITTI files without times are associated by index (as evo "
                                   "does), which needs as many poses as the ground truth: {} here, "
                                   "{} in {}",
                                   estimate.poses.size(), truth.poses.size(), truth_path));
    run.by_index = true;
    p.association = AssociationMode::kNearest;
    p.max_dt_s = 0.01;
    p.time_offset_s = 0.0;
  }
  const std::vector<StampedPose>& est = estimate.poses;
  const std::vector<StampedPose>& gt = truth.poses;
  std::string why;
  TrajectoryDiagnostics diagnostics;
  auto evaluation = EvaluateTrajectory(est, gt, p, &why, &diagnostics);
  if (!evaluation) {
    const PairCountDiagnostic& d = diagnostics.pair_count;
    if (d.pairs == 0)
      throw InputError(file, 0, "",
                       fmt::format("no estimate stamp overlaps the ground truth '{}' within {:g} s "
                                   "(estimate {} .. {} s, ground truth {} .. {} s, time offset "
                                   "{:g} s)",
                                   truth_path, p.max_dt_s, StampSeconds(est.front().t_ns),
                                   StampSeconds(est.back().t_ns), StampSeconds(gt.front().t_ns),
                                   StampSeconds(gt.back().t_ns), p.time_offset_s));
    const std::string fixes = DescribeRowFixes(estimate.report);
    throw InputError(file, 0, "",
                     "cannot evaluate: " + why + (fixes.empty() ? "" : " (note: " + fixes + ")"));
  }
  run.evaluation = std::move(*evaluation);
  run.estimate_span_s = NsToSeconds(est.back().t_ns - est.front().t_ns);
  if (keep_aligned_estimate)
    run.aligned_estimate = AlignedEstimate(est, run.evaluation, p.time_offset_s);
  return run;
}

EvalReport EvaluateInputs(LoadedTrajectory&& truth, const std::string& truth_path,
                          const std::vector<EvalInput>& inputs, EvaluationProtocol protocol,
                          const EvalOutputs& outputs) {
  protocol.keep_series = outputs.NeedsSeries();
  EvalReport report;
  report.truth = truth.report;
  report.relative_lengths_given = !protocol.relative_lengths_m.empty();
  for (const auto& input : inputs) {
    EvalEstimate estimate;
    estimate.label = input.label;
    estimate.source = input.source;
    estimate.is_folder = input.is_folder;
    for (size_t r = 0; r < input.runs.size(); ++r) {
      EvalRun run = EvaluateRun(input.runs[r].first, input.runs[r].second, truth, protocol,
                                truth_path, outputs.NeedsSeries());
      if (protocol.relative_lengths_m.empty())
        protocol.relative_lengths_m = run.evaluation.protocol.relative_lengths_m;
      run.run = input.is_folder ? static_cast<int>(r + 1) : 0;
      estimate.runs.push_back(std::move(run));
    }
    report.estimates.push_back(std::move(estimate));
  }
  report.protocol = protocol;
  report.truth_poses = std::move(truth.poses);
  return report;
}

}  // namespace mavloc
