#include "evaluation/comparison_report.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "core/rotation.h"

namespace mavloc {
namespace {

std::vector<double> Absolute(const std::vector<double>& values) {
  std::vector<double> out;
  out.reserve(values.size());
  for (const double v : values) out.push_back(std::abs(v));
  return out;
}

// T_B_C of each camera as position and roll/pitch/yaw [rad], with the sigmas of the marginal
// covariance (position; the rotation perturbation's components as the angles' sigmas).
void AddExtrinsics(const Estimate& estimate, EstimatorResult* result) {
  for (const auto& [camera, e] : estimate.extrinsics) {
    const EulerRpy euler = EulerFromRotation(e.T_B_C.R());
    const Eigen::Vector3d rpy(euler.roll, euler.pitch, euler.yaw);
    std::optional<Eigen::Matrix<double, 6, 1>> sigma;
    if (e.covariance) sigma = e.covariance->diagonal().cwiseSqrt();
    const char* axes[3] = {"x", "y", "z"};
    const char* angles[3] = {"roll", "pitch", "yaw"};
    for (int k = 0; k < 3; ++k) {
      result->parameters[camera + ".p_B_C." + axes[k]] = {
          e.T_B_C.p[k], sigma ? std::optional<double>((*sigma)[k]) : std::nullopt, "m"};
      result->parameters[camera + ".R_B_C." + angles[k]] = {
          rpy[k], sigma ? std::optional<double>((*sigma)[3 + k]) : std::nullopt, "rad"};
    }
  }
}

// Beyond this truth pitch, roll and yaw differences are dominated by the Euler parametrisation's
// singularity at +-90 deg (a small rotation error changes roll and yaw by tens of degrees).
constexpr double kGimbalLockPitchRad = 60.0 * M_PI / 180.0;

// Roll and yaw errors are left out near gimbal lock, with a warning that names the rotation angle.
void DropEulerNearGimbalLock(const EstimatorEvaluation& e, EstimatorResult* r) {
  double max_pitch = 0.0;
  for (const auto& q : e.quantity_errors)
    if (q.name == "pitch")
      for (const double truth : q.truth) max_pitch = std::max(max_pitch, std::abs(truth));
  if (max_pitch <= kGimbalLockPitchRad) return;
  const size_t erased = r->metrics.erase("roll") + r->metrics.erase("yaw");
  if (erased == 0) return;
  r->warnings.push_back(fmt::format(
      "roll and yaw errors left out: the pitch reaches {:.0f} deg, near the Euler angles' "
      "singularity, where their differences mislead; the rotation error is the angle in "
      "ate_rotation",
      max_pitch * 180.0 / M_PI));
}

}  // namespace

EstimatorResult ResultOfEvaluation(const EstimatorEvaluation& e) {
  EstimatorResult r;
  r.name = e.estimator;
  r.ran = e.ran;
  r.skipped_reason = e.skipped_reason;
  if (!e.ran) return r;
  r.is_reference = e.is_reference;
  r.coverage = e.coverage;
  if (e.ate) {
    r.metrics["ate_translation"] = {"m", std::nullopt, e.ate->translation_m};
    r.metrics["ate_rotation"] = {"rad", std::nullopt, e.ate->rotation_rad};
  }
  for (const auto& q : e.quantity_errors)
    r.metrics[q.name] = {q.unit, std::nullopt, ComputeStatistics(Absolute(q.error))};
  DropEulerNearGimbalLock(e, &r);
  for (const auto& rep : e.reprojection)
    r.metrics["reprojection_" + rep.camera] = {"px", rep.rms_px, std::nullopt};
  for (const auto& [name, p] : e.estimate.parameters)
    r.parameters[name] = {p.value, p.sigma, p.unit};
  AddExtrinsics(e.estimate, &r);
  r.frames_without_pose = e.estimate.FailureCount();
  r.rejected_measurements = e.estimate.RejectionCount();
  r.failures = e.estimate.failures;
  for (const auto& [reason, count] : e.estimate.rejections)
    r.failures["rejected: " + reason] += count;
  r.runtime_s = e.runtime_s;
  r.warnings.insert(r.warnings.begin(), e.warnings.begin(), e.warnings.end());
  if (e.coverage && e.coverage->estimate_span_s > 0.0 &&
      e.coverage->Fraction() < kLowCoverageFraction)
    r.warnings.push_back(fmt::format(
        "the {} covers only {:.1f} of the estimate's {:.1f} s ({} of {} poses): the numbers "
        "describe that part alone",
        e.is_reference ? "reference" : "ground truth", e.coverage->overlap_s,
        e.coverage->estimate_span_s, e.coverage->pairs, e.coverage->estimate_poses));
  return r;
}

Report ComparisonReport(const std::string& title, const Dataset& dataset,
                        const std::vector<EstimatorEvaluation>& evaluations,
                        const EvaluationOptions& options,
                        const std::vector<std::string>& left_out) {
  Report report;
  report.kind = "compare";
  report.title = "mavloc compare: " + title;
  report.provenance.input = dataset.root.empty() ? "scenario " + dataset.scenario : dataset.root;
  report.provenance.settings = dataset.scenario_info;
  if (const auto it = dataset.scenario_info.find("seed"); it != dataset.scenario_info.end()) {
    try {
      report.provenance.seeds.push_back(std::stoull(it->second));
    } catch (const std::exception&) {
    }
  }
  ReportProtocol protocol;
  protocol.reference = options.reference ? "estimate" : "truth";
  protocol.alignment = AlignmentModeName(options.align);
  protocol.association = "interpolate";
  protocol.max_dt_s = options.max_dt_s;
  report.protocol = protocol;
  for (const auto& e : evaluations) report.estimators.push_back(ResultOfEvaluation(e));
  for (const auto& entry : left_out)
    report.warnings.push_back("Not applicable to this dataset: " + entry);
  return report;
}

}  // namespace mavloc
