#include "solver/estimators/tag_ekf_estimator.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>

#include "core/errors.h"
#include "core/random.h"
#include "solver/board/frame_pnp.h"
#include "solver/board/pnp_initial_state.h"
#include "solver/pose/corner_pnp.h"
#include "solver/pose/tags_camera.h"

namespace mavloc {

namespace {

struct PendingFrame {
  TimeNs t_exposure_ns = 0;
  TimeNs t_available_ns = 0;
  std::vector<TagPoseMeasurement> tags;
  std::vector<TagObservation> observations;  // of map tags, for the PnP of a re-acquisition
};

}  // namespace

TagEkfEstimator::TagEkfEstimator(const EstimatorOptions& options)
    : options_(options),
      board_(ParseBoardInitOptions(options)),
      reacquire_(ParseReacquireOptions(options)) {
  const std::string init = options.GetString("init", "truth");
  if (init != "truth" && init != "zero" && init != "perturbed" && init != "window")
    throw InputError("", 0, "init",
                     "must be truth, zero, perturbed or window (got '" + init + "')");
  for (const char* key :
       {"init_pos_sigma", "init_vel_sigma", "init_att_sigma", "init_ba_sigma", "init_bg_sigma",
        "init_p0_scale", "delay_s", "rate_hz", "accel_var", "gyro_var", "accel_bias_var",
        "gyro_bias_var", "position_var", "attitude_var"}) {
    if (options.Has(key) && !(options.GetDouble(key, 0.0) >= 0.0))
      throw InputError("", 0, key, "must be >= 0");
  }
}

std::string TagEkfEstimator::InitMode(const Dataset& dataset) const {
  if (options_.Has("init")) return options_.GetString("init", "truth");
  if (dataset.map.frame == MapFrame::kBoard) return "window";
  const auto it = dataset.scenario_info.find("filter_init");
  return it != dataset.scenario_info.end() ? it->second : "truth";
}

Applicability TagEkfEstimator::AppliesTo(const Dataset& dataset) const {
  if (dataset.imu.samples.size() < 2) return Applicability::No("needs imu0 samples");
  const std::string camera = TagsCameraMissing(dataset, options_.GetString("camera", ""));
  if (!camera.empty()) return Applicability::No(camera);
  if (options_.GetBool("use_tags", true)) {
    if (dataset.tags.empty()) return Applicability::No("needs tags0 observations");
    if (dataset.map.tags.empty()) return Applicability::No("needs the tags of map.yaml");
  }
  const std::string init = InitMode(dataset);
  if (dataset.map.frame == MapFrame::kBoard) {
    if (!options_.GetBool("use_tags", true))
      return Applicability::No("board map: use_tags=0 leaves nothing to find gravity with");
    const std::string board = BoardWorldMissing(dataset);
    if (!board.empty()) return Applicability::No(board);
    if (init == "truth" || init == "perturbed")
      return Applicability::No("init=" + init +
                               ": on a board map the ground truth is not in the filter's W "
                               "(use init=window, the default there, or init=zero)");
  }
  if (init == "window" && dataset.tags.empty())
    return Applicability::No("init=window needs tags0 observations");
  if ((init == "truth" || init == "perturbed") && dataset.ground_truth.empty())
    return Applicability::No("init=" + init +
                             " needs ground truth (use --option init=window or init=zero)");
  return Applicability::Yes();
}

Estimate TagEkfEstimator::Run(const Dataset& dataset) {
  const std::string init = InitMode(dataset);  // of the input: a board map defaults to window
  return RunInWorldFrame(dataset, board_, [&](const Dataset& dataset_W, const BoardWorld* board) {
    EstimatorOptions options = options_;
    options.Set("init", init);
    TagEkfEstimator world(options);
    if (board == nullptr) return world.RunInWorld(dataset_W);
    return world.RunInWorld(dataset_W,
                            std::make_pair(board->t_init_begin_ns, board->t_init_end_ns));
  });
}

Estimate TagEkfEstimator::RunInWorld(const Dataset& dataset,
                                     std::optional<std::pair<TimeNs, TimeNs>> window_ns) {
  const CameraSensor& camera = *TagsCamera(dataset, options_.GetString("camera", ""));
  TagEkfOptions ekf_options;
  TagEkfNoise& noise = ekf_options.noise;
  noise.accel_var = options_.GetDouble("accel_var", noise.accel_var);
  noise.gyro_var = options_.GetDouble("gyro_var", noise.gyro_var);
  noise.accel_bias_var = options_.GetDouble("accel_bias_var", noise.accel_bias_var);
  noise.gyro_bias_var = options_.GetDouble("gyro_bias_var", noise.gyro_bias_var);
  noise.position_var = options_.GetDouble("position_var", noise.position_var);
  noise.attitude_var = options_.GetDouble("attitude_var", noise.attitude_var);
  ekf_options.compensate_delay = options_.GetBool("compensate_delay", true);
  ekf_options.gate_chi2 = options_.GetDouble("gate_chi2", ekf_options.gate_chi2);
  const double delay_s =
      options_.GetDouble("delay_s", ScenarioNumber(dataset, "processing_delay_s").value_or(0.0));
  ekf_options.buffer_s = std::max(1.0, 2.0 * delay_s + 0.5);
  const bool use_tags = options_.GetBool("use_tags", true);
  const std::string init = InitMode(dataset);
  const bool window = init == "window";

  // Initial state and covariance.
  const std::vector<ImuSample>& imu = dataset.imu.samples;
  Eigen::Matrix<double, 15, 1> sigma;
  sigma << Eigen::Vector3d::Constant(options_.GetDouble("init_pos_sigma", window ? 0.02 : 0.313)),
      Eigen::Vector3d::Constant(options_.GetDouble("init_vel_sigma", 0.1)),
      Eigen::Vector3d::Constant(options_.GetDouble("init_att_sigma", window ? 0.02 : 0.05)),
      Eigen::Vector3d::Constant(options_.GetDouble("init_ba_sigma", 0.05)),
      Eigen::Vector3d::Constant(options_.GetDouble("init_bg_sigma", 0.005));
  TagEkfVector x0 = TagEkfVector::Zero();
  size_t k_start = 0;  // the first IMU sample the filter sees
  // init=window: the frames up to the initial one went into x0 and are not applied again.
  TimeNs t_window_end_ns = std::numeric_limits<TimeNs>::min();
  Estimate estimate;
  if (window) {
    // The initial window: the board initialisation's, or as it defines its first one.
    if (!window_ns) {
      if (const std::optional<TimeNs> t_first =
              FirstMapTagTime(dataset, ResolveMinTags(dataset, board_.min_tags))) {
        const TimeNs t_begin = std::max(*t_first, imu.front().t_ns);
        window_ns = {t_begin,
                     std::min(t_begin + SecondsToNs(board_.gravity_init_s), imu.back().t_ns)};
      }
    }
    std::optional<PnpInitialState> start;
    if (window_ns) {
      start = InitialStateFromPoses(FramePnpPoses(dataset, window_ns->first, window_ns->second,
                                                  &estimate.failures,
                                                  ResolveMinTags(dataset, board_.min_tags)));
    }
    if (!start) {
      estimate.CountFailure("init=window: no PnP pose in the initial window");
      return estimate;
    }
    while (k_start + 1 < imu.size() && imu[k_start].t_ns < start->t_ns) ++k_start;
    const double dt_s = NsToSeconds(imu[k_start].t_ns - start->t_ns);
    x0.segment<3>(kTagEkfPos) = start->T_W_B.p + dt_s * start->v_W;
    x0.segment<3>(kTagEkfVel) = start->v_W;
    x0.segment<3>(kTagEkfAtt) = Euler123FromRotation(start->T_W_B.R());
    t_window_end_ns = start->t_ns;
  } else if (init != "zero") {
    const GroundTruthState& gt = NearestTruth(dataset.ground_truth, imu.front().t_ns);
    x0.segment<3>(kTagEkfPos) = gt.T_W_B.p;
    x0.segment<3>(kTagEkfVel) = gt.v_W;
    x0.segment<3>(kTagEkfAtt) = Euler123FromRotation(gt.T_W_B.R());
    x0.segment<3>(kTagEkfAccelBias) = gt.b_a;
    x0.segment<3>(kTagEkfGyroBias) = gt.b_g;
    if (init == "perturbed") {
      Rng rng(static_cast<uint64_t>(options_.GetInt("init_seed", 1)));
      for (int i = 0; i < 15; ++i) x0[i] += sigma[i] * rng.Gaussian();
    }
  }
  // P0 from the same sigmas, optionally scaled (to study a filter that trusts its start too much).
  const double p0_scale = options_.GetDouble("init_p0_scale", 1.0);
  const TagEkfMatrix P0 = (p0_scale * sigma).cwiseAbs2().asDiagonal();

  // Per-tag pose measurements of every frame, with the time they become available.
  std::vector<PendingFrame> frames;
  if (use_tags) {
    const TimeNs delay_ns = SecondsToNs(delay_s);
    for (size_t begin = 0; begin < dataset.tags.size();) {
      size_t end = begin;
      while (end < dataset.tags.size() && dataset.tags[end].t_ns == dataset.tags[begin].t_ns) ++end;
      if (dataset.tags[begin].t_ns <= t_window_end_ns) {
        estimate.CountFailure("frame inside the initialisation window");
        begin = end;
        continue;
      }
      PendingFrame frame;
      frame.t_exposure_ns = dataset.tags[begin].t_ns;
      frame.t_available_ns = frame.t_exposure_ns + delay_ns;
      for (size_t i = begin; i < end; ++i) {
        const TagObservation& obs = dataset.tags[i];
        const auto tag = dataset.map.tags.find(obs.tag_id);
        if (tag == dataset.map.tags.end()) {
          estimate.CountRejection("tag not in map");
          continue;
        }
        const CornerPnpResult pnp = CornerPnp({obs}, dataset.map.tags, camera);
        if (!pnp.ok) {
          estimate.CountRejection("per-tag PnP: " + pnp.reason);
          continue;
        }
        frame.tags.push_back({obs.tag_id, pnp.T_W_C.Inverse() * tag->second.T_W_T});
        frame.observations.push_back(obs);
      }
      if (!frame.tags.empty()) frames.push_back(std::move(frame));
      begin = end;
    }
  }

  std::vector<std::string> names = PoseQuantityNames(/*with_velocity=*/true);
  names.insert(names.end(), {"bgx", "bgy", "bgz", "bax", "bay", "baz"});
  estimate.quantities = MakeQuantityTable(names);
  estimate.covariance_names = PoseQuantityNames(/*with_velocity=*/true);

  TagEkf ekf(ekf_options, camera.T_B_C, dataset.map.tags);
  ekf.Initialize(imu[k_start], x0, P0);
  const double rate_hz = options_.GetDouble("rate_hz", 100.0);
  const TimeNs output_step_ns = std::max<TimeNs>(1, SecondsToNs(1.0 / std::max(rate_hz, 1e-3)));
  TimeNs next_output_ns = imu[k_start].t_ns;
  auto record = [&]() {
    const TagEkfVector& x = ekf.state();
    const Eigen::Vector3d alpha = x.segment<3>(kTagEkfAtt);
    const Pose T_W_B(RotationFromEuler123(alpha), Eigen::Vector3d(x.segment<3>(kTagEkfPos)));
    std::vector<double> values =
        PoseQuantityValues(T_W_B, Eigen::Vector3d(x.segment<3>(kTagEkfVel)));
    for (int i = 0; i < 3; ++i) values.push_back(x[kTagEkfGyroBias + i]);
    for (int i = 0; i < 3; ++i) values.push_back(x[kTagEkfAccelBias + i]);
    estimate.quantities.Append(ekf.time(), values);
    estimate.poses.push_back({ekf.time(), T_W_B});
    // Covariance of (x, y, z, roll, pitch, yaw, vx, vy, vz): J P J^T with the Euler conversion.
    Eigen::Matrix<double, 9, 15> J = Eigen::Matrix<double, 9, 15>::Zero();
    J.block<3, 3>(0, kTagEkfPos).setIdentity();
    J.block<3, 3>(3, kTagEkfAtt) = RpyJacobianWrtEuler123(alpha);
    J.block<3, 3>(6, kTagEkfVel).setIdentity();
    estimate.covariances.push_back({ekf.time(), J * ekf.covariance() * J.transpose()});
  };

  size_t next_frame = 0;
  std::vector<const PendingFrame*> gated;  // consecutive frames whose every tag was gated out
  int resets = 0;
  // Lost lock (tag_ekf_reacquire.h): restart from the whole-frame PnP of the gated frames.
  auto reacquire = [&](const ImuSample& now) {
    std::vector<StampedPose> poses;
    for (const PendingFrame* frame : gated) {
      const CornerPnpResult pnp = CornerPnp(frame->observations, dataset.map.tags, camera);
      if (pnp.ok) poses.push_back({frame->t_exposure_ns, pnp.T_W_B});
    }
    const auto state = ReacquireState(poses, now.t_ns, ekf.state(), ekf.covariance(), reacquire_);
    if (!state) return;  // tried again after the next gated frame
    ekf.Initialize(now, state->x, state->P);
    ++resets;
    estimate.events.push_back(
        fmt::format("re-acquired at t = {:.3f} s: every tag of {} consecutive frames gated out; "
                    "state reset from their whole-frame PnP",
                    NsToSeconds(now.t_ns), gated.size()));
    gated.clear();
  };
  auto apply_available = [&](const ImuSample& now) {
    while (next_frame < frames.size() && frames[next_frame].t_available_ns <= now.t_ns) {
      const PendingFrame& frame = frames[next_frame++];
      const TagUpdateResult result = ekf.Update(frame.t_exposure_ns, frame.tags);
      if (result.too_old) estimate.CountRejection("measurement older than the buffer");
      if (result.in_future) estimate.CountRejection("measurement exposed after the filter time");
      if (result.rejected_gate > 0)
        estimate.CountRejection("tag rejected by the innovation gate", result.rejected_gate);
      if (result.unknown_tag > 0) estimate.CountRejection("tag not in map", result.unknown_tag);
      if (!reacquire_.enabled || result.too_old || result.in_future) continue;
      if (result.applied > 0 || result.rejected_gate == 0) {
        gated.clear();
        continue;
      }
      gated.push_back(&frame);
      if (static_cast<int>(gated.size()) >= reacquire_.frames) reacquire(now);
    }
  };
  // Frames exposed before the filter's first IMU sample cannot be used.
  while (next_frame < frames.size() && frames[next_frame].t_exposure_ns < imu[k_start].t_ns) {
    estimate.CountRejection("measurement before the first IMU sample");
    ++next_frame;
  }
  apply_available(imu[k_start]);
  record();
  next_output_ns += output_step_ns;
  for (size_t k = k_start + 1; k < imu.size(); ++k) {
    ekf.Propagate(imu[k]);
    apply_available(imu[k]);
    if (imu[k].t_ns >= next_output_ns) {
      record();
      while (next_output_ns <= imu[k].t_ns) next_output_ns += output_step_ns;
    }
  }
  if (reacquire_.enabled)
    estimate.parameters["tag_ekf_resets"] = {static_cast<double>(resets), {}, ""};
  return estimate;
}

}  // namespace mavloc
