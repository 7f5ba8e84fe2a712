#include "evaluation/crlb/consistency.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <optional>

#include "core/rotation.h"
#include "evaluation/association.h"
#include "evaluation/json_number.h"
#include "solver/smoother/smoother_initialization.h"

namespace mavloc {

namespace {

// Standard normal quantile (Acklam's rational approximation, relative error < 1.2e-9).
double NormalQuantile(double p) {
  static const double a[] = {-3.969683028665376e+01, 2.209460984245205e+02,  -2.759285104469687e+02,
                             1.383577518672690e+02,  -3.066479806614716e+01, 2.506628277459239e+00};
  static const double b[] = {-5.447609879822406e+01, 1.615858368580409e+02, -1.556989798598866e+02,
                             6.680131188771972e+01, -1.328068155288572e+01};
  static const double c[] = {-7.784894002430293e-03, -3.223964580411365e-01, -2.400758277161838e+00,
                             -2.549732539343734e+00, 4.374664141464968e+00,  2.938163982698783e+00};
  static const double d[] = {7.784695709041462e-03, 3.224671290700398e-01, 2.445134137142996e+00,
                             3.754408661907416e+00};
  const double lo = 0.02425;
  if (p < lo) {
    const double q = std::sqrt(-2 * std::log(p));
    return (((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) /
           ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1);
  }
  if (p > 1 - lo) return -NormalQuantile(1 - p);
  const double q = p - 0.5, r = q * q;
  return (((((a[0] * r + a[1]) * r + a[2]) * r + a[3]) * r + a[4]) * r + a[5]) * q /
         (((((b[0] * r + b[1]) * r + b[2]) * r + b[3]) * r + b[4]) * r + 1);
}

int IndexOf(const std::vector<std::string>& names, const std::string& name) {
  auto it = std::find(names.begin(), names.end(), name);
  return it == names.end() ? -1 : static_cast<int>(it - names.begin());
}

constexpr TimeNs kToleranceNs = 2'000'000;
// Ground-truth rows at most this far apart are interpolated (200 Hz truth: 5 ms).
constexpr TimeNs kInterpolationGapNs = 4 * kToleranceNs;

// The true pose at t_ns: interpolated (linear position, slerp) between the two ground-truth rows
// around it when they are close, else the nearest row within kToleranceNs. Camera stamps need not
// fall on truth rows (marker-board-flight: 30 Hz frames, 200 Hz truth); a neighbouring row up to
// 2.5 ms away is off by millimetres at walking speed, more than the smoother's error.
std::optional<Pose> TruthAt(const std::vector<StampedPose>& truth, TimeNs t_ns) {
  auto next = std::lower_bound(truth.begin(), truth.end(), t_ns,
                               [](const StampedPose& p, TimeNs t) { return p.t_ns < t; });
  if (next != truth.end() && next->t_ns == t_ns) return next->T_W_B;
  if (next != truth.end() && next != truth.begin()) {
    const StampedPose& prev = *std::prev(next);
    if (next->t_ns - prev.t_ns <= kInterpolationGapNs) {
      const double u =
          static_cast<double>(t_ns - prev.t_ns) / static_cast<double>(next->t_ns - prev.t_ns);
      return Pose(prev.T_W_B.q.slerp(u, next->T_W_B.q).normalized(),
                  (1.0 - u) * prev.T_W_B.p + u * next->T_W_B.p);
    }
  }
  const StampedPose* nearest = nullptr;
  if (next != truth.end()) nearest = &*next;
  if (next != truth.begin() && (!nearest || t_ns - std::prev(next)->t_ns < nearest->t_ns - t_ns))
    nearest = &*std::prev(next);
  if (!nearest || std::abs(nearest->t_ns - t_ns) > kToleranceNs) return std::nullopt;
  return nearest->T_W_B;
}

}  // namespace

double ChiSquareQuantileWh(double k, double p) {
  const double z = NormalQuantile(p);
  const double h = 2.0 / (9.0 * k);
  const double t = 1.0 - h + z * std::sqrt(h);
  return k * t * t * t;
}

void MergeNees(const NeesAccumulator& other, NeesAccumulator* nees) {
  for (const auto& [to, from] :
       {std::pair{&nees->position, &other.position}, std::pair{&nees->attitude, &other.attitude}}) {
    for (const auto& [t, cell] : *from) {
      auto& sum = (*to)[t];
      sum.first += cell.first;
      sum.second += cell.second;
    }
  }
  nees->runs += other.runs;
}

nlohmann::json NeesToJson(const NeesAccumulator& nees) {
  nlohmann::json j = {{"runs", nees.runs}};
  for (const auto& [name, series] :
       {std::pair{"position", &nees.position}, std::pair{"attitude", &nees.attitude}}) {
    nlohmann::json rows = nlohmann::json::array();
    for (const auto& [t, cell] : *series) rows.push_back({t, JsonNumber(cell.first), cell.second});
    j[name] = rows;
  }
  return j;
}

NeesAccumulator NeesFromJson(const nlohmann::json& j) {
  NeesAccumulator nees;
  nees.runs = j.at("runs").get<int>();
  for (const auto& [name, series] :
       {std::pair{"position", &nees.position}, std::pair{"attitude", &nees.attitude}}) {
    for (const auto& row : j.at(name))
      (*series)[row.at(0).get<TimeNs>()] = {NumberFromJson(row.at(1)), row.at(2).get<int>()};
  }
  return nees;
}

bool AccumulateNees(const Dataset& dataset, const Estimate& estimate, NeesAccumulator* nees) {
  const auto& names = estimate.covariance_names;
  const int ix = IndexOf(names, "x"), iy = IndexOf(names, "y"), iz = IndexOf(names, "z");
  const int ir = IndexOf(names, "roll"), ip = IndexOf(names, "pitch"), iw = IndexOf(names, "yaw");
  const bool has_position = ix >= 0 && iy >= 0 && iz >= 0;
  const bool has_attitude = ir >= 0 && ip >= 0 && iw >= 0;
  if (estimate.covariances.empty() || (!has_position && !has_attitude)) return false;
  std::vector<StampedPose> poses = SeedPoses(estimate);
  if (poses.empty() || dataset.ground_truth.empty()) return false;
  std::sort(poses.begin(), poses.end(),
            [](const StampedPose& a, const StampedPose& b) { return a.t_ns < b.t_ns; });
  // Truth at the pose stamps.
  const std::vector<StampedPose> truth = GroundTruthPoses(dataset);
  bool any = false;
  for (const StampedCovariance& sc : estimate.covariances) {
    auto it = std::lower_bound(poses.begin(), poses.end(), sc.t_ns,
                               [](const StampedPose& p, TimeNs t) { return p.t_ns < t; });
    if (it == poses.end() || std::abs(it->t_ns - sc.t_ns) > kToleranceNs) continue;
    const std::optional<Pose> gt = TruthAt(truth, sc.t_ns);
    if (!gt) continue;
    const TimeNs key = (sc.t_ns + 500'000) / 1'000'000 * 1'000'000;
    const Eigen::MatrixXd& P = sc.covariance;
    if (has_position) {
      const Eigen::Vector3d e = it->T_W_B.p - gt->p;
      Eigen::Matrix3d C;
      const int idx[3] = {ix, iy, iz};
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) C(a, b) = P(idx[a], idx[b]);
      const Eigen::LDLT<Eigen::Matrix3d> ldlt(C);
      if (ldlt.info() == Eigen::Success && ldlt.isPositive()) {
        auto& cell = nees->position[key];
        cell.first += e.dot(ldlt.solve(e));
        cell.second += 1;
        any = true;
      }
    }
    if (has_attitude) {
      const EulerRpy est = EulerFromQuaternion(it->T_W_B.q);
      const EulerRpy tru = EulerFromQuaternion(gt->q);
      const Eigen::Vector3d e(WrapAngle(est.roll - tru.roll), WrapAngle(est.pitch - tru.pitch),
                              WrapAngle(est.yaw - tru.yaw));
      Eigen::Matrix3d C;
      const int idx[3] = {ir, ip, iw};
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) C(a, b) = P(idx[a], idx[b]);
      const Eigen::LDLT<Eigen::Matrix3d> ldlt(C);
      if (ldlt.info() == Eigen::Success && ldlt.isPositive()) {
        auto& cell = nees->attitude[key];
        cell.first += e.dot(ldlt.solve(e));
        cell.second += 1;
        any = true;
      }
    }
  }
  if (any) ++nees->runs;
  return any;
}

AneesSummary SummarizeAnees(const std::map<TimeNs, std::pair<double, int>>& series, int runs) {
  AneesSummary s;
  if (runs < 1) return s;
  s.runs = runs;
  s.band_low = ChiSquareQuantileWh(3.0 * runs, 0.025) / runs;
  s.band_high = ChiSquareQuantileWh(3.0 * runs, 0.975) / runs;
  double sum = 0.0;
  int inside = 0;
  for (const auto& [t, cell] : series) {
    if (cell.second < runs) continue;
    const double anees = cell.first / cell.second;
    sum += anees;
    inside += (anees >= s.band_low && anees <= s.band_high) ? 1 : 0;
    ++s.steps;
  }
  if (s.steps == 0) return s;
  s.available = true;
  s.mean_anees = sum / s.steps;
  s.fraction_inside = static_cast<double>(inside) / s.steps;
  return s;
}

}  // namespace mavloc
