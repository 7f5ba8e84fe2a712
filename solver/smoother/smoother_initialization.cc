#include "solver/smoother/smoother_initialization.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "core/rotation.h"
#include "solver/imu/imu_integrator.h"
#include "solver/pose/corner_pnp.h"

namespace mavloc {

namespace {

// The state at t_ns < later.t_ns from the IMU between them, backwards: with the preintegrated
// dR, dv, dp at zero biases (Forster eq. 33), R_i = R_j dR^T, v_i = v_j - g dt - R_i dv,
// p_i = p_j - v_i dt - g dt^2 / 2 - R_i dp (exact for the preintegrated measurements).
SmootherKeyframe PredictBackwards(const std::vector<ImuSample>& imu, const SmootherKeyframe& later,
                                  TimeNs t_ns) {
  const ImuPreintegration pre(imu, t_ns, later.t_ns, ImuBiases{}, ImuNoise{});
  const double dt = pre.dt_s();
  SmootherKeyframe kf;
  kf.t_ns = t_ns;
  kf.state.q_W_B = (later.state.q_W_B * pre.delta_q().conjugate()).normalized();
  const Eigen::Matrix3d R_i = kf.state.q_W_B.toRotationMatrix();
  kf.state.v_W = later.state.v_W - GravityW() * dt - R_i * pre.delta_v();
  kf.state.p_W =
      later.state.p_W - kf.state.v_W * dt - 0.5 * GravityW() * dt * dt - R_i * pre.delta_p();
  return kf;
}

}  // namespace

void BridgeBackwards(const Dataset& dataset, const std::vector<TimeNs>& keyframe_times,
                     SmootherInitialization* init) {
  if (init->keyframes.empty()) return;
  int bridged = 0;
  for (auto it = keyframe_times.rbegin(); it != keyframe_times.rend(); ++it) {
    if (*it >= init->keyframes.front().t_ns) continue;
    init->keyframes.insert(init->keyframes.begin(),
                           PredictBackwards(dataset.imu.samples, init->keyframes.front(), *it));
    init->seeded.insert(init->seeded.begin(), false);
    ++bridged;
  }
  if (bridged > 0)
    init->failures["keyframe before the first seed pose (bridged backwards)"] += bridged;
}

std::vector<TimeNs> SmootherKeyframeTimes(const Dataset& dataset, int stride) {
  std::vector<TimeNs> times;
  if (dataset.imu.samples.size() < 2) return times;
  const TimeNs first = dataset.imu.samples.front().t_ns, last = dataset.imu.samples.back().t_ns;
  auto add = [&](TimeNs t) {
    if (t >= first && t <= last) times.push_back(t);
  };
  if (!dataset.cameras.empty())
    for (const auto& f : dataset.cameras.front().frames) add(f.t_ns);
  for (const auto& o : dataset.features) add(o.t_ns);
  for (const auto& o : dataset.tags) add(o.t_ns);
  for (const auto& o : dataset.tags1) add(o.t_ns);
  for (const auto& o : dataset.laser) add(o.t_ns);
  std::sort(times.begin(), times.end());
  times.erase(std::unique(times.begin(), times.end()), times.end());
  if (stride > 1) {
    std::vector<TimeNs> kept;
    for (size_t k = 0; k < times.size(); k += stride) kept.push_back(times[k]);
    times = kept;
  }
  return times;
}

std::vector<StampedPose> SeedPoses(const Estimate& seed) {
  if (!seed.poses.empty()) return seed.poses;
  std::vector<StampedPose> poses;
  const QuantityTable& q = seed.quantities;
  const int ix = q.Index("x"), iy = q.Index("y"), iz = q.Index("z");
  const int ir = q.Index("roll"), ip = q.Index("pitch"), iw = q.Index("yaw");
  if (ix < 0 || iy < 0 || iz < 0 || ir < 0 || ip < 0 || iw < 0) return poses;
  for (size_t i = 0; i < q.size(); ++i) {
    const auto& row = q.rows[i];
    bool finite = true;
    for (int c : {ix, iy, iz, ir, ip, iw}) finite = finite && std::isfinite(row[c]);
    if (!finite) continue;
    const Pose T_W_B(QuaternionFromEuler({row[ir], row[ip], row[iw]}),
                     Eigen::Vector3d(row[ix], row[iy], row[iz]));
    poses.push_back({q.t_ns[i], T_W_B});
  }
  return poses;
}

SmootherInitialization InitializeFromSeed(const Dataset& dataset,
                                          const std::vector<TimeNs>& keyframe_times,
                                          const std::vector<StampedPose>& seed_poses,
                                          const SmootherInitializationOptions& options) {
  SmootherInitialization init;
  const int n = static_cast<int>(keyframe_times.size());
  const TimeNs tolerance_ns = SecondsToNs(options.match_tolerance_s);

  // The seed pose of each keyframe (nearest in time within the tolerance).
  std::vector<const Pose*> seed(n, nullptr);
  std::vector<StampedPose> sorted = seed_poses;
  std::sort(sorted.begin(), sorted.end(),
            [](const StampedPose& a, const StampedPose& b) { return a.t_ns < b.t_ns; });
  for (int k = 0; k < n; ++k) {
    auto it = std::lower_bound(sorted.begin(), sorted.end(), keyframe_times[k],
                               [](const StampedPose& s, TimeNs t) { return s.t_ns < t; });
    TimeNs best_dt = tolerance_ns + 1;
    for (auto c : {it, it == sorted.begin() ? it : std::prev(it)}) {
      if (c == sorted.end()) continue;
      const TimeNs dt = std::abs(c->t_ns - keyframe_times[k]);
      if (dt < best_dt && c->T_W_B.p.allFinite() && c->T_W_B.q.coeffs().allFinite()) {
        best_dt = dt;
        seed[k] = &c->T_W_B;
      }
    }
  }

  // Finite-difference velocity of a seeded keyframe from its nearest seeded neighbours.
  const TimeNs window_ns = SecondsToNs(options.max_difference_window_s);
  auto velocity = [&](int k) -> Eigen::Vector3d {
    int before = -1, after = -1;
    for (int j = k - 1; j >= 0 && keyframe_times[k] - keyframe_times[j] <= window_ns; --j)
      if (seed[j]) {
        before = j;
        break;
      }
    for (int j = k + 1; j < n && keyframe_times[j] - keyframe_times[k] <= window_ns; ++j)
      if (seed[j]) {
        after = j;
        break;
      }
    const int a = before >= 0 ? before : k, b = after >= 0 ? after : k;
    if (a == b) return Eigen::Vector3d::Zero();
    return (seed[b]->p - seed[a]->p) / NsToSeconds(keyframe_times[b] - keyframe_times[a]);
  };

  const ImuIntegrator integrator(&dataset.imu.samples);
  const ImuBiases zero_biases;
  int first = 0;
  while (first < n && !seed[first]) ++first;
  for (int k = first; k < n; ++k) {
    std::optional<NavState> predicted;
    if (!init.keyframes.empty()) {
      const SmootherKeyframe& prev = init.keyframes.back();
      NavState x{prev.t_ns, prev.state.q_W_B, prev.state.p_W, prev.state.v_W};
      predicted = integrator.Integrate(x, keyframe_times[k], zero_biases);
    }
    SmootherKeyframe kf;
    kf.t_ns = keyframe_times[k];
    bool use_seed = seed[k] != nullptr;
    if (use_seed && predicted && init.seeded.back() &&
        (seed[k]->p - predicted->p_W).norm() > options.gate_m) {
      use_seed = false;
      ++init.failures["seed pose rejected (far from the IMU prediction)"];
    }
    if (use_seed) {
      kf.state.q_W_B = seed[k]->q.normalized();
      kf.state.p_W = seed[k]->p;
      kf.state.v_W = velocity(k);
    } else {
      if (!seed[k]) ++init.failures["no seed pose (bridged by IMU prediction)"];
      kf.state.q_W_B = predicted->q_W_B;
      kf.state.p_W = predicted->p_W;
      kf.state.v_W = predicted->v_W;
    }
    init.keyframes.push_back(kf);
    init.seeded.push_back(use_seed);
  }
  BridgeBackwards(dataset, keyframe_times, &init);
  return init;
}

std::map<int, Eigen::Vector3d> TriangulateFeatures(const Dataset& dataset,
                                                   const std::vector<SmootherKeyframe>& keyframes,
                                                   bool on_ground) {
  std::map<int, Eigen::Vector3d> result;
  if (dataset.cameras.empty()) return result;
  const Pose& T_B_C = dataset.cameras.front().T_B_C;
  std::vector<TimeNs> times;
  for (const auto& kf : keyframes) times.push_back(kf.t_ns);
  struct Accumulator {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
    Eigen::Vector3d b = Eigen::Vector3d::Zero();
    int count = 0;
  };
  std::map<int, Accumulator> acc;
  for (const FeatureObservation& obs : dataset.features) {
    auto it = std::lower_bound(times.begin(), times.end(), obs.t_ns);
    if (it == times.end() || std::abs(*it - obs.t_ns) > 1'000'000) continue;
    const ImuKeyframeState& s = keyframes[it - times.begin()].state;
    const Pose T_W_C = Pose(s.q_W_B, s.p_W) * T_B_C;
    const Eigen::Vector3d c_W = T_W_C.p;
    const Eigen::Vector3d d_W =
        (T_W_C.q * Eigen::Vector3d(obs.xy.x(), obs.xy.y(), 1.0)).normalized();
    Accumulator& a = acc[obs.landmark_id];
    if (on_ground) {
      if (!(d_W.z() < -1e-6)) continue;  // the ray must go down to z = 0
      const double s_m = -c_W.z() / d_W.z();
      if (s_m <= 0.0) continue;
      a.sum += c_W + s_m * d_W;
      ++a.count;
    } else {
      const Eigen::Matrix3d P = Eigen::Matrix3d::Identity() - d_W * d_W.transpose();
      a.A += P;
      a.b += P * c_W;
      ++a.count;
    }
  }
  for (const auto& [id, a] : acc) {
    if (a.count == 0) continue;
    if (on_ground) {
      result[id] = a.sum / a.count;
    } else {
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(a.A);
      if (a.count < 2 || eig.eigenvalues()[0] < 1e-6 * std::max(1.0, eig.eigenvalues()[2]))
        continue;
      result[id] = a.A.ldlt().solve(a.b);
    }
  }
  return result;
}

}  // namespace mavloc

namespace mavloc {

std::optional<Plane> FitLaserPlane(const Dataset& dataset,
                                   const std::vector<SmootherKeyframe>& keyframes,
                                   const LaserBeam& beam) {
  if (dataset.cameras.empty() || keyframes.empty()) return std::nullopt;
  const Pose& T_B_C = dataset.cameras.front().T_B_C;
  std::vector<TimeNs> times;
  for (const auto& kf : keyframes) times.push_back(kf.t_ns);
  std::vector<Eigen::Vector3d> spots_W;
  const Eigen::Vector3d l = beam.direction_C.normalized();
  for (const LaserObservation& obs : dataset.laser) {
    auto it = std::lower_bound(times.begin(), times.end(), obs.t_ns);
    if (it == times.end() || std::abs(*it - obs.t_ns) > 1'000'000) continue;
    const ImuKeyframeState& s = keyframes[it - times.begin()].state;
    // Closest points of the rays t b (camera) and o + s l (laser), in C.
    const Eigen::Vector3d b = Eigen::Vector3d(obs.xy.x(), obs.xy.y(), 1.0).normalized();
    const Eigen::Vector3d& o = beam.origin_C;
    const double bl = b.dot(l), denominator = 1.0 - bl * bl;
    if (denominator < 1e-9) continue;
    const double t = (b.dot(o) - bl * l.dot(o)) / denominator;
    const double s_m = t * bl - l.dot(o);
    if (t <= 0.0 || s_m <= 0.0) continue;
    const Eigen::Vector3d spot_C = 0.5 * (t * b + o + s_m * l);
    spots_W.push_back(Pose(s.q_W_B, s.p_W) * (T_B_C * spot_C));
  }
  if (spots_W.size() < 3) return std::nullopt;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& p : spots_W) mean += p / static_cast<double>(spots_W.size());
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (const auto& p : spots_W) scatter += (p - mean) * (p - mean).transpose();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(scatter);
  if (eig.eigenvalues()[1] < 1e-6 * eig.eigenvalues()[2]) return std::nullopt;  // collinear spots
  Plane plane;
  plane.n_W = eig.eigenvectors().col(0).normalized();
  const Eigen::Vector3d camera_W =
      (Pose(keyframes.front().state.q_W_B, keyframes.front().state.p_W) * T_B_C).p;
  if (plane.n_W.dot(camera_W - mean) < 0.0) plane.n_W = -plane.n_W;
  plane.d_m = plane.n_W.dot(mean);
  return plane;
}

}  // namespace mavloc

namespace mavloc {

std::vector<StampedPose> LandmarkPnpSeed(const Dataset& dataset,
                                         std::map<std::string, int>* failures) {
  std::vector<StampedPose> poses;
  if (dataset.cameras.empty()) return poses;
  const CameraSensor& camera = dataset.cameras.front();
  const CameraModel& model = camera.model;
  size_t i = 0;
  while (i < dataset.features.size()) {
    const TimeNs t_ns = dataset.features[i].t_ns;
    std::vector<Eigen::Vector3d> X_W;
    std::vector<Eigen::Vector2d> uv_ideal;
    for (; i < dataset.features.size() && dataset.features[i].t_ns == t_ns; ++i) {
      const FeatureObservation& obs = dataset.features[i];
      auto it = dataset.map.landmarks_W.find(obs.landmark_id);
      if (it == dataset.map.landmarks_W.end()) continue;
      X_W.push_back(it->second);
      uv_ideal.emplace_back(model.fu() * obs.xy.x() + model.cu(),
                            model.fv() * obs.xy.y() + model.cv());
    }
    if (X_W.size() < 4) {
      if (failures) ++(*failures)["landmark-pnp: fewer than 4 landmarks"];
      continue;
    }
    const CornerPnpResult r = CornerPnpFromCorrespondences(X_W, uv_ideal, camera);
    if (!r.ok) {
      if (failures) ++(*failures)["landmark-pnp: " + r.reason];
      continue;
    }
    poses.push_back({t_ns, r.T_W_B});
  }
  return poses;
}

std::vector<StampedPose> TagPnpSeed(const Dataset& dataset, int camera_index,
                                    std::map<std::string, int>* failures) {
  std::vector<StampedPose> poses;
  const std::vector<TagObservation>* stream = camera_index == 0   ? &dataset.tags
                                              : camera_index == 1 ? &dataset.tags1
                                                                  : nullptr;
  if (!stream || camera_index >= static_cast<int>(dataset.cameras.size())) return poses;
  const CameraSensor& camera = dataset.cameras[camera_index];
  for (size_t begin = 0; begin < stream->size();) {
    size_t end = begin;
    while (end < stream->size() && (*stream)[end].t_ns == (*stream)[begin].t_ns) ++end;
    const std::vector<TagObservation> frame(stream->begin() + begin, stream->begin() + end);
    const CornerPnpResult r = CornerPnp(frame, dataset.map.tags, camera);
    if (r.ok) {
      poses.push_back({frame.front().t_ns, r.T_W_B});
    } else if (failures) {
      ++(*failures)["tag-pnp " + camera.name + ": " + r.reason];
    }
    begin = end;
  }
  return poses;
}

}  // namespace mavloc

namespace mavloc {

SmootherInitialization InitializeFromLaserModes(const Dataset& dataset,
                                                const std::vector<TimeNs>& keyframe_times,
                                                const QuantityTable& modes, Plane* gauge_plane) {
  SmootherInitialization init;
  const int i_d = modes.Index("d"), i_v = modes.Index("v_o"), i_r = modes.Index("roll");
  const int i_p = modes.Index("pitch"), i_a = modes.Index("alpha");
  if (i_d < 0 || i_v < 0 || i_r < 0 || i_p < 0 || i_a < 0 || dataset.cameras.empty() ||
      modes.empty()) {
    init.failures["laser modes missing (d, v_o, roll, pitch, alpha)"] +=
        static_cast<int>(keyframe_times.size());
    return init;
  }
  std::vector<double> alphas;
  for (const auto& row : modes.rows)
    if (std::isfinite(row[i_a])) alphas.push_back(row[i_a]);
  if (alphas.empty()) return init;
  std::nth_element(alphas.begin(), alphas.begin() + alphas.size() / 2, alphas.end());
  const double alpha = alphas[alphas.size() / 2];
  const Eigen::Matrix3d R_W_P = Rx(alpha);
  const Eigen::Vector3d n_W = R_W_P.col(2);
  gauge_plane->n_W = n_W;
  gauge_plane->d_m = 0.0;

  const Pose& T_B_C = dataset.cameras.front().T_B_C;
  const std::vector<ImuSample>& imu = dataset.imu.samples;
  const ImuIntegrator integrator(&imu);
  auto mode_row = [&](TimeNs t) -> const std::vector<double>* {
    auto it = std::lower_bound(modes.t_ns.begin(), modes.t_ns.end(), t);
    const std::vector<double>* best = nullptr;
    TimeNs best_dt = 20'000'000;
    for (auto c : {it, it == modes.t_ns.begin() ? it : std::prev(it)}) {
      if (c == modes.t_ns.end()) continue;
      const auto& row = modes.rows[c - modes.t_ns.begin()];
      const TimeNs dt = std::abs(*c - t);
      if (dt <= best_dt && std::isfinite(row[i_d]) && std::isfinite(row[i_r]) &&
          std::isfinite(row[i_p])) {
        best_dt = dt;
        best = &row;
      }
    }
    return best;
  };
  auto up_in_camera = [&](TimeNs t) {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    const TimeNs half = 500'000'000;
    auto it = std::lower_bound(imu.begin(), imu.end(), t - half,
                               [](const ImuSample& s, TimeNs x) { return s.t_ns < x; });
    for (; it != imu.end() && it->t_ns <= t + half; ++it) sum += it->accel_m_s2;
    return Eigen::Vector3d(T_B_C.q.conjugate() * sum).normalized();
  };

  for (const TimeNs t : keyframe_times) {
    const std::vector<double>* row = mode_row(t);
    std::optional<NavState> predicted;
    if (!init.keyframes.empty()) {
      const SmootherKeyframe& prev = init.keyframes.back();
      predicted = integrator.Integrate(
          {prev.t_ns, prev.state.q_W_B, prev.state.p_W, prev.state.v_W}, t, ImuBiases{});
    }
    // A diverged filter is not a seed: modes outside a plausible range, or a distance far from
    // the IMU prediction, are bridged like missing ones.
    if (row) {
      const double d = (*row)[i_d], v_o = (*row)[i_v];
      bool plausible = d > 0.02 && d < 50.0 && std::isfinite(v_o) && std::abs(v_o) < 10.0;
      if (plausible && predicted && init.seeded.back()) {
        const Eigen::Vector3d p_pred_C = predicted->p_W + predicted->q_W_B * T_B_C.p;
        plausible = std::abs(n_W.dot(p_pred_C) - d) < 0.5;
      }
      if (!plausible) {
        row = nullptr;
        if (predicted)
          ++init.failures["seed modes rejected (implausible or far from the IMU prediction)"];
      }
    }
    SmootherKeyframe kf;
    kf.t_ns = t;
    if (!row) {
      if (!predicted) continue;  // before the first seed: bridged backwards below
      ++init.failures["no seed pose (bridged by IMU prediction)"];
      kf.state.q_W_B = predicted->q_W_B;
      kf.state.p_W = predicted->p_W;
      kf.state.v_W = predicted->v_W;
      init.keyframes.push_back(kf);
      init.seeded.push_back(false);
      continue;
    }
    const double d = (*row)[i_d], v_o = std::isfinite((*row)[i_v]) ? (*row)[i_v] : 0.0;
    const Eigen::Matrix3d R_rp = RotationFromEuler({(*row)[i_r], (*row)[i_p], 0.0});
    // Yaw about the normal from gravity: Rz(psi) R_rp u_C = R_W_P^T e_z (both "up").
    const Eigen::Vector3d v = R_rp * up_in_camera(t),
                          w = R_W_P.transpose() * Eigen::Vector3d::UnitZ();
    const double psi =
        std::hypot(w.x(), w.y()) > 1e-3 ? std::atan2(w.y(), w.x()) - std::atan2(v.y(), v.x()) : 0.0;
    const Eigen::Matrix3d R_W_C = R_W_P * Rz(psi) * R_rp;
    const Eigen::Matrix3d R_W_B = R_W_C * T_B_C.R().transpose();
    Eigen::Vector3d p_W_C = d * n_W, v_W = v_o * n_W;
    if (predicted) {
      const Eigen::Vector3d p_pred_C = predicted->p_W + R_W_B * T_B_C.p;
      p_W_C = p_pred_C + (d - n_W.dot(p_pred_C)) * n_W;
      v_W = predicted->v_W + (v_o - n_W.dot(predicted->v_W)) * n_W;
    }
    kf.state.q_W_B = Eigen::Quaterniond(R_W_B).normalized();
    kf.state.p_W = p_W_C - R_W_B * T_B_C.p;
    kf.state.v_W = v_W;
    init.keyframes.push_back(kf);
    init.seeded.push_back(true);
  }
  BridgeBackwards(dataset, keyframe_times, &init);
  return init;
}

}  // namespace mavloc
