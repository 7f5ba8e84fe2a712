#include "evaluation/comparison.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>

#include "core/errors.h"
#include "core/rotation.h"
#include "evaluation/association.h"
#include "evaluation/report_writer.h"
#include "evaluation/trajectory_evaluation.h"

namespace mavloc {

namespace {

ErrorStatistics Scaled(ErrorStatistics s, double factor) {
  for (double* v : {&s.rmse, &s.mean, &s.median, &s.std, &s.min, &s.max}) *v *= factor;
  s.sse *= factor * factor;
  return s;
}

// The ATE of the one trajectory-error engine (trajectory_evaluation.h) under the comparison's
// protocol (ComparisonProtocol), with the coverage and the engine's diagnostics.
void EvaluatePoses(const std::vector<StampedPose>& truth, const EvaluationOptions& options,
                   EstimatorEvaluation* evaluation) {
  const std::vector<StampedPose>& poses = evaluation->estimate.poses;
  Coverage coverage;
  coverage.estimate_poses = poses.size();
  coverage.estimate_span_s = NsToSeconds(poses.back().t_ns - poses.front().t_ns);
  std::string why;
  const auto result = EvaluateTrajectory(poses, truth, ComparisonProtocol(options), &why);
  if (!result) {
    evaluation->coverage = coverage;
    evaluation->warnings.push_back("no ATE: " + why);
    return;
  }
  coverage.pairs = result->pair_count;
  coverage.overlap_s = result->duration_s;
  evaluation->coverage = coverage;
  AteResult ate;
  ate.align = options.align;
  ate.alignment = result->alignment;
  ate.translation_m = result->ape_translation_m;
  ate.rotation_rad = Scaled(result->ape_rotation_deg, M_PI / 180.0);
  ate.translation_errors_m = result->ape.translation_m;
  evaluation->ate = std::move(ate);
  for (auto& message : result->diagnostics.Messages()) evaluation->warnings.push_back(message);
}

}  // namespace

EvaluationProtocol ComparisonProtocol(const EvaluationOptions& options) {
  EvaluationProtocol protocol;
  protocol.association = AssociationMode::kInterpolate;
  protocol.max_dt_s = options.max_dt_s;
  protocol.alignment = options.align;
  protocol.rpe_deltas.clear();  // compare reports the ATE; eval the RPE and relative errors
  protocol.relative_length_fractions.clear();
  return protocol;
}

EstimatorEvaluation EvaluateEstimate(const std::string& estimator_name, Estimate estimate,
                                     const Dataset& dataset, const EvaluationOptions& options) {
  EstimatorEvaluation evaluation;
  evaluation.estimator = estimator_name;
  evaluation.ran = true;
  evaluation.estimate = std::move(estimate);
  evaluation.warnings = evaluation.estimate.events;
  evaluation.reprojection = ComputeTagReprojection(dataset, evaluation.estimate);
  const QuantityTable& q = evaluation.estimate.quantities;
  if (options.reference) {
    // Against a reference estimate: the quantities both provide, and the ATE to its poses.
    const ComparisonReference& reference = *options.reference;
    if (reference.kind == ComparisonReference::Kind::kEstimator &&
        reference.name == estimator_name) {
      evaluation.is_reference = true;
      return evaluation;
    }
    evaluation.quantity_errors =
        ComputeQuantityErrors(q, reference.quantities, options.max_dt_s, options.quantities);
    if (!evaluation.estimate.poses.empty() && !reference.poses.empty())
      EvaluatePoses(reference.poses, options, &evaluation);
    return evaluation;
  }
  // The dataset's extra truth quantities come first: where they name a quantity (the laser
  // paper's roll and pitch are the camera's attitude relative to the plane, not the vehicle's),
  // they define it. The remaining names are compared with the ground-truth states.
  const auto wanted = [&](const std::string& name) {
    return options.quantities.empty() ||
           std::find(options.quantities.begin(), options.quantities.end(), name) !=
               options.quantities.end();
  };
  std::vector<std::string> from_extra, from_states;
  for (const auto& name : q.names) {
    if (!wanted(name)) continue;
    (dataset.truth_quantities.Has(name) ? from_extra : from_states).push_back(name);
  }
  if (!from_extra.empty()) {
    evaluation.quantity_errors =
        ComputeQuantityErrors(q, dataset.truth_quantities, options.max_dt_s, from_extra);
  }
  if (!from_states.empty() && !dataset.ground_truth.empty()) {
    for (auto& series :
         ComputeQuantityErrors(q, GroundTruthQuantities(dataset), options.max_dt_s, from_states))
      evaluation.quantity_errors.push_back(std::move(series));
  }
  if (!evaluation.estimate.poses.empty() && !dataset.ground_truth.empty())
    EvaluatePoses(GroundTruthPoses(dataset), options, &evaluation);
  return evaluation;
}

EstimatorEvaluation RunAndEvaluate(const std::string& estimator_name,
                                   const EstimatorOptions& estimator_options,
                                   const Dataset& dataset, const EvaluationOptions& options) {
  const EstimatorEntry* entry = FindEstimator(estimator_name);
  if (!entry) throw InputError("unknown estimator '" + estimator_name + "' (see `mavloc list`)");
  auto estimator = entry->create(estimator_options);
  const Applicability applicability = estimator->AppliesTo(dataset);
  if (!applicability.applies) {
    EstimatorEvaluation skipped;
    skipped.estimator = estimator_name;
    skipped.skipped_reason = applicability.reason;
    return skipped;
  }
  const auto start = std::chrono::steady_clock::now();
  Estimate estimate = estimator->Run(dataset);
  const double runtime_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EstimatorEvaluation evaluation =
      EvaluateEstimate(estimator_name, std::move(estimate), dataset, options);
  evaluation.runtime_s = runtime_s;
  return evaluation;
}

nlohmann::json EvaluationToJson(const EstimatorEvaluation& evaluation) {
  nlohmann::json j = nlohmann::json::object();
  if (!evaluation.ran) {
    j["skipped"] = evaluation.skipped_reason;
    return j;
  }
  nlohmann::json quantities = nlohmann::json::object();
  for (const auto& q : evaluation.quantity_errors)
    quantities[q.name] = {{"mean_abs", q.mean_abs},
                          {"rmse", q.rmse},
                          {"max_abs", q.max_abs},
                          {"count", q.error.size()},
                          {"unit", q.unit}};
  j["quantities"] = quantities;
  if (evaluation.ate) {
    const auto& a = *evaluation.ate;
    j["ate"] = {{"rmse", a.translation_m.rmse},        {"mean", a.translation_m.mean},
                {"median", a.translation_m.median},    {"std", a.translation_m.std},
                {"min", a.translation_m.min},          {"max", a.translation_m.max},
                {"count", a.translation_m.count},      {"rotation_rmse_rad", a.rotation_rad.rmse},
                {"align", AlignmentModeName(a.align)}, {"unit", "m"}};
  }
  if (evaluation.is_reference) j["reference"] = true;
  if (!evaluation.reprojection.empty()) {
    nlohmann::json reprojection = nlohmann::json::object();
    for (const auto& r : evaluation.reprojection)
      reprojection[r.camera] = {{"rms_px", r.rms_px},      {"median_px", r.median_px},
                                {"max_px", r.max_px},      {"corners", r.corners},
                                {"over_3px", r.over_3px},  {"unmatched", r.unmatched},
                                {"off_image", r.off_image}};
    j["reprojection"] = reprojection;
  }
  if (!evaluation.estimate.parameters.empty()) {
    nlohmann::json parameters = nlohmann::json::object();
    for (const auto& [name, p] : evaluation.estimate.parameters) {
      nlohmann::json entry = {{"value", p.value}, {"unit", p.unit}};
      if (p.sigma) entry["sigma"] = *p.sigma;
      parameters[name] = entry;
    }
    j["parameters"] = parameters;
  }
  if (!evaluation.estimate.extrinsics.empty()) {
    nlohmann::json extrinsics = nlohmann::json::object();
    for (const auto& [camera, e] : evaluation.estimate.extrinsics) {
      const auto& q = e.T_B_C.q;
      nlohmann::json entry = {{"p_B_C_m", {e.T_B_C.p.x(), e.T_B_C.p.y(), e.T_B_C.p.z()}},
                              {"q_B_C_wxyz", {q.w(), q.x(), q.y(), q.z()}}};
      if (e.covariance) {
        const Eigen::Matrix<double, 6, 1> sigma = e.covariance->diagonal().cwiseSqrt();
        entry["sigma_p_m"] = {sigma[0], sigma[1], sigma[2]};
        entry["sigma_rotation_rad"] = {sigma[3], sigma[4], sigma[5]};
      }
      extrinsics[camera] = entry;
    }
    j["extrinsics"] = extrinsics;
  }
  j["runtime_s"] = evaluation.runtime_s;
  if (!evaluation.estimate.failures.empty()) j["failures"] = evaluation.estimate.failures;
  if (!evaluation.warnings.empty()) j["warnings"] = evaluation.warnings;
  return j;
}

std::string ErrorsCsv(const std::vector<EstimatorEvaluation>& evaluations, size_t max_rows,
                      size_t* stride) {
  size_t rows = 0;
  for (const auto& e : evaluations)
    for (const auto& q : e.quantity_errors) rows += q.error.size();
  const size_t k = RowStride(rows, max_rows);
  if (stride) *stride = k;
  std::string csv = "estimator,quantity,unit,t_s,estimate,truth,error\n";
  for (const auto& e : evaluations) {
    for (const auto& q : e.quantity_errors) {
      const double scale = ReportScale(q.unit);
      const std::string unit = ReportUnit(q.unit);
      for (size_t i = 0; i < q.error.size(); i += k) {
        csv += fmt::format("{},{},{},{:.9f},{:.9g},{:.9g},{:.9g}\n", e.estimator, q.name, unit,
                           NsToSeconds(q.t_ns[i]), q.estimate[i] * scale, q.truth[i] * scale,
                           q.error[i] * scale);
      }
    }
  }
  return csv;
}

}  // namespace mavloc
