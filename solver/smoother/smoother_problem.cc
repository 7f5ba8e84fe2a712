#include "solver/smoother/smoother_problem.h"

#include <ceres/ceres.h>
#include <ceres/sphere_manifold.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <set>

#include "core/board_frame.h"
#include "core/rotation.h"
#include "core/tag_geometry.h"
#include "solver/smoother/imu_time_shift.h"
#include "solver/smoother/residuals/anchored_bearing_factor.h"
#include "solver/smoother/residuals/bias_random_walk_factor.h"
#include "solver/smoother/residuals/calibrated_reprojection_factor.h"
#include "solver/smoother/residuals/feature_bearing_factor.h"
#include "solver/smoother/residuals/imu_factor.h"
#include "solver/smoother/residuals/laser_spot_plane_factor.h"
#include "solver/smoother/residuals/map_point_reprojection_factor.h"
#include "solver/smoother/residuals/marginal_prior_factor.h"
#include "solver/smoother/residuals/pose_prior_factor.h"
#include "solver/smoother/residuals/vector_prior_factor.h"
#include "solver/smoother/smoother_covariance.h"
#include "solver/smoother/smoother_marginalization.h"
#include "solver/smoother/tilt_manifold.h"

namespace mavloc {

namespace {

constexpr TimeNs kAttachToleranceNs = 1'000'000;  // 1 ms

// A map point's reprojection factor, analytic unless the options ask for the autodiff reference.
ceres::CostFunction* MapPointReprojection(const SmootherProblemOptions& options,
                                          const CameraModel& model, const Pose& T_B_C,
                                          const Eigen::Vector3d& p_W,
                                          const Eigen::Vector2d& uv_px) {
  return options.autodiff_jacobians
             ? MapPointReprojectionFactorAutoDiff::Create(model, T_B_C, p_W, uv_px,
                                                          options.pixel_sigma_px)
             : MapPointReprojectionFactor::Create(model, T_B_C, p_W, uv_px, options.pixel_sigma_px);
}

// Parameter storage of one keyframe (quaternion in Eigen order x, y, z, w).
struct KeyframeBlocks {
  std::array<double, 4> q{};
  std::array<double, 3> p{}, v{}, b_g{}, b_a{};
};

KeyframeBlocks ToBlocks(const ImuKeyframeState& s) {
  KeyframeBlocks b;
  const Eigen::Quaterniond q = s.q_W_B.normalized();
  b.q = {q.x(), q.y(), q.z(), q.w()};
  for (int k = 0; k < 3; ++k) {
    b.p[k] = s.p_W[k];
    b.v[k] = s.v_W[k];
    b.b_g[k] = s.biases.b_g[k];
    b.b_a[k] = s.biases.b_a[k];
  }
  return b;
}

ImuKeyframeState FromBlocks(const KeyframeBlocks& b) {
  ImuKeyframeState s;
  s.q_W_B = Eigen::Quaterniond(b.q[3], b.q[0], b.q[1], b.q[2]).normalized();
  s.p_W = Eigen::Vector3d(b.p.data());
  s.v_W = Eigen::Vector3d(b.v.data());
  s.biases.b_g = Eigen::Vector3d(b.b_g.data());
  s.biases.b_a = Eigen::Vector3d(b.b_a.data());
  return s;
}

ImuNoise WithFloor(const ImuNoise& noise, const ImuNoise& floor) {
  return {std::max(noise.gyroscope_noise_density, floor.gyroscope_noise_density),
          std::max(noise.gyroscope_random_walk, floor.gyroscope_random_walk),
          std::max(noise.accelerometer_noise_density, floor.accelerometer_noise_density),
          std::max(noise.accelerometer_random_walk, floor.accelerometer_random_walk)};
}

// Index of the keyframe at t (within the tolerance), or -1.
int KeyframeAt(const std::vector<TimeNs>& times, TimeNs t_ns) {
  auto it = std::lower_bound(times.begin(), times.end(), t_ns);
  int best = -1;
  TimeNs best_dt = kAttachToleranceNs + 1;
  for (auto c : {it, it == times.begin() ? it : std::prev(it)}) {
    if (c == times.end()) continue;
    const TimeNs dt = std::abs(*c - t_ns);
    if (dt < best_dt) {
      best_dt = dt;
      best = static_cast<int>(c - times.begin());
    }
  }
  return best_dt <= kAttachToleranceNs ? best : -1;
}

// Relative regularization of the IMU noise fit's information matrix (SmootherCovarianceOptions):
// small against every constrained direction's curvature, large against long double rounding.
constexpr double kImuFitRegularization = 1e-9;

double Seconds(std::chrono::steady_clock::duration d) {
  return std::chrono::duration<double>(d).count();
}

// Calibration storage: one extrinsic per camera (quaternion in Eigen order x, y, z, w).
struct ExtrinsicBlocks {
  std::array<double, 4> q{};
  std::array<double, 3> p{};
  Pose prior;  // the dataset's T_B_C
};

std::array<double, 4> QuaternionBlock(const Eigen::Quaterniond& q_raw) {
  const Eigen::Quaterniond q = q_raw.normalized();
  return {q.x(), q.y(), q.z(), q.w()};
}

Eigen::Quaterniond QuaternionFromBlock(const std::array<double, 4>& b) {
  return Eigen::Quaterniond(b[3], b[0], b[1], b[2]).normalized();
}

// The tag observations of camera index c (tags0, tags1); empty for other indices.
const std::vector<TagObservation>& TagStream(const Dataset& dataset, int c) {
  static const std::vector<TagObservation> kNone;
  return c == 0 ? dataset.tags : c == 1 ? dataset.tags1 : kNone;
}

// Ceres' quaternion tangent is a left perturbation of half the angle:
// q (+) delta = [cos|delta|, sin|delta| delta/|delta|] q, so dtheta_right = 2 R^T delta. Returns
// the 6 x 6 covariance of [p; dtheta_right] from the tangent-space blocks.
Eigen::Matrix<double, 6, 6> PoseCovarianceFromTangent(const Eigen::Matrix3d& pp,
                                                      const Eigen::Matrix3d& qq,
                                                      const Eigen::Matrix3d& pq,
                                                      const Eigen::Quaterniond& q) {
  const Eigen::Matrix3d M = 2.0 * q.toRotationMatrix().transpose();
  Eigen::Matrix<double, 6, 6> C;
  C.topLeftCorner<3, 3>() = pp;
  C.topRightCorner<3, 3>() = pq * M.transpose();
  C.bottomLeftCorner<3, 3>() = M * pq.transpose();
  C.bottomRightCorner<3, 3>() = M * qq * M.transpose();
  return C;
}

std::string LinearSolverDescription(const ceres::Solver::Options& o) {
  return std::string(ceres::LinearSolverTypeToString(o.linear_solver_type)) + " (" +
         ceres::SparseLinearAlgebraLibraryTypeToString(o.sparse_linear_algebra_library_type) + ")";
}

}  // namespace

void AddStatistics(const SmootherStatistics& from, SmootherStatistics* to) {
  to->iterations += from.iterations;
  to->solves += from.solves;
  to->preintegration_s += from.preintegration_s;
  to->solve_s += from.solve_s;
  to->linear_solver_s += from.linear_solver_s;
  to->residual_evaluation_s += from.residual_evaluation_s;
  to->jacobian_evaluation_s += from.jacobian_evaluation_s;
  to->covariance_s += from.covariance_s;
}

SmootherResult SolveSmoother(const Dataset& dataset, const std::vector<SmootherKeyframe>& initial,
                             const std::map<int, Eigen::Vector3d>& initial_landmarks_W,
                             const std::optional<Plane>& initial_plane,
                             const SmootherProblemOptions& options) {
  SmootherResult result;
  const int n = static_cast<int>(initial.size());
  result.statistics.num_keyframes = n;
  if (n < 2) {
    result.message = "fewer than 2 keyframes";
    return result;
  }
  if (dataset.cameras.empty() && (!dataset.features.empty() || !dataset.tags.empty())) {
    result.message = "visual measurements without a camera";
    return result;
  }
  const CameraSensor* camera = dataset.cameras.empty() ? nullptr : &dataset.cameras.front();
  std::vector<TimeNs> times;
  for (const auto& kf : initial) times.push_back(kf.t_ns);

  std::vector<KeyframeBlocks> blocks(n);
  for (int k = 0; k < n; ++k) blocks[k] = ToBlocks(initial[k].state);
  std::map<int, std::array<double, 3>> landmarks;
  for (const auto& [id, p] : initial_landmarks_W) landmarks[id] = {p.x(), p.y(), p.z()};
  // Feature tracks: anchored once at the initial keyframes, kept over the relinearization rounds.
  std::map<int, AnchoredTrack> tracks;
  if (options.landmarks == LandmarkMode::kTracks) {
    std::vector<Pose> T_W_B;
    for (const auto& kf : initial) T_W_B.emplace_back(kf.state.q_W_B, kf.state.p_W);
    tracks = AnchorTracks(dataset, times, T_W_B, initial_landmarks_W, options.tracks);
  }
  std::array<double, 3> plane_n{0.0, 0.0, 1.0};
  std::array<double, 1> plane_d{0.0};
  const bool use_laser =
      options.laser_beam && !dataset.laser.empty() && camera &&
      (options.estimate_plane ? initial_plane.has_value() : dataset.map.plane.has_value());
  if (use_laser) {
    const Plane plane = options.estimate_plane ? *initial_plane : *dataset.map.plane;
    const Eigen::Vector3d unit_n = plane.n_W.normalized();
    plane_n = {unit_n.x(), unit_n.y(), unit_n.z()};
    plane_d[0] = plane.d_m;
  }

  // Calibration blocks (kept over the relinearization rounds). The calibrated residual is used
  // when anything in it is estimated or not the identity / zero.
  const bool board = options.initial_q_W_M.has_value();
  const bool shifted = options.estimate_time_offset || options.initial_time_offset_s != 0.0;
  const bool calibrated = board || options.estimate_extrinsics || shifted;
  std::map<int, ExtrinsicBlocks> extrinsics;
  for (const int c : options.cameras) {
    if (TagStream(dataset, c).empty()) continue;
    if (c < 0 || c >= static_cast<int>(dataset.cameras.size())) {
      result.message =
          "tags" + std::to_string(c) + " without the calibration of cam" + std::to_string(c);
      return result;
    }
    ExtrinsicBlocks e;
    e.prior = dataset.cameras[c].T_B_C;
    auto it = options.initial_T_B_C.find(c);
    const Pose start = it != options.initial_T_B_C.end() ? it->second : e.prior;
    e.q = QuaternionBlock(start.q);
    e.p = {start.p.x(), start.p.y(), start.p.z()};
    extrinsics[c] = e;
  }
  std::array<double, 1> time_offset{options.initial_time_offset_s};
  std::array<double, 4> q_W_M =
      QuaternionBlock(options.initial_q_W_M.value_or(Eigen::Quaterniond::Identity()));

  const ImuNoise noise = WithFloor(dataset.imu.noise, options.noise_floor);
  ceres::EigenQuaternionManifold quaternion_manifold;
  TiltManifold tilt_manifold;
  ceres::SphereManifold<3> sphere_manifold;
  ceres::SubsetManifold fix_yz(3, {1, 2});  // P2 on the x axis
  ceres::SubsetManifold fix_z(3, {2});      // ground features on z = 0
  std::unique_ptr<ceres::LossFunction> loss;
  if (options.loss == SmootherLoss::kHuber)
    loss = std::make_unique<ceres::HuberLoss>(options.loss_scale);
  if (options.loss == SmootherLoss::kCauchy)
    loss = std::make_unique<ceres::CauchyLoss>(options.loss_scale);

  std::vector<ImuBiases> linearization(n);
  for (int k = 0; k < n; ++k) linearization[k] = initial[k].state.biases;

  for (int round = 0; round <= options.relinearize_rounds; ++round) {
    // Preintegration between consecutive keyframes at the current linearization biases.
    const auto t_pre = std::chrono::steady_clock::now();
    std::vector<ImuPreintegration> preintegrations;
    preintegrations.reserve(n - 1);
    for (int k = 0; k + 1 < n; ++k)
      preintegrations.emplace_back(dataset.imu.samples, times[k], times[k + 1], linearization[k],
                                   noise);
    // The motion around each keyframe over +-max_time_offset_s for the time offset.
    const auto zero_shift = std::make_shared<const ImuTimeShift>();
    std::vector<std::shared_ptr<const ImuTimeShift>> shifts(n, zero_shift);
    if (calibrated && shifted) {
      for (int k = 0; k < n; ++k)
        shifts[k] = std::make_shared<const ImuTimeShift>(FitImuTimeShift(
            dataset.imu.samples, times[k], linearization[k], options.max_time_offset_s));
    }
    result.statistics.preintegration_s += Seconds(std::chrono::steady_clock::now() - t_pre);

    ceres::Problem::Options problem_options;
    problem_options.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    problem_options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    ceres::Problem problem(problem_options);
    for (auto& b : blocks) {
      problem.AddParameterBlock(b.q.data(), 4, &quaternion_manifold);
      problem.AddParameterBlock(b.p.data(), 3);
      problem.AddParameterBlock(b.v.data(), 3);
      problem.AddParameterBlock(b.b_g.data(), 3);
      problem.AddParameterBlock(b.b_a.data(), 3);
    }
    const int num_constant = std::clamp(options.constant_keyframes, 0, n);
    for (int k = 0; k < num_constant; ++k)
      for (double* block : {blocks[k].q.data(), blocks[k].p.data(), blocks[k].v.data(),
                            blocks[k].b_g.data(), blocks[k].b_a.data()})
        problem.SetParameterBlockConstant(block);

    // Inertial factors.
    std::vector<ceres::ResidualBlockId> imu_group;
    for (int k = 0; k + 1 < n; ++k) {
      KeyframeBlocks& a = blocks[k];
      KeyframeBlocks& b = blocks[k + 1];
      const ImuPreintegration& pre = preintegrations[k];
      const Eigen::Matrix<double, 9, 9> sqrt_information = pre.SqrtInformation(1e-9, 1e-9, 1e-9);
      imu_group.push_back(problem.AddResidualBlock(
          options.autodiff_jacobians ? ImuFactorAutoDiff::Create(pre, sqrt_information)
                                     : ImuFactor::Create(pre, sqrt_information),
          nullptr, a.q.data(), a.p.data(), a.v.data(), a.b_g.data(), a.b_a.data(), b.q.data(),
          b.p.data(), b.v.data()));
      imu_group.push_back(problem.AddResidualBlock(
          BiasRandomWalkFactor::Create(noise.gyroscope_random_walk, noise.accelerometer_random_walk,
                                       pre.dt_s()),
          nullptr, a.b_g.data(), a.b_a.data(), b.b_g.data(), b.b_a.data()));
    }
    if (num_constant > 0) {
      // The constant context holds the first keyframe's biases.
    } else if (options.first_keyframe_prior) {
      problem.AddResidualBlock(new MarginalPriorFactor(*options.first_keyframe_prior), nullptr,
                               blocks[0].q.data(), blocks[0].p.data(), blocks[0].v.data(),
                               blocks[0].b_g.data(), blocks[0].b_a.data());
    } else {
      problem.AddResidualBlock(
          VectorPriorFactor::Create(Eigen::Vector3d::Zero(), options.gyro_bias_prior_rad_s),
          nullptr, blocks[0].b_g.data());
      problem.AddResidualBlock(
          VectorPriorFactor::Create(Eigen::Vector3d::Zero(), options.accel_bias_prior_m_s2),
          nullptr, blocks[0].b_a.data());
    }
    result.statistics.num_imu_factors = n - 1;
    for (const TimeNs t_ns : options.zero_velocity_times) {
      const int k = KeyframeAt(times, t_ns);
      if (k >= 0)
        problem.AddResidualBlock(
            VectorPriorFactor::Create(Eigen::Vector3d::Zero(), options.zero_velocity_sigma_m_s),
            nullptr, blocks[k].v.data());
    }

    // Visual residuals. An observation is dropped when no keyframe is at its time, or when its
    // point is behind the camera at the initial state (the residual is undefined there).
    std::map<std::string, int> dropped;
    const auto drop = [&](const std::string& reason, TimeNs t_ns) {
      if (t_ns < options.count_dropped_before_ns) ++dropped[reason];
    };
    std::vector<ceres::ResidualBlockId> corner_residuals;
    int num_visual = 0;
    int num_anchored = 0;  // residuals against known map points (they fix the gauge)
    auto initial_depth = [&](int k, const Eigen::Vector3d& p_W, const Pose& T_B_C) {
      const Pose T_W_B(FromBlocks(blocks[k]).q_W_B, Eigen::Vector3d(blocks[k].p.data()));
      return ((T_W_B * T_B_C).Inverse() * p_W).z();
    };
    // A track's observation: the anchor's own cam0 observation defines its bearing (no residual);
    // its cam1 observation at the anchor is a stereo residual on rho alone; any other keyframe's
    // observation couples the anchor and the observing keyframe (track_landmarks.h).
    std::set<int> tracks_in_problem;
    const auto add_track_residual = [&](const FeatureObservation& obs, int k,
                                        const CameraSensor& sensor) {
      auto it = tracks.find(obs.landmark_id);
      if (it == tracks.end()) {
        drop("feature: track without a cam0 observation at a keyframe", obs.t_ns);
        return false;
      }
      AnchoredTrack& track = it->second;
      const int a = track.anchor_keyframe;
      const Pose& T_B_C0 = dataset.cameras.front().T_B_C;
      if (k == a && obs.camera == 0) return false;
      if (k == a) {
        problem.AddResidualBlock(
            AnchorStereoBearingFactor::Create(T_B_C0, track.b_anchor_C0, sensor.T_B_C, obs.xy,
                                              options.bearing_sigma_rad),
            loss.get(), track.rho.data());
      } else {
        problem.AddResidualBlock(
            options.autodiff_jacobians
                ? AnchoredBearingFactorAutoDiff::Create(T_B_C0, track.b_anchor_C0, sensor.T_B_C,
                                                        obs.xy, options.bearing_sigma_rad)
                : AnchoredBearingFactor::Create(T_B_C0, track.b_anchor_C0, sensor.T_B_C, obs.xy,
                                                options.bearing_sigma_rad),
            loss.get(), blocks[a].q.data(), blocks[a].p.data(), blocks[k].q.data(),
            blocks[k].p.data(), track.rho.data());
      }
      if (tracks_in_problem.insert(obs.landmark_id).second) {
        problem.AddResidualBlock(
            InverseDepthPriorFactor::Create(options.tracks.rho_prior_mean_per_m,
                                            options.tracks.rho_prior_sigma_per_m),
            nullptr, track.rho.data());
        problem.SetParameterLowerBound(track.rho.data(), 0, options.tracks.min_rho_per_m);
        problem.SetParameterUpperBound(track.rho.data(), 0, options.tracks.max_rho_per_m);
      }
      return true;
    };
    if (camera) {
      const bool landmark_parameters = options.landmarks != LandmarkMode::kKnown;
      // features0 (cam0), then features1 (cam1: stereo tracks, the same landmark ids).
      const bool has_cam1 = dataset.cameras.size() > 1;
      for (const std::vector<FeatureObservation>* stream : {&dataset.features, &dataset.features1})
        for (const FeatureObservation& obs : *stream) {
          if (obs.camera == 1 && !has_cam1) {
            drop("feature: features1 without cam1's calibration", obs.t_ns);
            continue;
          }
          const CameraSensor& sensor = dataset.cameras[obs.camera];
          const int k = KeyframeAt(times, obs.t_ns);
          if (k < 0) {
            drop("feature: no keyframe at its time", obs.t_ns);
            continue;
          }
          if (options.landmarks == LandmarkMode::kTracks) {
            if (add_track_residual(obs, k, sensor)) ++num_visual;
            continue;
          }
          if (!landmark_parameters) {
            auto it = dataset.map.landmarks_W.find(obs.landmark_id);
            if (it == dataset.map.landmarks_W.end()) {
              drop("feature: landmark not in the map", obs.t_ns);
              continue;
            }
            if (initial_depth(k, it->second, sensor.T_B_C) <= 0.01) {
              drop("feature: behind the camera at the seed", obs.t_ns);
              continue;
            }
            if (options.features_as_bearings) {
              auto& block = landmarks[obs.landmark_id];
              block = {it->second.x(), it->second.y(), it->second.z()};
              problem.AddResidualBlock(
                  FeatureBearingFactor::Create(sensor.T_B_C, obs.xy, options.bearing_sigma_rad),
                  loss.get(), blocks[k].q.data(), blocks[k].p.data(), block.data());
              problem.SetParameterBlockConstant(block.data());
            } else {
              problem.AddResidualBlock(
                  MapPointReprojection(options, sensor.model, sensor.T_B_C, it->second,
                                       sensor.model.NormalizedToPixel(obs.xy)),
                  loss.get(), blocks[k].q.data(), blocks[k].p.data());
            }
            ++num_anchored;
          } else {
            auto it = landmarks.find(obs.landmark_id);
            if (it == landmarks.end()) {
              drop("feature: landmark not initialized", obs.t_ns);
              continue;
            }
            problem.AddResidualBlock(
                FeatureBearingFactor::Create(sensor.T_B_C, obs.xy, options.bearing_sigma_rad),
                loss.get(), blocks[k].q.data(), blocks[k].p.data(), it->second.data());
          }
          ++num_visual;
        }
      // Tag corners of every selected camera. Map coordinates are in W, or in M on a board map.
      const Eigen::Matrix3d R_W_M_now = QuaternionFromBlock(q_W_M).toRotationMatrix();
      bool shared_blocks_added = false;
      for (auto& [cam, e] : extrinsics) {
        const CameraSensor& sensor = dataset.cameras[cam];
        bool camera_blocks_added = false;
        const Pose T_B_C_now(QuaternionFromBlock(e.q), Eigen::Vector3d(e.p.data()));
        for (const TagObservation& obs : TagStream(dataset, cam)) {
          const int k = KeyframeAt(times, obs.t_ns);
          auto it = dataset.map.tags.find(obs.tag_id);
          if (k < 0 || it == dataset.map.tags.end()) {
            drop(k < 0 ? "tag: no keyframe at its time" : "tag: not in the map", obs.t_ns);
            continue;
          }
          const std::array<Eigen::Vector3d, 4> corners_map = TagCornersInWorld(it->second);
          const Pose T_C_W =
              (Pose(FromBlocks(blocks[k]).q_W_B, Eigen::Vector3d(blocks[k].p.data())) *
               (calibrated ? T_B_C_now : sensor.T_B_C))
                  .Inverse();
          for (int c = 0; c < 4; ++c) {
            const Eigen::Vector3d p_W =
                calibrated ? Eigen::Vector3d(R_W_M_now * corners_map[c]) : corners_map[c];
            if ((T_C_W * p_W).z() <= 0.01) {
              drop("tag corner: behind the camera at the seed", obs.t_ns);
              continue;
            }
            ceres::ResidualBlockId id;
            if (!calibrated) {
              id =
                  problem.AddResidualBlock(MapPointReprojection(options, sensor.model, sensor.T_B_C,
                                                                corners_map[c], obs.corners_px[c]),
                                           loss.get(), blocks[k].q.data(), blocks[k].p.data());
            } else {
              if (!shared_blocks_added) {
                problem.AddParameterBlock(q_W_M.data(), 4, &tilt_manifold);
                if (!board) problem.SetParameterBlockConstant(q_W_M.data());
                problem.AddParameterBlock(time_offset.data(), 1);
                if (options.estimate_time_offset) {
                  problem.SetParameterLowerBound(time_offset.data(), 0, -options.max_time_offset_s);
                  problem.SetParameterUpperBound(time_offset.data(), 0, options.max_time_offset_s);
                } else {
                  problem.SetParameterBlockConstant(time_offset.data());
                }
                shared_blocks_added = true;
              }
              if (!camera_blocks_added) {
                problem.AddParameterBlock(e.q.data(), 4, &quaternion_manifold);
                problem.AddParameterBlock(e.p.data(), 3);
                if (options.estimate_extrinsics) {
                  Eigen::Matrix<double, 6, 6> L = Eigen::Matrix<double, 6, 6>::Zero();
                  L.topLeftCorner<3, 3>().diagonal().setConstant(1.0 /
                                                                 options.extrinsics_prior_rad);
                  L.bottomRightCorner<3, 3>().diagonal().setConstant(1.0 /
                                                                     options.extrinsics_prior_m);
                  problem.AddResidualBlock(PosePriorFactor::Create(e.prior, L), nullptr, e.q.data(),
                                           e.p.data());
                } else {
                  problem.SetParameterBlockConstant(e.q.data());
                  problem.SetParameterBlockConstant(e.p.data());
                }
                camera_blocks_added = true;
              }
              id = problem.AddResidualBlock(
                  CalibratedReprojectionFactor::Create(sensor.model, shifts[k], corners_map[c],
                                                       obs.corners_px[c], options.pixel_sigma_px),
                  loss.get(), blocks[k].q.data(), blocks[k].p.data(), blocks[k].v.data(),
                  q_W_M.data(), e.q.data(), e.p.data(), time_offset.data());
            }
            corner_residuals.push_back(id);
            ++num_visual;
            ++num_anchored;
          }
        }
      }
      if (use_laser) {
        problem.AddParameterBlock(plane_n.data(), 3, &sphere_manifold);
        problem.AddParameterBlock(plane_d.data(), 1);
        if (!options.estimate_plane) {
          problem.SetParameterBlockConstant(plane_n.data());
          problem.SetParameterBlockConstant(plane_d.data());
        }
        for (const LaserObservation& obs : dataset.laser) {
          const int k = KeyframeAt(times, obs.t_ns);
          if (k < 0) {
            drop("laser: no keyframe at its time", obs.t_ns);
            continue;
          }
          ceres::CostFunction* cost = LaserSpotPlaneFactor::Create(
              camera->T_B_C, options.laser_beam->origin_C, options.laser_beam->direction_C, obs.xy,
              options.laser_sigma_rad);
          const double* parameters[4] = {blocks[k].q.data(), blocks[k].p.data(), plane_n.data(),
                                         plane_d.data()};
          double r[2];
          if (!cost->Evaluate(parameters, r, nullptr)) {
            delete cost;
            drop("laser: no spot on the plane at the seed", obs.t_ns);
            continue;
          }
          problem.AddResidualBlock(cost, loss.get(), blocks[k].q.data(), blocks[k].p.data(),
                                   plane_n.data(), plane_d.data());
          ++num_visual;
        }
      }
    }
    result.dropped = dropped;
    result.statistics.num_visual_residuals = num_visual;
    if (num_visual == 0) {
      result.message = "no visual residual could be built";
      return result;
    }

    // Gauge. With known map points (tags, surveyed landmarks) the map fixes all six degrees of
    // freedom and nothing is added. Otherwise the IMU makes roll and pitch observable (gravity)
    // but not the position and the yaw, which must be fixed explicitly:
    const bool unknown_landmarks_used =
        options.landmarks != LandmarkMode::kKnown && num_visual > num_anchored;
    if (num_anchored > 0) {
      // Known map points fix all six degrees of freedom.
    } else if (num_constant > 0) {
      // A constant context keyframe fixes them (a sliding window).
    } else if (options.landmarks == LandmarkMode::kUnknownGround && unknown_landmarks_used) {
      // Three-point scenario (Troiani et al., sec. III, fig. 2): P1 (lowest id) is the origin, P2
      // lies on the x axis, the features are on the ground z = 0 (planar-ground assumption). The
      // distance D = |P1 P2| need not be fixed: the accelerometer makes the scale observable
      // (Martinelli, T-RO 2012), so D is estimated and reported unless given_D_m is set.
      // (Landmarks without any residual are not in the problem and are skipped.)
      auto it = landmarks.begin();
      if (problem.HasParameterBlock(it->second.data())) {
        it->second = {0.0, 0.0, 0.0};
        problem.SetParameterBlockConstant(it->second.data());
      }
      if (++it != landmarks.end() && problem.HasParameterBlock(it->second.data())) {
        it->second[1] = it->second[2] = 0.0;
        if (options.given_D_m) {
          it->second[0] = *options.given_D_m;
          problem.SetParameterBlockConstant(it->second.data());
        } else {
          problem.SetManifold(it->second.data(), &fix_yz);
        }
      }
      for (it = landmarks.begin(); it != landmarks.end(); ++it) {
        if (it == landmarks.begin() || it == std::next(landmarks.begin())) continue;
        if (!problem.HasParameterBlock(it->second.data())) continue;
        it->second[2] = 0.0;
        problem.SetManifold(it->second.data(), &fix_z);
      }
    } else if (!options.hold_gauge) {
      // Left free on purpose (SmootherProblemOptions::hold_gauge).
    } else if (unknown_landmarks_used || (use_laser && options.estimate_plane)) {
      // Free landmarks, or the laser spot on an unknown plane: the first keyframe's position and
      // its yaw (rotation about gravity) define the frame (strong prior at the seed).
      const ImuKeyframeState s0 = FromBlocks(blocks[0]);
      const Eigen::Matrix3d R0_T = s0.q_W_B.toRotationMatrix().transpose();
      Eigen::Matrix<double, 6, 6> L = Eigen::Matrix<double, 6, 6>::Zero();
      const Eigen::Vector3d yaw_axis_B = R0_T * Eigen::Vector3d::UnitZ();
      L.block<1, 3>(0, 0) = 1e6 * yaw_axis_B.transpose();
      L.block<3, 3>(3, 3) = 1e6 * Eigen::Matrix3d::Identity();
      if (use_laser && !unknown_landmarks_used) {
        // The laser spot observes only the distance to the plane, the velocity along its normal,
        // the attitude relative to it and the plane's inclination alpha (RR-7906, eq. 7 and
        // appendix B). Besides the position (with d) and the velocity along the plane, two
        // rotations are unobservable: about gravity (yaw), and about the plane normal n together
        // with the constant acceleration a = g - R g along the plane (R the rotation), which the
        // unobservable motion along the plane absorbs: a . n = g . n - g . R^T n = 0, so the
        // spots do not change, and R_i dv_ij = v_j - v_i - (R g + a) dt holds as before. Fix the
        // component of the first rotation about n too (when n is not vertical: about a vertical
        // normal the two rotations coincide).
        const Eigen::Vector3d n_plane = Eigen::Vector3d(plane_n.data()).normalized();
        Eigen::Vector3d about_normal_B = R0_T * n_plane;
        about_normal_B -= about_normal_B.dot(yaw_axis_B) * yaw_axis_B;
        if (about_normal_B.norm() > std::sin(1.0 * kDeg))
          L.block<1, 3>(1, 0) = 1e6 * about_normal_B.normalized().transpose();
        // The velocity along the plane (symmetries w3, w4 of appendix B): held near the seed.
        const Eigen::Matrix3d L_v =
            (Eigen::Matrix3d::Identity() - n_plane * n_plane.transpose()) / 0.1;
        problem.AddResidualBlock(VectorPriorFactor::Create(s0.v_W, L_v), nullptr,
                                 blocks[0].v.data());
      }
      problem.AddResidualBlock(PosePriorFactor::Create(Pose(s0.q_W_B, s0.p_W), L), nullptr,
                               blocks[0].q.data(), blocks[0].p.data());
    }

    ceres::Solver::Options solver_options;
    // The information matrix is block-banded (IMU factors chain consecutive keyframes; each visual
    // residual touches one keyframe, plus the few landmark/plane blocks that touch many): an
    // arrow-head matrix that a fill-reducing sparse Cholesky (SuiteSparse CHOLMOD, AMD ordering)
    // factorises in time linear in the number of keyframes. SPARSE_SCHUR would eliminate the
    // landmarks first and couple every keyframe that sees them into a dense reduced system.
    solver_options.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
    solver_options.sparse_linear_algebra_library_type =
        ceres::IsSparseLinearAlgebraLibraryTypeAvailable(ceres::SUITE_SPARSE) ? ceres::SUITE_SPARSE
                                                                              : ceres::EIGEN_SPARSE;
    solver_options.num_threads = std::max(1, options.num_threads);
    solver_options.max_num_iterations = options.max_iterations;
    solver_options.function_tolerance = options.function_tolerance;
    solver_options.parameter_tolerance = options.parameter_tolerance;
    solver_options.gradient_tolerance = 1e-14;
    solver_options.minimizer_progress_to_stdout = options.verbose;
    ceres::Solver::Summary summary;
    ceres::Solve(solver_options, &problem, &summary);
    if (options.verbose) {
      // Cost by residual kind at the solution (diagnostics).
      std::vector<ceres::ResidualBlockId> ids;
      problem.GetResidualBlocks(&ids);
      std::map<int, double> cost_by_size;
      std::map<int, double> worst_by_size;
      for (auto id : ids) {
        double cost = 0.0;
        problem.EvaluateResidualBlock(id, false, &cost, nullptr, nullptr);
        const int size = problem.GetCostFunctionForResidualBlock(id)->num_residuals();
        cost_by_size[size] += cost;
        worst_by_size[size] = std::max(worst_by_size[size], cost);
      }
      for (const auto& [size, cost] : cost_by_size)
        std::fprintf(stderr, "residuals of size %d: cost %.6g (worst block %.6g)\n", size, cost,
                     worst_by_size[size]);
    }

    SmootherStatistics& st = result.statistics;
    if (round == 0) st.initial_cost = summary.initial_cost;
    st.final_cost = summary.final_cost;
    st.iterations += summary.num_successful_steps + summary.num_unsuccessful_steps;
    st.solves += 1;
    st.solve_s += summary.total_time_in_seconds;
    st.linear_solver_s += summary.linear_solver_time_in_seconds;
    st.residual_evaluation_s += summary.residual_evaluation_time_in_seconds;
    st.jacobian_evaluation_s += summary.jacobian_evaluation_time_in_seconds;
    st.num_parameters = summary.num_effective_parameters;
    st.linear_solver = LinearSolverDescription(solver_options);
    st.converged = summary.termination_type == ceres::CONVERGENCE;
    st.last_relative_cost_change = summary.iterations.empty() || !(summary.final_cost > 0.0)
                                       ? 0.0
                                       : summary.iterations.back().cost_change / summary.final_cost;
    st.ceres_brief_report = summary.BriefReport();
    st.ceres_full_report = summary.FullReport();
    result.usable = summary.IsSolutionUsable();
    result.message = summary.message;
    if (!result.usable) return result;

    // Covariances on the last round only.
    bool relinearize = false;
    for (int k = 0; k < n; ++k) {
      const ImuKeyframeState s = FromBlocks(blocks[k]);
      if ((s.biases.b_g - linearization[k].b_g).cwiseAbs().maxCoeff() >
              options.relinearize_gyro_rad_s ||
          (s.biases.b_a - linearization[k].b_a).cwiseAbs().maxCoeff() >
              options.relinearize_accel_m_s2)
        relinearize = true;
    }
    const bool last_round = !relinearize || round == options.relinearize_rounds;

    // Tag corners at this solution: pixel errors before the loss, and how many the loss
    // down-weights (Huber and Cauchy change the weight beyond |whitened residual| = loss_scale).
    {
      SmootherCornerStatistics& cs = result.corner_statistics;
      cs = SmootherCornerStatistics{};
      double sum_sq_px = 0.0;
      for (const ceres::ResidualBlockId id : corner_residuals) {
        double r[2];
        double cost = 0.0;
        if (!problem.EvaluateResidualBlock(id, false, &cost, r, nullptr)) continue;
        const double whitened = std::hypot(r[0], r[1]);
        const double px = whitened * options.pixel_sigma_px;
        sum_sq_px += px * px;
        ++cs.corners;
        if (options.loss != SmootherLoss::kNone && whitened > options.loss_scale) ++cs.downweighted;
      }
      if (cs.corners > 0) cs.rms_px = std::sqrt(sum_sq_px / cs.corners);
    }

    // The calibration blocks that are estimated (in the problem and not constant).
    auto estimated = [&](double* block) {
      return problem.HasParameterBlock(block) && !problem.IsParameterBlockConstant(block);
    };
    std::vector<int> estimated_cameras;
    for (auto& [cam, e] : extrinsics)
      if (estimated(e.q.data())) estimated_cameras.push_back(cam);
    const bool time_offset_estimated = estimated(time_offset.data());
    const bool tilt_estimated = estimated(q_W_M.data());
    const bool calibration_asked =
        options.calibration_covariance &&
        (!estimated_cameras.empty() || time_offset_estimated || tilt_estimated);
    // The keyframe chain in time order; every other block is placed after the last keyframe that
    // shares a residual with it (smoother_covariance.h).
    const auto covariance_layout = [&] {
      SmootherCovarianceLayout layout;
      layout.keyframes.reserve(n);
      for (auto& b : blocks)
        layout.keyframes.push_back(
            {b.q.data(), b.p.data(), b.v.data(), b.b_g.data(), b.b_a.data()});
      for (auto& [id, p] : landmarks) layout.others.push_back(p.data());
      for (auto& [id, track] : tracks) layout.others.push_back(track.rho.data());
      layout.others.insert(layout.others.end(),
                           {plane_n.data(), plane_d.data(), q_W_M.data(), time_offset.data()});
      for (auto& [cam, e] : extrinsics) {
        layout.others.push_back(e.q.data());
        layout.others.push_back(e.p.data());
      }
      return layout;
    };
    if (last_round && options.fit_imu_noise && !imu_group.empty()) {
      SmootherCovarianceOptions fit_options;
      fit_options.num_threads = std::max(1, options.num_threads);
      fit_options.regularization = kImuFitRegularization;
      SmootherCovariance fit(fit_options);
      if (fit.Compute(covariance_layout(), {}, &problem, &imu_group))
        result.imu_fit = fit.group_fit();
      else if (options.verbose)
        std::fprintf(stderr, "IMU noise fit: %s\n", fit.message().c_str());
    }
    if (last_round && options.marginalize_before_keyframe > 0) {
      std::vector<KeyframeBlockPointers> keyframe_blocks;
      keyframe_blocks.reserve(n);
      for (auto& b : blocks)
        keyframe_blocks.push_back({b.q.data(), b.p.data(), b.v.data(), b.b_g.data(), b.b_a.data()});
      result.marginal_prior =
          MarginalizeKeyframes(&problem, keyframe_blocks, options.marginalize_before_keyframe,
                               options.num_threads, &result.marginalization_failure);
    }
    if (last_round && (options.compute_covariance || calibration_asked)) {
      const auto t_cov = std::chrono::steady_clock::now();
      std::vector<std::pair<const double*, const double*>> pairs;
      if (options.compute_covariance) {
        for (auto& b : blocks) {
          pairs.emplace_back(b.p.data(), b.p.data());
          pairs.emplace_back(b.q.data(), b.q.data());
          pairs.emplace_back(b.p.data(), b.q.data());
        }
      }
      if (calibration_asked) {
        for (const int cam : estimated_cameras) {
          ExtrinsicBlocks& e = extrinsics[cam];
          pairs.emplace_back(e.p.data(), e.p.data());
          pairs.emplace_back(e.q.data(), e.q.data());
          pairs.emplace_back(e.p.data(), e.q.data());
        }
        if (time_offset_estimated) pairs.emplace_back(time_offset.data(), time_offset.data());
        if (tilt_estimated) pairs.emplace_back(q_W_M.data(), q_W_M.data());
      }
      // Both methods answer the same tangent-space blocks (smoother_problem.h).
      std::unique_ptr<ceres::Covariance> ceres_covariance;
      SmootherCovarianceOptions structured_options;
      structured_options.num_threads = std::max(1, options.num_threads);
      SmootherCovariance structured(structured_options);
      bool computed = false;
      if (options.covariance_method == SmootherCovarianceMethod::kCeres) {
        ceres::Covariance::Options covariance_options;
        covariance_options.num_threads = std::max(1, options.num_threads);
        ceres_covariance = std::make_unique<ceres::Covariance>(covariance_options);
        computed = ceres_covariance->Compute(pairs, &problem);
      } else {
        // The keyframe chain in time order; every other block is placed after the last keyframe
        // that shares a residual with it (smoother_covariance.h).
        computed = structured.Compute(covariance_layout(), pairs, &problem);
        st.covariance_min_relative_pivot = structured.statistics().min_relative_pivot;
        if (!computed && options.verbose)
          std::fprintf(stderr, "covariance: %s\n", structured.message().c_str());
      }
      auto tangent_block = [&](const double* a, const double* b, double* out) {
        if (ceres_covariance)
          ceres_covariance->GetCovarianceBlockInTangentSpace(a, b, out);
        else
          structured.GetCovarianceBlockInTangentSpace(a, b, out);
      };
      if (options.compute_covariance) result.pose_covariances.assign(n, std::nullopt);
      if (!computed && calibration_asked) result.calibration.covariance_failed = true;
      if (computed && options.compute_covariance) {
        for (int k = 0; k < n; ++k) {
          Eigen::Matrix<double, 3, 3, Eigen::RowMajor> pp, qq, pq;
          tangent_block(blocks[k].p.data(), blocks[k].p.data(), pp.data());
          tangent_block(blocks[k].q.data(), blocks[k].q.data(), qq.data());
          tangent_block(blocks[k].p.data(), blocks[k].q.data(), pq.data());
          result.pose_covariances[k] =
              PoseCovarianceFromTangent(pp, qq, pq, FromBlocks(blocks[k]).q_W_B);
        }
      }
      if (computed && calibration_asked) {
        SmootherCalibration& cal = result.calibration;
        for (const int cam : estimated_cameras) {
          ExtrinsicBlocks& e = extrinsics[cam];
          Eigen::Matrix<double, 3, 3, Eigen::RowMajor> pp, qq, pq;
          tangent_block(e.p.data(), e.p.data(), pp.data());
          tangent_block(e.q.data(), e.q.data(), qq.data());
          tangent_block(e.p.data(), e.q.data(), pq.data());
          cal.T_B_C_covariance[cam] =
              PoseCovarianceFromTangent(pp, qq, pq, QuaternionFromBlock(e.q));
        }
        if (time_offset_estimated) {
          double var = 0.0;  // no manifold: tangent = ambient
          tangent_block(time_offset.data(), time_offset.data(), &var);
          cal.time_offset_sigma_s = std::sqrt(std::max(var, 0.0));
        }
        if (tilt_estimated) {
          Eigen::Matrix<double, 2, 2, Eigen::RowMajor> tt;
          tangent_block(q_W_M.data(), q_W_M.data(), tt.data());
          cal.tilt_covariance = Eigen::Matrix2d(tt);
        }
      }
      st.covariance_s += Seconds(std::chrono::steady_clock::now() - t_cov);
    }
    if (last_round) break;
    for (int k = 0; k < n; ++k) linearization[k] = FromBlocks(blocks[k]).biases;
  }

  for (int k = 0; k < n; ++k) result.keyframes.push_back({times[k], FromBlocks(blocks[k])});
  SmootherCalibration& cal = result.calibration;
  for (const auto& [cam, e] : extrinsics)
    cal.T_B_C[cam] = Pose(QuaternionFromBlock(e.q), Eigen::Vector3d(e.p.data()));
  cal.time_offset_s = time_offset[0];
  if (board) {
    // Re-express the solution in the W of core/board_frame.h: the rotation about z_W that takes
    // the estimated R_W_M to the canonical one (a rotation about gravity leaves the IMU factors
    // unchanged). Positions, velocities, the position part of the pose covariances and the tilt
    // tangent (about W's x and y) rotate with it; body-frame quantities do not.
    const Eigen::Matrix3d R_W_M = QuaternionFromBlock(q_W_M).toRotationMatrix();
    const Eigen::Matrix3d R_canonical = CanonicalBoardToWorldRotation(R_W_M);
    const Eigen::Matrix3d R_z = R_canonical * R_W_M.transpose();
    const Eigen::Quaterniond q_z(R_z);
    for (SmootherKeyframe& kf : result.keyframes) {
      kf.state.q_W_B = (q_z * kf.state.q_W_B).normalized();
      kf.state.p_W = R_z * kf.state.p_W;
      kf.state.v_W = R_z * kf.state.v_W;
    }
    for (auto& C : result.pose_covariances) {
      if (!C) continue;
      C->topLeftCorner<3, 3>() = R_z * C->topLeftCorner<3, 3>() * R_z.transpose();
      C->topRightCorner<3, 3>() = R_z * C->topRightCorner<3, 3>();
      C->bottomLeftCorner<3, 3>() = C->topRightCorner<3, 3>().transpose();
    }
    cal.q_W_M = Eigen::Quaterniond(R_canonical).normalized();
    if (cal.tilt_covariance) {
      const Eigen::Matrix2d R2 = R_z.topLeftCorner<2, 2>();
      cal.tilt_covariance = R2 * *cal.tilt_covariance * R2.transpose();
    }
  }
  if (options.landmarks != LandmarkMode::kKnown) {
    for (const auto& [id, p] : landmarks)
      result.landmarks_W[id] = Eigen::Vector3d(p[0], p[1], p[2]);
  }
  if (options.landmarks == LandmarkMode::kTracks && !result.keyframes.empty()) {
    const Pose& T_B_C0 = dataset.cameras.front().T_B_C;
    for (const auto& [id, track] : tracks) {
      const ImuKeyframeState& s = result.keyframes[track.anchor_keyframe].state;
      result.landmarks_W[id] = TrackPositionW(track, Pose(s.q_W_B, s.p_W), T_B_C0);
    }
  }
  if (use_laser && options.estimate_plane) {
    Plane plane;
    plane.n_W = Eigen::Vector3d(plane_n.data()).normalized();
    plane.d_m = plane_d[0];
    result.plane = plane;
  }
  return result;
}

}  // namespace mavloc
