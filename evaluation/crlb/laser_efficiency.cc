#include "evaluation/crlb/laser_efficiency.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>

#include "core/numbers.h"
#include "core/rotation.h"
#include "evaluation/crlb/laser_bound.h"
#include "evaluation/json_number.h"

namespace mavloc {

namespace {

const QuantityEfficiency* Find(const LaserEfficiencySums& s, const std::string& name) {
  auto it = s.quantities.find(name);
  return it == s.quantities.end() ? nullptr : &it->second;
}

}  // namespace

void LaserEfficiencySums::Add(const LaserEfficiencySums& other) {
  runs += other.runs;
  for (const auto& [name, from] : other.quantities) {
    QuantityEfficiency& to = quantities[name];
    to.error2 += from.error2;
    to.bound2 += from.bound2;
    to.frames += from.frames;
    to.run_error2.insert(to.run_error2.end(), from.run_error2.begin(), from.run_error2.end());
    to.run_bound2.insert(to.run_bound2.end(), from.run_bound2.begin(), from.run_bound2.end());
  }
}

double LaserEfficiencySums::BoundRms(const std::string& name) const {
  const QuantityEfficiency* q = Find(*this, name);
  return q && q->frames > 0 ? std::sqrt(q->bound2 / q->frames) : kNaN;
}

double LaserEfficiencySums::Rmse(const std::string& name) const {
  const QuantityEfficiency* q = Find(*this, name);
  return q && q->frames > 0 ? std::sqrt(q->error2 / q->frames) : kNaN;
}

double LaserEfficiencySums::Ratio(const std::string& name) const {
  const QuantityEfficiency* q = Find(*this, name);
  return q && q->frames > 0 && q->bound2 > 0.0 ? std::sqrt(q->error2 / q->bound2) : kNaN;
}

double LaserEfficiencySums::RatioStandardError(const std::string& name) const {
  const QuantityEfficiency* q = Find(*this, name);
  if (!q || q->run_error2.size() < 2 || q->run_error2.size() != q->run_bound2.size()) return kNaN;
  const double n = static_cast<double>(q->run_error2.size());
  double me = 0.0, mb = 0.0;
  for (size_t i = 0; i < q->run_error2.size(); ++i) {
    me += q->run_error2[i] / n;
    mb += q->run_bound2[i] / n;
  }
  if (!(mb > 0.0) || !(me > 0.0)) return kNaN;
  // r^2 = me / mb; var(r^2) ~ var(e - r^2 b) / (n mb^2); se(r) = se(r^2) / (2 r).
  const double ratio2 = me / mb;
  double var = 0.0;
  for (size_t i = 0; i < q->run_error2.size(); ++i) {
    const double r = q->run_error2[i] - ratio2 * q->run_bound2[i];
    var += r * r / (n - 1.0);
  }
  return 0.5 * std::sqrt(var / n) / mb / std::sqrt(ratio2);
}

LaserEfficiencySums CompareLaserWithBound(const SmootherCrlb& bound, const QuantityTable& estimate,
                                          BoundKind kind, TimeNs max_dt_ns) {
  LaserEfficiencySums s;
  if (!bound.ok || !bound.laser_only || estimate.empty()) return s;
  const std::vector<std::string>& names = LaserQuantityNames();
  std::vector<int> column(names.size());
  for (size_t i = 0; i < names.size(); ++i) column[i] = estimate.Index(names[i]);
  // Rows by time (the table is appended in time order by every estimator; sort to be safe).
  std::vector<size_t> order(estimate.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(),
            [&](size_t a, size_t b) { return estimate.t_ns[a] < estimate.t_ns[b]; });
  for (const CrlbKeyframe& kf : bound.keyframes) {
    if (!kf.laser) continue;
    const Eigen::Matrix<double, 5, 5>* C = kind == BoundKind::kSmoothing ? &kf.laser->smoothing
                                           : kf.laser->filtering         ? &*kf.laser->filtering
                                                                         : nullptr;
    if (!C) continue;
    auto it = std::lower_bound(order.begin(), order.end(), kf.t_ns - max_dt_ns,
                               [&](size_t row, TimeNs t) { return estimate.t_ns[row] < t; });
    const size_t* best = nullptr;
    for (; it != order.end() && estimate.t_ns[*it] <= kf.t_ns + max_dt_ns; ++it)
      if (!best ||
          std::abs(estimate.t_ns[*it] - kf.t_ns) < std::abs(estimate.t_ns[*best] - kf.t_ns))
        best = &*it;
    if (!best) continue;
    for (size_t i = 0; i < names.size(); ++i) {
      if (column[i] < 0) continue;
      const double value = estimate.rows[*best][column[i]];
      const double variance = (*C)(i, i);
      if (!std::isfinite(value) || !std::isfinite(variance) || !(variance > 0.0)) continue;
      double error = value - kf.laser->truth(i);
      if (LaserQuantityUnits()[i] == "rad") error = WrapAngle(error);
      QuantityEfficiency& q = s.quantities[names[i]];
      q.error2 += error * error;
      q.bound2 += variance;
      ++q.frames;
    }
  }
  bool any = false;
  for (auto& [name, q] : s.quantities) {
    if (q.frames == 0) continue;
    any = true;
    q.run_error2 = {q.error2 / q.frames};
    q.run_bound2 = {q.bound2 / q.frames};
  }
  if (any) s.runs = 1;
  return s;
}

nlohmann::json LaserEfficiencySumsToJson(const LaserEfficiencySums& sums) {
  nlohmann::json quantities = nlohmann::json::object();
  for (const auto& [name, q] : sums.quantities)
    quantities[name] = {{"error2", JsonNumber(q.error2)},
                        {"bound2", JsonNumber(q.bound2)},
                        {"frames", q.frames},
                        {"run_error2", JsonNumbers(q.run_error2)},
                        {"run_bound2", JsonNumbers(q.run_bound2)}};
  return {{"runs", sums.runs}, {"quantities", quantities}};
}

LaserEfficiencySums LaserEfficiencySumsFromJson(const nlohmann::json& json) {
  LaserEfficiencySums sums;
  sums.runs = json.at("runs").get<int>();
  const nlohmann::json& quantities = json.at("quantities");
  for (auto it = quantities.begin(); it != quantities.end(); ++it) {
    const nlohmann::json& j = it.value();
    QuantityEfficiency q;
    q.error2 = NumberFromJson(j.at("error2"));
    q.bound2 = NumberFromJson(j.at("bound2"));
    q.frames = j.at("frames").get<int>();
    q.run_error2 = NumbersFromJson(j.at("run_error2"));
    q.run_bound2 = NumbersFromJson(j.at("run_bound2"));
    sums.quantities[it.key()] = q;
  }
  return sums;
}

}  // namespace mavloc
