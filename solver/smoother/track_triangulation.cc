#include "solver/smoother/track_triangulation.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <unordered_map>

namespace mavloc {

namespace {

struct Ray {
  Eigen::Vector3d c_W;  // camera centre
  Eigen::Vector3d d_W;  // unit direction
};

}  // namespace

std::map<int, Eigen::Vector3d> TriangulateTracks(const Dataset& dataset,
                                                 const std::vector<SmootherKeyframe>& keyframes,
                                                 const std::set<int>& skip,
                                                 const TrackTriangulationOptions& options) {
  std::map<int, Eigen::Vector3d> result;
  if (dataset.cameras.empty() || keyframes.empty()) return result;
  std::vector<TimeNs> times;
  for (const auto& kf : keyframes) times.push_back(kf.t_ns);
  std::unordered_map<int, std::vector<Ray>> rays;
  for (const std::vector<FeatureObservation>* stream : {&dataset.features, &dataset.features1}) {
    for (const FeatureObservation& obs : *stream) {
      if (skip.count(obs.landmark_id) || obs.camera >= static_cast<int>(dataset.cameras.size()))
        continue;
      auto it = std::lower_bound(times.begin(), times.end(), obs.t_ns);
      if (it == times.end() || *it != obs.t_ns) continue;
      const ImuKeyframeState& s = keyframes[it - times.begin()].state;
      const Pose T_W_C = Pose(s.q_W_B, s.p_W) * dataset.cameras[obs.camera].T_B_C;
      rays[obs.landmark_id].push_back(
          {T_W_C.p, (T_W_C.q * Eigen::Vector3d(obs.xy.x(), obs.xy.y(), 1.0)).normalized()});
    }
  }
  const double min_cos = std::cos(options.min_parallax_rad);
  for (const auto& [id, track_rays] : rays) {
    if (track_rays.size() < 2) continue;
    double smallest_cos = 1.0;
    for (const Ray& r : track_rays)
      smallest_cos = std::min(smallest_cos, r.d_W.dot(track_rays.front().d_W));
    if (smallest_cos > min_cos) continue;  // too little parallax
    Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
    Eigen::Vector3d b = Eigen::Vector3d::Zero();
    for (const Ray& r : track_rays) {
      const Eigen::Matrix3d P = Eigen::Matrix3d::Identity() - r.d_W * r.d_W.transpose();
      A += P;
      b += P * r.c_W;
    }
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(A);
    if (!(eig.eigenvalues()[0] > 1e-9 * eig.eigenvalues()[2])) continue;
    const Eigen::Vector3d p_W = A.ldlt().solve(b);
    bool good = p_W.allFinite();
    for (const Ray& r : track_rays) {
      const Eigen::Vector3d v = p_W - r.c_W;
      const double along = v.dot(r.d_W);
      if (!(along > 0.0) ||
          std::acos(std::clamp(along / v.norm(), -1.0, 1.0)) > options.max_error_rad) {
        good = false;
        break;
      }
    }
    if (good) result[id] = p_W;
  }
  return result;
}

}  // namespace mavloc
