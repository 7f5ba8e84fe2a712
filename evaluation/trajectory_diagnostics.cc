#include "evaluation/trajectory_diagnostics.h"

#include <fmt/format.h>

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include "core/numbers.h"
#include "core/rotation.h"

namespace mavloc {

namespace {

// |omega| of a pose sequence averaged over a baseline b, on a uniform grid:
//   rate(t) = |Log(R(t - b/2)^T R(t + b/2))| / b,  t = begin + step k,
// R(t) slerped between the poses (whose stamps, in seconds from t0, are shifted by offset_s).
// Both trajectories use the same baseline (the grid's spacing of the pass), so a noisy
// high-rate truth and a low-rate estimate are differentiated alike. The magnitude of a
// body-frame rate does not change under a constant body-frame offset.
struct RateSeries {
  double begin = 0.0;
  double step = 0.0;
  std::vector<double> rate;
  double end() const { return begin + step * static_cast<double>(rate.size() - 1); }
  // Linear interpolation; NaN outside.
  double At(double t) const {
    const double x = (t - begin) / step;
    if (!(x >= 0.0) || rate.size() < 2) return std::numeric_limits<double>::quiet_NaN();
    const size_t i = static_cast<size_t>(x);
    if (i + 1 >= rate.size()) {
      return i + 1 == rate.size() && x == static_cast<double>(i)
                 ? rate[i]
                 : std::numeric_limits<double>::quiet_NaN();
    }
    const double a = x - static_cast<double>(i);
    return (1.0 - a) * rate[i] + a * rate[i + 1];
  }
};

// Slerped orientation at time t (seconds, already shifted) with a forward-moving index.
class OrientationCursor {
 public:
  OrientationCursor(const std::vector<StampedPose>& poses, TimeNs t0, double offset_s)
      : poses_(poses), t0_(t0), offset_s_(offset_s) {}
  double Time(size_t k) const { return NsToSeconds(poses_[k].t_ns - t0_) + offset_s_; }
  double First() const { return Time(0); }
  double Last() const { return Time(poses_.size() - 1); }
  Eigen::Quaterniond At(double t) {
    while (k_ + 2 < poses_.size() && Time(k_ + 1) <= t) ++k_;
    const double ta = Time(k_), tb = Time(k_ + 1);
    const double a = tb > ta ? std::clamp((t - ta) / (tb - ta), 0.0, 1.0) : 0.0;
    return poses_[k_].T_W_B.q.slerp(a, poses_[k_ + 1].T_W_B.q);
  }

 private:
  const std::vector<StampedPose>& poses_;
  TimeNs t0_;
  double offset_s_;
  size_t k_ = 0;
};

RateSeries BaselineRate(const std::vector<StampedPose>& poses, TimeNs t0, double offset_s,
                        double baseline, double step) {
  RateSeries out;
  out.step = step;
  OrientationCursor lower(poses, t0, offset_s), upper(poses, t0, offset_s);
  out.begin = lower.First() + 0.5 * baseline;
  const double last = lower.Last() - 0.5 * baseline;
  if (!(last > out.begin)) return out;
  const size_t count = static_cast<size_t>((last - out.begin) / step) + 1;
  out.rate.resize(count);
  for (size_t k = 0; k < count; ++k) {
    const double t = out.begin + step * static_cast<double>(k);
    out.rate[k] =
        lower.At(t - 0.5 * baseline).angularDistance(upper.At(t + 0.5 * baseline)) / baseline;
  }
  return out;
}

// Mean squared difference est(t) - gt(t + tau) over est's samples where both exist; the overlap
// count in *n.
double ShiftCost(const RateSeries& est, const RateSeries& gt, double tau, size_t* n) {
  double sum = 0.0;
  size_t count = 0;
  for (size_t k = 0; k < est.rate.size(); ++k) {
    const double g = gt.At(est.begin + est.step * static_cast<double>(k) + tau);
    if (std::isnan(g)) continue;
    sum += (est.rate[k] - g) * (est.rate[k] - g);
    ++count;
  }
  *n = count;
  return count > 0 ? sum / static_cast<double>(count) : std::numeric_limits<double>::infinity();
}

// The shift tau = center + step * s, |s| <= half_steps, of least cost, refined by a parabola
// through the best cost and its neighbours; nullopt without an overlap of half the estimate.
struct ShiftSearch {
  double tau = 0.0;
  double cost = 0.0;
  double curvature = 0.0;  // d^2 cost / d tau^2 from the parabola (0 when none)
};
std::optional<ShiftSearch> SearchShift(const RateSeries& est, const RateSeries& gt, double center,
                                       double step, long half_steps) {
  const size_t min_overlap = std::max<size_t>(8, est.rate.size() / 2);
  std::vector<double> cost(static_cast<size_t>(2 * half_steps + 1),
                           std::numeric_limits<double>::infinity());
  long best = -half_steps - 1;
  for (long s = -half_steps; s <= half_steps; ++s) {
    size_t n = 0;
    const double c = ShiftCost(est, gt, center + step * static_cast<double>(s), &n);
    if (n < min_overlap) continue;
    cost[static_cast<size_t>(s + half_steps)] = c;
    if (best < -half_steps || c < cost[static_cast<size_t>(best + half_steps)]) best = s;
  }
  if (best < -half_steps) return std::nullopt;
  const double cb = cost[static_cast<size_t>(best + half_steps)];
  double refined = static_cast<double>(best), curvature = 0.0;
  if (best > -half_steps && best < half_steps) {
    const double cm = cost[static_cast<size_t>(best - 1 + half_steps)];
    const double cp = cost[static_cast<size_t>(best + 1 + half_steps)];
    const double denominator = cm - 2.0 * cb + cp;
    if (std::isfinite(cm) && std::isfinite(cp) && denominator > 0) {
      refined += std::clamp(0.5 * (cm - cp) / denominator, -0.5, 0.5);
      curvature = denominator / (step * step);
    }
  }
  return ShiftSearch{center + step * refined, cb, curvature};
}

std::string Seconds(TimeNs t_ns) { return fmt::format("{:.3f}", NsToSeconds(t_ns)); }

}  // namespace

double MedianSpacingSeconds(const std::vector<StampedPose>& poses) {
  if (poses.size() < 2) return 0.0;
  std::vector<TimeNs> dt(poses.size() - 1);
  for (size_t k = 0; k + 1 < poses.size(); ++k) dt[k] = poses[k + 1].t_ns - poses[k].t_ns;
  const size_t m = dt.size() / 2;
  std::nth_element(dt.begin(), dt.begin() + m, dt.end());
  double median = NsToSeconds(dt[m]);
  if (dt.size() % 2 == 0)
    median = 0.5 * (median + NsToSeconds(*std::max_element(dt.begin(), dt.begin() + m)));
  return median;
}

RotationOffsetDiagnostic DiagnoseRotationOffset(const PairedPoses& aligned_pairs,
                                                const DiagnosticOptions& options) {
  RotationOffsetDiagnostic d;
  if (aligned_pairs.size() < 3) return d;
  d.evaluated = true;
  // Chordal L2 mean (Hartley et al. 2013, sec. 5.3): project sum_i R_gt,i^T R_est,i onto SO(3).
  Eigen::Matrix3d sum = Eigen::Matrix3d::Zero();
  for (const auto& pair : aligned_pairs)
    sum += (pair.T_W_B_gt.q.conjugate() * pair.T_W_B_est.q).toRotationMatrix();
  Eigen::Matrix3d R = NearestRotation(sum);
  // Geodesic L2 (Karcher) mean by Gauss-Newton on the tangent space at R.
  for (int iteration = 0; iteration < 10; ++iteration) {
    Eigen::Vector3d mean_phi = Eigen::Vector3d::Zero();
    const Eigen::Quaterniond q_inv(R.transpose());
    for (const auto& pair : aligned_pairs)
      mean_phi += LogQuaternion(q_inv * pair.T_W_B_gt.q.conjugate() * pair.T_W_B_est.q);
    mean_phi /= static_cast<double>(aligned_pairs.size());
    R = R * ExpSO3(mean_phi);
    if (mean_phi.norm() < 1e-10) break;
  }
  double sum_sq = 0.0;
  const Eigen::Quaterniond q_inv(R.transpose());
  for (const auto& pair : aligned_pairs)
    sum_sq += LogQuaternion(q_inv * pair.T_W_B_gt.q.conjugate() * pair.T_W_B_est.q).squaredNorm();
  d.noise_deg = std::sqrt(sum_sq / static_cast<double>(aligned_pairs.size())) * kRadToDeg;
  d.R_off = R;
  const Eigen::Vector3d phi = LogSO3(R);
  d.angle_deg = phi.norm() * kRadToDeg;
  if (phi.norm() > 1e-12) d.axis = phi.normalized();
  d.detected = d.angle_deg > std::max(options.min_rotation_offset_deg,
                                      options.rotation_offset_sigma_factor * d.noise_deg);
  return d;
}

TimeOffsetDiagnostic DiagnoseTimeOffset(const std::vector<StampedPose>& estimate,
                                        const std::vector<StampedPose>& truth,
                                        const DiagnosticOptions& options,
                                        double estimate_time_offset_s) {
  TimeOffsetDiagnostic d;
  d.estimate_period_s = MedianSpacingSeconds(estimate);
  if (estimate.size() < 10 || truth.size() < 10 || !(d.estimate_period_s > 0)) return d;
  const TimeNs t0 = std::min(estimate.front().t_ns, truth.front().t_ns);
  const double span = NsToSeconds(estimate.back().t_ns - estimate.front().t_ns);
  // Two grids: a coarse one (at most 20000 samples) searched over the whole window, and one on
  // the estimate's period (at most 200000 samples) searched around the coarse optimum in steps
  // of one period, then of 1/8 period; each search ends with a parabola through the best three
  // costs. The truth's rate is sampled 8 times finer than the estimate's on each grid.
  const double h_fine = std::max(d.estimate_period_s, span / 200000.0);
  const double h_coarse = std::max(h_fine, span / 20000.0);
  const RateSeries est_coarse =
      BaselineRate(estimate, t0, estimate_time_offset_s, h_coarse, h_coarse);
  const RateSeries gt_coarse = BaselineRate(truth, t0, 0.0, h_coarse, h_coarse / 8.0);
  if (est_coarse.rate.size() < 8 || gt_coarse.rate.size() < 8) return d;
  // Without rotation there is nothing to correlate: the truth's |omega| must vary.
  double mean = 0.0, sq = 0.0;
  for (double v : gt_coarse.rate) {
    mean += v;
    sq += v * v;
  }
  mean /= static_cast<double>(gt_coarse.rate.size());
  if (!(sq / static_cast<double>(gt_coarse.rate.size()) - mean * mean > 1e-6)) return d;
  const long coarse_steps =
      static_cast<long>(std::ceil(options.max_time_offset_search_s / h_coarse));
  const auto coarse = SearchShift(est_coarse, gt_coarse, 0.0, h_coarse, coarse_steps);
  if (!coarse) return d;
  const RateSeries est_fine = BaselineRate(estimate, t0, estimate_time_offset_s, h_fine, h_fine);
  const RateSeries gt_fine = BaselineRate(truth, t0, 0.0, h_fine, h_fine / 8.0);
  if (est_fine.rate.size() < 8 || gt_fine.rate.size() < 8) return d;
  const long medium_steps = static_cast<long>(std::ceil(2.0 * h_coarse / h_fine));
  const auto medium = SearchShift(est_fine, gt_fine, coarse->tau, h_fine, medium_steps);
  if (!medium) return d;
  const auto fine = SearchShift(est_fine, gt_fine, medium->tau, h_fine / 8.0, 8);
  if (!fine) return d;
  const auto zero = SearchShift(est_fine, gt_fine, 0.0, h_fine, 0);
  if (!zero) return d;
  d.evaluated = true;
  // |omega_est|(t) = |omega_gt|(t + tau): the estimate's stamp t belongs at truth time t + tau.
  d.offset_s = fine->tau;
  d.cost_at_zero = zero->cost;
  d.cost_at_offset = std::min(fine->cost, zero->cost);
  // Standard deviation of tau: with the rate difference e = n + g' dtau (noise of variance ~ the
  // residual cost c*, N samples), cost(tau) = c* + (kappa / 2)(tau - tau*)^2 with kappa = 2
  // mean(g'^2), and sigma_tau^2 = c* / (N mean(g'^2)) = 2 c* / (N kappa).
  if (medium->curvature > 0) {
    d.sigma_s = std::sqrt(2.0 * fine->cost /
                          (static_cast<double>(est_fine.rate.size()) * medium->curvature));
  }
  // Reported beyond one estimate period when significant (3 sigma).
  d.detected = std::abs(d.offset_s) > d.estimate_period_s && d.sigma_s > 0 &&
               std::abs(d.offset_s) > 3.0 * d.sigma_s;
  return d;
}

ScaleDiagnostic DiagnoseScale(bool sim3, double scale, const DiagnosticOptions& options) {
  ScaleDiagnostic d;
  d.evaluated = sim3;
  d.scale = scale;
  d.detected =
      sim3 && options.metric_estimator && std::abs(scale - 1.0) > options.max_scale_deviation;
  return d;
}

PairCountDiagnostic DiagnosePairCount(size_t pairs, const std::vector<StampedPose>& estimate,
                                      const std::vector<StampedPose>& truth,
                                      const DiagnosticOptions& options) {
  PairCountDiagnostic d;
  d.pairs = pairs;
  d.estimate_count = estimate.size();
  d.truth_count = truth.size();
  if (!estimate.empty()) {
    d.estimate_first_ns = estimate.front().t_ns;
    d.estimate_last_ns = estimate.back().t_ns;
  }
  if (!truth.empty()) {
    d.truth_first_ns = truth.front().t_ns;
    d.truth_last_ns = truth.back().t_ns;
  }
  d.estimate_median_dt_s = MedianSpacingSeconds(estimate);
  d.truth_median_dt_s = MedianSpacingSeconds(truth);
  const size_t shorter = std::min(estimate.size(), truth.size());
  d.detected =
      pairs < options.min_pairs ||
      static_cast<double>(pairs) < options.min_pair_fraction * static_cast<double>(shorter);
  return d;
}

AlignmentConditionDiagnostic DiagnoseAlignmentCondition(const std::vector<Eigen::Vector3d>& p_gt,
                                                        const std::string& mode, bool needs_two,
                                                        const DiagnosticOptions& options) {
  AlignmentConditionDiagnostic d;
  d.mode = mode;
  if (p_gt.size() < 2) return d;
  d.evaluated = true;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& p : p_gt) mean += p;
  mean /= static_cast<double>(p_gt.size());
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (const auto& p : p_gt) scatter += (p - mean) * (p - mean).transpose();
  scatter /= static_cast<double>(p_gt.size());
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(scatter);
  const Eigen::Vector3d variances = solver.eigenvalues().cwiseMax(0.0);  // ascending
  d.extents_m =
      Eigen::Vector3d(std::sqrt(variances[2]), std::sqrt(variances[1]), std::sqrt(variances[0]));
  d.detected = d.extents_m[needs_two ? 1 : 0] < options.min_alignment_extent_m;
  return d;
}

std::vector<std::string> TrajectoryDiagnostics::Messages() const {
  std::vector<std::string> out;
  if (alignment_condition.detected) {
    out.push_back(fmt::format(
        "the {} alignment is ill-conditioned: the truth positions it fits spread only {:.3f} m "
        "and {:.3f} m (RMS) in their two main directions, too little to fix its rotation, so the "
        "errors after it mean little; use --align-origin or --align none",
        alignment_condition.mode, alignment_condition.extents_m[0],
        alignment_condition.extents_m[1]));
  }
  if (pair_count.detected) {
    out.push_back(fmt::format(
        "only {} associated pairs (estimate {} poses, {} .. {} s, median spacing {:.4f} s; truth "
        "{} "
        "poses, {} .. {} s, median spacing {:.4f} s): check the stamps' units and clock, the time "
        "offset and the association tolerance",
        pair_count.pairs, pair_count.estimate_count, Seconds(pair_count.estimate_first_ns),
        Seconds(pair_count.estimate_last_ns), pair_count.estimate_median_dt_s,
        pair_count.truth_count, Seconds(pair_count.truth_first_ns),
        Seconds(pair_count.truth_last_ns), pair_count.truth_median_dt_s));
  }
  if (rotation_offset.detected) {
    const Eigen::Vector3d& a = rotation_offset.axis;
    out.push_back(fmt::format(
        "constant rotation offset of {:.2f} deg about axis ({:.3f}, {:.3f}, {:.3f}) (body frame) "
        "between estimate and truth after alignment (rotation noise {:.2f} deg): the estimate is "
        "likely expressed in another body or camera frame (e.g. camera instead of IMU); "
        "R_gt^T R_est = R_off",
        rotation_offset.angle_deg, a.x(), a.y(), a.z(), rotation_offset.noise_deg));
  }
  if (time_offset.detected) {
    out.push_back(fmt::format(
        "time offset of {:+.4f} s (+- {:.4f} s) between estimate and truth from their angular "
        "rates (more than one estimate period, {:.4f} s): add it to the estimate's stamps "
        "(--t-offset) or check the clocks",
        time_offset.offset_s, time_offset.sigma_s, time_offset.estimate_period_s));
  }
  if (scale.detected) {
    out.push_back(fmt::format(
        "Sim3 scale {:.4f} is far from 1 for a metric estimator: the estimate's scale is wrong "
        "(monocular scale drift, wrong IMU or stereo baseline units) or the files use other units",
        scale.scale));
  }
  return out;
}

}  // namespace mavloc
