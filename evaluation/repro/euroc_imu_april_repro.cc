#include "evaluation/repro/euroc_imu_april_repro.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>

#include "core/errors.h"
#include "core/key_values.h"
#include "core/numbers.h"
#include "core/progress.h"
#include "core/rotation.h"
#include "datasets/io/aprilgrid_log_import.h"
#include "datasets/io/calibration_io.h"
#include "evaluation/association.h"
#include "evaluation/comparison.h"
#include "evaluation/reference.h"
#include "evaluation/report/report_protocol.h"
#include "evaluation/report_writer.h"
#include "evaluation/repro/repro_units.h"
#include "solver/estimator.h"

namespace mavloc {
namespace {

constexpr const char* kImuAprilStage = "repro euroc-imu-april";
// chi-square with 3 degrees of freedom at 99.73 % (the probability of 3 sigma in one dimension).
constexpr double kChi2ThreeDof3Sigma = 14.16;

// The nearest signed permutation matrix: a camera mounting known only "by the drawing".
Eigen::Matrix3d RoundToAxes(const Eigen::Matrix3d& R) {
  Eigen::Matrix3d out = Eigen::Matrix3d::Zero();
  std::array<bool, 3> used_row{false, false, false};
  for (int c = 0; c < 3; ++c) {
    int best = -1;
    for (int r = 0; r < 3; ++r)
      if (!used_row[r] && (best < 0 || std::abs(R(r, c)) > std::abs(R(best, c)))) best = r;
    used_row[best] = true;
    out(best, c) = R(best, c) > 0 ? 1.0 : -1.0;
  }
  return out;
}

Dataset FirstSeconds(const Dataset& full, double duration_s) {
  if (!(duration_s > 0.0) || full.imu.samples.empty()) return full;
  Dataset d = full;
  const TimeNs end = full.imu.samples.front().t_ns + SecondsToNs(duration_s);
  auto trim = [end](auto& items) {
    items.erase(std::remove_if(items.begin(), items.end(),
                               [end](const auto& item) { return item.t_ns > end; }),
                items.end());
  };
  trim(d.imu.samples);
  for (auto& camera : d.cameras) trim(camera.frames);
  trim(d.tags);
  trim(d.tags1);
  return d;
}

struct SmootherRun {
  std::string label;    // "cam0", "cam1", "cam0+cam1"
  std::string cameras;  // option value
  Estimate estimate;
  double runtime_s = 0.0;
  bool ran = false;
  std::string why;
};

// Error of an estimated extrinsic against a reference one: translation p_ref - p_est [m],
// rotation dtheta = Log(R_est^T R_ref) [rad] (the right perturbation of the covariance).
struct ExtrinsicError {
  Eigen::Vector3d dp = Eigen::Vector3d::Zero();
  Eigen::Vector3d dtheta = Eigen::Vector3d::Zero();
  std::optional<Eigen::Vector3d> sigma_p, sigma_theta;
  double mahalanobis_p = kNaN, mahalanobis_theta = kNaN;
};

ExtrinsicError CompareExtrinsic(const EstimatedExtrinsic& est, const Pose& reference) {
  ExtrinsicError e;
  e.dp = reference.p - est.T_B_C.p;
  e.dtheta = LogSO3(est.T_B_C.R().transpose() * reference.R());
  if (est.covariance) {
    const Eigen::Matrix3d P = est.covariance->topLeftCorner<3, 3>();
    const Eigen::Matrix3d T = est.covariance->bottomRightCorner<3, 3>();
    e.sigma_p = P.diagonal().cwiseSqrt();
    e.sigma_theta = T.diagonal().cwiseSqrt();
    e.mahalanobis_p = e.dp.dot(P.ldlt().solve(e.dp));
    e.mahalanobis_theta = e.dtheta.dot(T.ldlt().solve(e.dtheta));
  }
  return e;
}

nlohmann::json Xyz(const Eigen::Vector3d& v) { return {v[0], v[1], v[2]}; }

double Param(const Estimate& e, const std::string& name, bool sigma = false) {
  const auto it = e.parameters.find(name);
  if (it == e.parameters.end()) return kNaN;
  if (sigma) return it->second.sigma.value_or(kNaN);
  return it->second.value;
}

struct InBoard {
  double position_rms_m = kNaN;
  double rotation_rms_rad = kNaN;
  double gravity_angle_rad = kNaN;
};

// The protocol of every trajectory comparison here: two solutions of the same images share their
// keyframe stamps, so association is nearest within 5 ms (a tenth of the 20 Hz camera interval),
// without alignment (both are expressed in the board's frame M, or both in their own W).
EvaluationProtocol SameImagesProtocol() {
  EvaluationProtocol protocol;
  protocol.association = AssociationMode::kNearest;
  protocol.max_dt_s = 0.005;
  protocol.alignment = AlignmentMode::kNone;
  protocol.rpe_deltas.clear();
  protocol.relative_length_fractions.clear();
  return protocol;
}

InBoard CompareInBoard(const Estimate& estimate, const Estimate& reference) {
  InBoard out;
  if (!estimate.T_W_M || !reference.T_W_M) return out;
  auto to_board = [](const Estimate& e) {
    std::vector<StampedPose> poses;
    const Pose T_M_W = e.T_W_M->Inverse();
    for (const auto& p : e.poses) poses.push_back({p.t_ns, T_M_W * p.T_W_B});
    return poses;
  };
  if (const auto ate =
          EvaluateTrajectory(to_board(estimate), to_board(reference), SameImagesProtocol())) {
    out.position_rms_m = ate->ape_translation_m.rmse;
    out.rotation_rms_rad = ate->ape_rotation_deg.rmse * kDeg;
  }
  const Eigen::Vector3d up_a = estimate.T_W_M->R().transpose() * Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d up_b = reference.T_W_M->R().transpose() * Eigen::Vector3d::UnitZ();
  out.gravity_angle_rad = std::atan2(up_a.cross(up_b).norm(), up_a.dot(up_b));
  return out;
}

// One run on one real log: the report, made in this process.
Report EurocImuAprilReport(const ReproOptions& options) {
  for (const auto& [key, value] : options.settings) {
    if (key != "data" && key != "official" && key != "initial" && key != "duration_s" &&
        key != "estimators" && key.rfind("smoother.", 0) != 0)
      throw InputError("repro euroc-imu-april: unknown setting '" + key +
                       "' (data, official, initial, duration_s, estimators, smoother.KEY)");
  }
  const std::string data =
      GetStringSetting(options.settings, "data", "../shared/data/euroc_imu_april");
  const std::string official_root =
      GetStringSetting(options.settings, "official", "../shared/data/euroc_v1_01_easy/mav0");
  const std::string initial = GetStringSetting(options.settings, "initial", "coarse");
  if (initial != "coarse" && initial != "official")
    throw InputError("repro euroc-imu-april: initial must be coarse or official, not '" + initial +
                     "'");
  const double duration_s = GetDoubleSetting(options.settings, "duration_s", 0.0);
  const auto estimators = SplitList(GetStringSetting(
      options.settings, "estimators",
      "tag-pnp,tag-ekf,tag-ekf:reacquire=0,tag-ekf:gate_chi2=0,pnp,upright-2p,pixhawk-kf"));
  // "name" or "name:key=value" (a variant with one option).
  auto split_variant = [](const std::string& item) {
    const auto colon = item.find(':');
    EstimatorOptions variant_options;
    if (colon != std::string::npos) {
      const std::string kv = item.substr(colon + 1);
      const auto eq = kv.find('=');
      if (eq == std::string::npos)
        throw InputError("repro euroc-imu-april: estimator variant '" + item +
                         "' must read name:key=value");
      variant_options.Set(kv.substr(0, eq), kv.substr(eq + 1));
    }
    return std::make_pair(item.substr(0, colon), variant_options);
  };
  for (const auto& item : estimators)
    if (!FindEstimator(split_variant(item).first))
      throw InputError("unknown estimator '" + split_variant(item).first + "'");

  // 1. The log as a dataset, with EuRoC's official T_B_C of both cameras.
  ReportProgress(kImuAprilStage, "importing " + data);
  AprilgridLogInputs inputs;
  inputs.imu_csv = data + "/imu0.csv";
  inputs.corners = {"cam0=" + data + "/cam0", "cam1=" + data + "/cam1"};
  inputs.configs = {data + "/config.yaml"};
  inputs.extrinsics = {"cam0=" + official_root + "/cam0/sensor.yaml",
                       "cam1=" + official_root + "/cam1/sensor.yaml"};
  AprilgridLogImport imported = ImportAprilgridLog(inputs);
  const Dataset official = FirstSeconds(imported.dataset, duration_s);
  if (official.cameras.size() < 2)
    throw InputError(data, 0, "", "the log must hold corners of cam0 and cam1");
  const Pose T_B_C0_official = official.cameras[0].T_B_C;
  const Pose T_B_C1_official = official.cameras[1].T_B_C;
  const CalibrationSource config = ReadCalibrationSource(data + "/config.yaml");
  std::optional<Pose> T_C0_C1_config;
  if (const auto it = config.cameras.find(1); it != config.cameras.end())
    T_C0_C1_config = it->second.T_C0_C;

  // 2. The smoother's starting point: coarse (axis-rounded rotation, zero translation) or the
  //    official values.
  Dataset start = official;
  if (initial == "coarse")
    for (auto& camera : start.cameras)
      camera.T_B_C = Pose(Eigen::Matrix3d(RoundToAxes(camera.T_B_C.R())), Eigen::Vector3d::Zero());

  std::map<std::string, std::string> smoother_options = {{"estimate_extrinsics", "1"},
                                                         {"estimate_time_offset", "1"}};
  for (const auto& [key, value] : options.settings)
    if (key.rfind("smoother.", 0) == 0) smoother_options[key.substr(9)] = value;

  std::vector<SmootherRun> runs = {{"cam0", "cam0", {}, 0, false, ""},
                                   {"cam1", "cam1", {}, 0, false, ""},
                                   {"cam0+cam1", "cam0,cam1", {}, 0, false, ""}};
  for (auto& run : runs) {
    ReportProgress(kImuAprilStage, "smoother with " + run.label);
    EstimatorOptions estimator_options(smoother_options);
    estimator_options.Set("cameras", run.cameras);
    auto smoother = FindEstimator("smoother")->create(estimator_options);
    const Applicability applies = smoother->AppliesTo(start);
    if (!applies.applies) {
      run.why = applies.reason;
      continue;
    }
    const auto t0 = std::chrono::steady_clock::now();
    run.estimate = smoother->Run(start);
    run.runtime_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    run.ran = !run.estimate.poses.empty();
    if (!run.ran) run.why = "no solution";
  }

  Report report;
  report.title =
      "EuRoC imu_april: the smoother and the papers' estimators on a real calibration log";
  report.provenance.input = data;
  report.protocol = ReportProtocolOf(SameImagesProtocol(), false);
  report.protocol->reference = "estimate";
  nlohmann::json& tables = report.details["tables"];
  std::string setup = fmt::format(
      "Log: `{}` ({} IMU samples, {} cam0 frames with {} tag observations, {} cam1 frames with {} "
      "tag observations, {:.1f} s). There is no ground truth: what is known is EuRoC's official "
      "camera-IMU calibration (`{}`, computed by Kalibr from these sequences), the stereo "
      "calibration T_cam0_cam1 of `config.yaml`, and that the board is static. The smoother starts "
      "from the {} T_B_C.\n\n",
      data, official.imu.samples.size(), official.cameras[0].frames.size(), official.tags.size(),
      official.cameras[1].frames.size(), official.tags1.size(),
      NsToSeconds(official.imu.samples.back().t_ns - official.imu.samples.front().t_ns),
      official_root,
      initial == "coarse" ? "coarse (official rotation rounded to the axes, zero translation)"
                          : "official");
  for (const auto& note : imported.notes) setup += "- " + note + "\n";
  report.sections.push_back({"Setup", setup});
  report.sections.back().before_tables = true;

  // 3. Extrinsics against the official calibration (the target: 1 cm and 0.5 deg).
  {
    ReportTable table =
        ReproTable("extrinsics_vs_official", "T_B_C against EuRoC's official calibration",
                   {"run", "camera", "dp x [m]", "dp y [m]", "dp z [m]", "|dp| [m]",
                    "dtheta x [rad]", "dtheta y [rad]", "dtheta z [rad]", "|dtheta| [rad]", "d^2 p",
                    "d^2 theta", "within 1 cm, 0.5 deg"});
    nlohmann::json rows = nlohmann::json::array();
    for (const auto& run : runs) {
      if (!run.ran) table.rows.push_back({run.label, "no solution: " + run.why});
      for (const auto& [camera, extrinsic] : run.estimate.extrinsics) {
        const Pose& reference = camera == "cam1" ? T_B_C1_official : T_B_C0_official;
        const ExtrinsicError e = CompareExtrinsic(extrinsic, reference);
        const bool within = e.dp.norm() < 0.01 && e.dtheta.norm() < 0.5 * kDeg;
        table.rows.push_back({run.label, camera, e.dp[0], e.dp[1], e.dp[2], e.dp.norm(),
                              e.dtheta[0], e.dtheta[1], e.dtheta[2], e.dtheta.norm(),
                              e.mahalanobis_p, e.mahalanobis_theta, within ? "yes" : "no"});
        rows.push_back({{"run", run.label},
                        {"camera", camera},
                        {"p_B_C_m", Xyz(extrinsic.T_B_C.p)},
                        {"translation_error_m", e.dp.norm()},
                        {"translation_error_xyz_m", Xyz(e.dp)},
                        {"rotation_error_rad", e.dtheta.norm()},
                        {"rotation_error_xyz_rad", Xyz(e.dtheta)},
                        {"three_sigma_p_m", e.sigma_p ? Xyz(3.0 * *e.sigma_p) : nlohmann::json()},
                        {"three_sigma_rotation_rad",
                         e.sigma_theta ? Xyz(3.0 * *e.sigma_theta) : nlohmann::json()},
                        {"mahalanobis_p", e.mahalanobis_p},
                        {"mahalanobis_rotation", e.mahalanobis_theta},
                        {"within_1cm_0.5deg", within},
                        {"paper", {{"translation_m", 0.01}, {"rotation_rad", 0.5 * kDeg}}}});
      }
    }
    table.rows.push_back(
        {"target", "", nullptr, nullptr, nullptr, 0.01, nullptr, nullptr, nullptr, 0.5 * kDeg});
    tables["extrinsics_vs_official"] = rows;
    report.tables.push_back(std::move(table));
    report.sections.push_back(
        {"T_B_C against EuRoC's official calibration",
         "Error = official - estimate (translation; rotation as Log(R_est^T R_official)); the "
         "target is 1 cm and 0.5 deg. Mahalanobis d^2 of the error (3 dof; 14.2 = 3 sigma) from "
         "the smoother's marginal covariance (its 3 sigma in details) treats the official value "
         "as exact, which it is not (it is Kalibr's estimate from the same data).\n"});
  }

  // 4. Stereo: the relative pose of the two estimates against T_cam0_cam1 of config.yaml.
  {
    ReportTable table = ReproTable(
        "stereo_vs_config", "The two cameras' relative pose against T_cam0_cam1 of config.yaml",
        {"from", "p_C0_C1 x [m]", "p_C0_C1 y [m]", "p_C0_C1 z [m]", "|dp| [m]", "dtheta [rad]"});
    auto add = [&](const std::string& label, const Pose& T_B_C0, const Pose& T_B_C1) {
      if (!T_C0_C1_config) return;
      const Pose T_C0_C1 = T_B_C0.Inverse() * T_B_C1;
      const double dp = (T_C0_C1.p - T_C0_C1_config->p).norm();
      const double dtheta = RotationAngleBetween(T_C0_C1.q, T_C0_C1_config->q);
      table.rows.push_back({label, T_C0_C1.p[0], T_C0_C1.p[1], T_C0_C1.p[2], dp, dtheta});
    };
    add("EuRoC official T_BS (cam0, cam1)", T_B_C0_official, T_B_C1_official);
    const SmootherRun& both = runs[2];
    if (both.ran && both.estimate.extrinsics.count("cam0") &&
        both.estimate.extrinsics.count("cam1"))
      add("smoother cam0+cam1", both.estimate.extrinsics.at("cam0").T_B_C,
          both.estimate.extrinsics.at("cam1").T_B_C);
    if (runs[0].ran && runs[1].ran && runs[0].estimate.extrinsics.count("cam0") &&
        runs[1].estimate.extrinsics.count("cam1"))
      add("smoother cam0 run, cam1 run", runs[0].estimate.extrinsics.at("cam0").T_B_C,
          runs[1].estimate.extrinsics.at("cam1").T_B_C);
    if (T_C0_C1_config)
      report.tables.push_back(std::move(table));
    else
      report.warnings.push_back("config.yaml has no T_cam0_cam1: no stereo comparison");
  }

  // 5. Time offset, reprojection, robust loss, board tilt, run time.
  {
    ReportTable table = ReproTable(
        "smoother_solutions", "Time offset, reprojection and gravity of the smoother's solutions",
        {"run", "t_d [s]", "sigma t_d [s]", "reprojection rms [px]", "down-weighted corners",
         "board roll [rad]", "board pitch [rad]", "runtime [s]"});
    for (const auto& run : runs) {
      if (!run.ran) continue;
      const Estimate& e = run.estimate;
      table.rows.push_back({run.label, Param(e, "time_offset"), Param(e, "time_offset", true),
                            Param(e, "reprojection_rms"), Param(e, "downweighted_corners"),
                            Param(e, "board_roll"), Param(e, "board_pitch"), run.runtime_s});
    }
    report.tables.push_back(std::move(table));
    report.sections.push_back(
        {"Time offset, reprojection and gravity of the smoother's solutions",
         "t_d: exposure = image stamp + t_d (EuRoC's VI-sensor is hardware-synchronised, so 0 is "
         "expected). Reprojection RMS over every corner of the solution; corners the robust loss "
         "down-weights (whitened error beyond its scale).\n"});
  }

  // 6. cam0-only against cam1-only trajectories.
  if (runs[0].ran && runs[1].ran) {
    const auto ate =
        EvaluateTrajectory(runs[0].estimate.poses, runs[1].estimate.poses, SameImagesProtocol());
    if (ate) {
      tables["cam0_vs_cam1_trajectories"] = {
          {"pairs", ate->pair_count},
          {"position_rms_m", ate->ape_translation_m.rmse},
          {"position_max_m", ate->ape_translation_m.max},
          {"rotation_rms_rad", ate->ape_rotation_deg.rmse * kDeg}};
      report.sections.push_back(
          {"cam0-only against cam1-only",
           fmt::format("The body trajectories of the two independent solutions (each in the W of "
                       "its own gravity estimate) over {} common keyframes: position RMS {} mm "
                       "(max {} mm), rotation RMS {} deg.\n",
                       ate->pair_count, FormatNumber(ate->ape_translation_m.rmse * 1e3, 2),
                       FormatNumber(ate->ape_translation_m.max * 1e3, 2),
                       FormatNumber(ate->ape_rotation_deg.rmse, 3))});
    }
  }

  // 7. The papers' estimators against the smoother (cam0, and both cameras) as the reference.
  {
    std::vector<std::pair<std::string, Estimate>> results;
    for (const auto& name : estimators) {
      ReportProgress(kImuAprilStage, name);
      const auto [estimator_name, variant_options] = split_variant(name);
      EstimatorEvaluation e = RunAndEvaluate(estimator_name, variant_options, official, {});
      if (!e.ran) {
        results.push_back({name + " (skipped: " + e.skipped_reason + ")", Estimate{}});
        continue;
      }
      results.push_back({name, std::move(e.estimate)});
    }
    ReportTable table =
        ReproTable("papers_vs_smoother", "The papers' estimators against the smoother",
                   {"reference", "estimator", "W: position RMS [m]", "W: rotation RMS [rad]",
                    "M: position RMS [m]", "M: rotation RMS [rad]", "gravity angle [rad]",
                    "reprojection rms [px]", "corners off image", "no solution"});
    nlohmann::json comparisons = nlohmann::json::object();
    std::string events;  // filter resets and other events, once per estimator
    for (const auto& [name, estimate] : results)
      for (const auto& event : estimate.events) events += "- " + name + ": " + event + "\n";
    for (int r : {0, 2}) {
      if (!runs[r].ran) continue;
      const std::string reference_name = "smoother " + runs[r].label;
      const ComparisonReference reference = ReferenceFromEstimate(reference_name, runs[r].estimate);
      EvaluationOptions evaluation_options;
      evaluation_options.reference = &reference;
      for (const auto& [name, estimate] : results) {
        if (estimate.poses.empty() && estimate.quantities.empty()) {
          table.rows.push_back({reference_name, name});
          continue;
        }
        const auto e =
            EvaluateEstimate(split_variant(name).first, estimate, official, evaluation_options);
        // The same in the board frame M (T_M_B = T_W_M^-1 T_W_B of each): the pose estimation
        // without the gravity estimate, and the angle between the two gravity directions.
        const InBoard board = CompareInBoard(estimate, runs[r].estimate);
        const auto ate = [&](auto f) {
          return e.ate ? nlohmann::json(f(*e.ate)) : nlohmann::json();
        };
        table.rows.push_back(
            {reference_name, name, ate([](const AteResult& a) { return a.translation_m.rmse; }),
             ate([](const AteResult& a) { return a.rotation_rad.rmse; }), board.position_rms_m,
             board.rotation_rms_rad, board.gravity_angle_rad,
             e.reprojection.empty() ? nlohmann::json() : nlohmann::json(e.reprojection[0].rms_px),
             e.reprojection.empty() ? nlohmann::json()
                                    : nlohmann::json(e.reprojection[0].off_image),
             estimate.FailureCount()});
        nlohmann::json entry = EvaluationToJson(e);
        entry["in_board_frame"] = {{"position_rms_m", board.position_rms_m},
                                   {"rotation_rms_rad", board.rotation_rms_rad},
                                   {"gravity_angle_rad", board.gravity_angle_rad}};
        comparisons[reference_name][name] = entry;
      }
    }
    tables["papers_vs_smoother"] = comparisons;
    report.tables.push_back(std::move(table));
    report.sections.push_back(
        {"The papers' estimators against the smoother",
         "The reference is the smoother's solution: an estimate, not a truth. The papers' "
         "estimators use cam0 with EuRoC's official T_B_C and initialise the board's gravity "
         "direction from the first frames. Differences: ATE RMS (no alignment) and rotation RMS in "
         "W (each estimator's own gravity-aligned frame, core/board_frame.h), the same in the "
         "board frame M (pose estimation alone), the angle between the two gravity estimates; "
         "reprojection RMS of cam0's corners through each estimator's own poses and board tilt.\n" +
             (events.empty() ? std::string() : "\nEvents:\n\n" + events)});
  }
  return report;
}

}  // namespace

ReproDefinition EurocImuAprilRepro() {
  return {.name = "euroc-imu-april",
          .description =
              "smoother calibration (T_B_C, t_d, gravity) and the papers' tag "
              "estimators on EuRoC's real imu_april log, against EuRoC's official "
              "calibration",
          .paper = "EuRoC imu_april, real aprilgrid corners + IMU, no ground truth",
          .single = EurocImuAprilReport};
}

}  // namespace mavloc
