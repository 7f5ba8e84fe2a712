#include "evaluation/trajectory_evaluation.h"

#include <fmt/format.h>

#include <cmath>
#include <future>

#include "core/heap_release.h"
#include "core/numbers.h"
#include "core/rotation.h"

namespace mavloc {

namespace {

// Pairs from which the relative errors run on a second thread (below, the thread costs more than
// it saves).
constexpr size_t kPairsForSecondThread = 50'000;

void SetWhy(std::string* why, const std::string& text) {
  if (why) *why = text;
}

// Least-squares slope of y against x (0 when x does not vary).
double Slope(const std::vector<double>& x, const std::vector<double>& y) {
  const double n = static_cast<double>(x.size());
  if (x.size() < 2) return 0.0;
  double mx = 0.0, my = 0.0;
  for (size_t i = 0; i < x.size(); ++i) {
    mx += x[i];
    my += y[i];
  }
  mx /= n;
  my /= n;
  double sxy = 0.0, sxx = 0.0;
  for (size_t i = 0; i < x.size(); ++i) {
    sxy += (x[i] - mx) * (y[i] - my);
    sxx += (x[i] - mx) * (x[i] - mx);
  }
  return sxx > 0 ? sxy / sxx : 0.0;
}

YawDrift ComputeYawDrift(const PairedPoses& aligned, const std::vector<double>& dist) {
  YawDrift drift;
  if (aligned.size() < 2) return drift;
  std::vector<double> yaw_deg(aligned.size()), t_s(aligned.size());
  double previous = 0.0, unwrapped = 0.0;
  const TimeNs t0_ns = aligned.t_ns(0);
  for (size_t i = 0; i < aligned.size(); ++i) {
    const PosePair pair = aligned[i];
    const Eigen::Matrix3d R_err_W =
        (pair.T_W_B_est.q * pair.T_W_B_gt.q.conjugate()).toRotationMatrix();
    const double yaw = EulerFromRotation(R_err_W).yaw;
    unwrapped = i == 0 ? yaw : unwrapped + WrapAngle(yaw - previous);
    previous = yaw;
    yaw_deg[i] = unwrapped * kRadToDeg;
    t_s[i] = NsToSeconds(pair.t_ns - t0_ns);
  }
  drift.valid = true;
  drift.rate_deg_per_m = Slope(dist, yaw_deg);
  drift.rate_deg_per_s = Slope(t_s, yaw_deg);
  drift.final_deg = yaw_deg.back() - yaw_deg.front();
  return drift;
}

// APE of one aligned pair (evo): E = T_gt^-1 T_est'; the translation error ||p_est' - p_gt|| from
// the positions (the same norm as E's translation, evo's translation_part).
PoseErrorValues ApeErrors(const PosePair& pair) {
  const Eigen::Matrix3d R_gt = pair.T_W_B_gt.R();
  PoseErrorValues e = PoseErrors(R_gt.transpose() * pair.T_W_B_est.R(),
                                 R_gt.transpose() * (pair.T_W_B_est.p - pair.T_W_B_gt.p));
  e.translation_m = (pair.T_W_B_est.p - pair.T_W_B_gt.p).norm();
  return e;
}

double PathLength(const std::vector<StampedPose>& poses) {
  double length = 0.0;
  for (size_t i = 1; i < poses.size(); ++i)
    length += (poses[i].T_W_B.p - poses[i - 1].T_W_B.p).norm();
  return length;
}

}  // namespace

const ErrorStatistics& TrajectoryEvaluation::HeadlineApe() const {
  switch (protocol.ape_relation) {
    case PoseRelation::kTranslation:
      return ape_translation_m;
    case PoseRelation::kRotationAngleDeg:
      return ape_rotation_deg;
    case PoseRelation::kRotationPart:
      return ape_rotation_part;
    case PoseRelation::kFull:
      return ape_full;
  }
  return ape_translation_m;
}

std::optional<TrajectoryEvaluation> EvaluateTrajectory(const std::vector<StampedPose>& estimate,
                                                       const std::vector<StampedPose>& truth,
                                                       const EvaluationProtocol& protocol,
                                                       std::string* why,
                                                       TrajectoryDiagnostics* diagnostics_out) {
  TrajectoryEvaluation out;
  out.protocol = protocol;
  out.estimate_count = estimate.size();
  out.truth_count = truth.size();

  // 1. Association: pairs by index into the two trajectories (paired_poses.h).
  const AssociationOptions association_options{protocol.association, protocol.max_dt_s,
                                               protocol.time_offset_s};
  PairedPoses pairs = AssociatePairs(estimate, truth, association_options);
  out.pair_count = pairs.size();
  out.diagnostics.pair_count =
      DiagnosePairCount(pairs.size(), estimate, truth, protocol.diagnostics);
  if (diagnostics_out) *diagnostics_out = out.diagnostics;
  if (pairs.empty()) {
    SetWhy(why, fmt::format("no estimate stamp within {} s of a truth stamp (time offset {} s)",
                            protocol.max_dt_s, protocol.time_offset_s));
    return std::nullopt;
  }
  // One pose is not a trajectory: any alignment fits it exactly and the "error" is zero, so it is
  // refused rather than reported.
  if (pairs.size() < 2) {
    SetWhy(why, fmt::format("only 1 pose pair ({} estimate and {} truth poses): a trajectory "
                            "evaluation needs at least 2",
                            estimate.size(), truth.size()));
    return std::nullopt;
  }

  // 2. Alignment.
  if (protocol.align_origin && protocol.alignment != AlignmentMode::kNone) {
    SetWhy(why, "align_origin cannot be combined with another alignment (as in evo)");
    return std::nullopt;
  }
  const size_t n_align =
      protocol.n_to_align < 0
          ? pairs.size()
          : std::min(pairs.size(), static_cast<size_t>(std::max(1L, protocol.n_to_align)));
  std::optional<Similarity> S;
  if (protocol.align_origin) {
    const PosePair first = pairs.front();
    S = AlignOrigin(first.T_W_B_est, first.T_W_B_gt);
  } else if (n_align == 1 && protocol.alignment != AlignmentMode::kNone) {
    const PosePair first = pairs.front();
    S = AlignFirstPose(first.T_W_B_est, first.T_W_B_gt, protocol.alignment);
  } else {
    std::vector<Eigen::Vector3d> p_est(n_align), p_gt(n_align);
    for (size_t i = 0; i < n_align; ++i) {
      p_est[i] = estimate[pairs.estimate_index(i)].T_W_B.p;
      p_gt[i] = pairs.p_gt(i);
    }
    S = AlignPoints(p_est, p_gt, protocol.alignment);
    if (protocol.alignment != AlignmentMode::kNone)
      out.diagnostics.alignment_condition = DiagnoseAlignmentCondition(
          p_gt, AlignmentModeName(protocol.alignment), protocol.alignment != AlignmentMode::kPosYaw,
          protocol.diagnostics);
  }
  if (!S) {
    SetWhy(why, fmt::format("cannot align with {} on {} pairs: too few, or the positions are "
                            "degenerate (coincident or collinear)",
                            AlignmentModeName(protocol.alignment), n_align));
    return std::nullopt;
  }
  out.alignment = *S;
  out.aligned_pairs = protocol.alignment == AlignmentMode::kNone && !protocol.align_origin
                          ? 0
                          : (protocol.align_origin ? 1 : n_align);

  // From here on every pair read carries the aligned estimate (no copy of the pairs).
  pairs.SetAlignment(*S);
  const PairedPoses& aligned = pairs;

  // The time-offset diagnostic resamples both trajectories' angular rates (the truth's 8 times
  // finer than the estimate's period: 25 MB for a 1 kHz truth of 1000 s); it runs before the
  // relative errors start beside the rest, and its memory goes back to the system before they do
  // (glibc keeps freed heap memory resident otherwise), so that the two do not add up.
  out.diagnostics.time_offset =
      DiagnoseTimeOffset(estimate, truth, protocol.diagnostics, protocol.time_offset_s);
  if (aligned.size() >= kPairsForSecondThread) ReleaseFreeHeapPages();

  // 3. Relative error (rpg: the unaligned estimate with the alignment's scale, its error expressed
  //    in the unaligned estimate's world; the aligned pairs with scale 1 and R^T give the same),
  //    on a second thread for long trajectories while APE, RPE and yaw drift are computed here
  //    (collected at the end).
  const std::vector<double> dist = AccumulatedDistances(aligned);
  out.truth_path_length_m = dist.back();
  out.duration_s = NsToSeconds(aligned.back().t_ns - aligned.front().t_ns);
  if (out.protocol.relative_lengths_m.empty()) {
    out.protocol.relative_lengths_m =
        DefaultRelativeLengths(PathLength(truth), protocol.relative_length_fractions);
  }
  const auto relative_errors = [&out, &aligned, &dist, &protocol, R_raw = S->R.transpose()] {
    std::vector<RelativeErrorAtLength> relative;
    for (double length : out.protocol.relative_lengths_m) {
      relative.push_back(ComputeRelativeError(aligned, dist, length,
                                              protocol.max_length_diff_fraction, 1.0, R_raw,
                                              protocol.keep_series));
    }
    return relative;
  };
  std::future<std::vector<RelativeErrorAtLength>> relative_future;
  if (aligned.size() >= kPairsForSecondThread)
    relative_future = std::async(std::launch::async, relative_errors);

  // 4. APE (evo).
  if (protocol.keep_series) {
    out.pair_t_ns.reserve(aligned.size());
    for (auto* series :
         {&out.ape.translation_m, &out.ape.rotation_deg, &out.ape.rotation_part, &out.ape.full})
      series->reserve(aligned.size());
    for (const PosePair pair : aligned) {
      const PoseErrorValues e = ApeErrors(pair);
      out.pair_t_ns.push_back(pair.t_ns);
      out.ape.translation_m.push_back(e.translation_m);
      out.ape.rotation_deg.push_back(e.rotation_deg);
      out.ape.rotation_part.push_back(e.rotation_part);
      out.ape.full.push_back(e.full);
    }
    out.ape_translation_m = ComputeStatistics(out.ape.translation_m);
    out.ape_rotation_deg = ComputeStatistics(out.ape.rotation_deg);
    out.ape_rotation_part = ComputeStatistics(out.ape.rotation_part);
    out.ape_full = ComputeStatistics(out.ape.full);
  } else {
    const PoseErrorStatistics ape = StatisticsInTwoPasses(aligned.size(), [&](const auto& sink) {
      for (const PosePair pair : aligned) sink(ApeErrors(pair));
    });
    out.ape_translation_m = ape.translation_m;
    out.ape_rotation_deg = ape.rotation_deg;
    out.ape_rotation_part = ape.rotation_part;
    out.ape_full = ape.full;
  }

  // 5. RPE (evo, on the aligned estimate).
  for (const RpeDelta& delta : protocol.rpe_deltas) {
    auto rpe = ComputeRpeEvo(aligned, delta, protocol.keep_series);
    if (!rpe) {
      rpe = RpeDeltaResult{};
      rpe->delta = delta;
    }
    out.rpe.push_back(std::move(*rpe));
  }

  // 6. Yaw drift and diagnostics.
  out.yaw_drift = ComputeYawDrift(aligned, dist);
  out.diagnostics.rotation_offset = DiagnoseRotationOffset(aligned, protocol.diagnostics);
  out.diagnostics.scale =
      DiagnoseScale(protocol.alignment == AlignmentMode::kSim3, S->scale, protocol.diagnostics);
  out.relative = relative_future.valid() ? relative_future.get() : relative_errors();
  if (diagnostics_out) *diagnostics_out = out.diagnostics;
  return out;
}

}  // namespace mavloc
