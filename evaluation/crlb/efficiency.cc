#include "evaluation/crlb/efficiency.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/numbers.h"
#include "core/rotation.h"
#include "evaluation/json_number.h"

namespace mavloc {

namespace {
double Ratio(double a, double b) { return b > 0.0 ? std::sqrt(a / b) : kNaN; }

}  // namespace

nlohmann::json EfficiencySumsToJson(const EfficiencySums& e) {
  nlohmann::json per_time = nlohmann::json::array();
  for (const auto& [t, v] : e.per_time)
    per_time.push_back({t, JsonNumber(v[0]), JsonNumber(v[1]), JsonNumber(v[2]), JsonNumber(v[3]),
                        JsonNumber(v[4])});
  return {{"position_error2", JsonNumber(e.position_error2)},
          {"position_bound2", JsonNumber(e.position_bound2)},
          {"attitude_error2", JsonNumber(e.attitude_error2)},
          {"attitude_bound2", JsonNumber(e.attitude_bound2)},
          {"frames", e.frames},
          {"runs", e.runs},
          {"run_position_error2", JsonNumbers(e.run_position_error2)},
          {"run_position_bound2", JsonNumbers(e.run_position_bound2)},
          {"run_attitude_error2", JsonNumbers(e.run_attitude_error2)},
          {"run_attitude_bound2", JsonNumbers(e.run_attitude_bound2)},
          {"per_time", per_time}};
}

EfficiencySums EfficiencySumsFromJson(const nlohmann::json& j) {
  EfficiencySums e;
  e.position_error2 = NumberFromJson(j.at("position_error2"));
  e.position_bound2 = NumberFromJson(j.at("position_bound2"));
  e.attitude_error2 = NumberFromJson(j.at("attitude_error2"));
  e.attitude_bound2 = NumberFromJson(j.at("attitude_bound2"));
  e.frames = j.at("frames").get<int>();
  e.runs = j.at("runs").get<int>();
  e.run_position_error2 = NumbersFromJson(j.at("run_position_error2"));
  e.run_position_bound2 = NumbersFromJson(j.at("run_position_bound2"));
  e.run_attitude_error2 = NumbersFromJson(j.at("run_attitude_error2"));
  e.run_attitude_bound2 = NumbersFromJson(j.at("run_attitude_bound2"));
  for (const auto& row : j.at("per_time")) {
    std::array<double, 5> v;
    for (int i = 0; i < 5; ++i) v[i] = NumberFromJson(row.at(i + 1));
    e.per_time[row.at(0).get<TimeNs>()] = v;
  }
  return e;
}

void EfficiencySums::Add(const EfficiencySums& o) {
  position_error2 += o.position_error2;
  position_bound2 += o.position_bound2;
  attitude_error2 += o.attitude_error2;
  attitude_bound2 += o.attitude_bound2;
  frames += o.frames;
  runs += o.runs;
  for (auto [to, from] : {std::pair{&run_position_error2, &o.run_position_error2},
                          std::pair{&run_position_bound2, &o.run_position_bound2},
                          std::pair{&run_attitude_error2, &o.run_attitude_error2},
                          std::pair{&run_attitude_bound2, &o.run_attitude_bound2}})
    to->insert(to->end(), from->begin(), from->end());
  for (const auto& [t, v] : o.per_time) {
    auto& cell = per_time[t];
    for (size_t i = 0; i < v.size(); ++i) cell[i] += v[i];
  }
}

double EfficiencySums::PositionBoundRms() const {
  return frames > 0 ? std::sqrt(position_bound2 / frames) : kNaN;
}
double EfficiencySums::AttitudeBoundRms() const {
  return frames > 0 ? std::sqrt(attitude_bound2 / frames) : kNaN;
}
double EfficiencySums::PositionRatio() const { return Ratio(position_error2, position_bound2); }
double EfficiencySums::AttitudeRatio() const { return Ratio(attitude_error2, attitude_bound2); }

EfficiencySums CompareWithBound(const SmootherCrlb& bound, const std::vector<StampedPose>& poses,
                                BoundKind kind, TimeNs max_dt_ns) {
  EfficiencySums s;
  if (!bound.ok || poses.empty()) return s;
  std::vector<StampedPose> sorted = poses;
  std::sort(sorted.begin(), sorted.end(),
            [](const StampedPose& a, const StampedPose& b) { return a.t_ns < b.t_ns; });
  for (const CrlbKeyframe& kf : bound.keyframes) {
    const Matrix15d* C = kind == BoundKind::kSmoothing ? &kf.smoothing
                         : kf.filtering                ? &*kf.filtering
                                                       : nullptr;
    if (!C) continue;
    auto it = std::lower_bound(sorted.begin(), sorted.end(), kf.t_ns - max_dt_ns,
                               [](const StampedPose& p, TimeNs t) { return p.t_ns < t; });
    const StampedPose* best = nullptr;
    for (; it != sorted.end() && it->t_ns <= kf.t_ns + max_dt_ns; ++it)
      if (!best || std::abs(it->t_ns - kf.t_ns) < std::abs(best->t_ns - kf.t_ns)) best = &*it;
    if (!best) continue;
    const double angle = LogQuaternion(kf.T_W_B.q.conjugate() * best->T_W_B.q).norm();
    s.position_error2 += (best->T_W_B.p - kf.T_W_B.p).squaredNorm();
    s.attitude_error2 += angle * angle;
    s.position_bound2 += C->block<3, 3>(kCrlbP, kCrlbP).trace();
    s.attitude_bound2 += C->block<3, 3>(kCrlbTheta, kCrlbTheta).trace();
    ++s.frames;
    s.per_time[(kf.t_ns + 500'000) / 1'000'000 * 1'000'000] = {
        (best->T_W_B.p - kf.T_W_B.p).squaredNorm(), C->block<3, 3>(kCrlbP, kCrlbP).trace(),
        angle * angle, C->block<3, 3>(kCrlbTheta, kCrlbTheta).trace(), 1.0};
  }
  if (s.frames > 0) {
    s.runs = 1;
    s.run_position_error2 = {s.position_error2 / s.frames};
    s.run_position_bound2 = {s.position_bound2 / s.frames};
    s.run_attitude_error2 = {s.attitude_error2 / s.frames};
    s.run_attitude_bound2 = {s.attitude_bound2 / s.frames};
  }
  return s;
}

}  // namespace mavloc
