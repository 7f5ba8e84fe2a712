#include "evaluation/repro/apriltag_repro.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "core/errors.h"
#include "core/key_values.h"
#include "core/numbers.h"
#include "core/progress.h"
#include "core/random.h"
#include "core/rotation.h"
#include "core/tag_geometry.h"
#include "datasets/rendering/tag_renderer.h"
#include "datasets/scenarios/tag_arena.h"
#include "evaluation/comparison.h"
#include "evaluation/exact_json.h"
#include "evaluation/json_number.h"
#include "evaluation/report_writer.h"
#include "evaluation/repro/repro_units.h"
#include "frontends/apriltag/detect_tags.h"
#include "frontends/apriltag/tag_pose.h"

namespace mavloc {

namespace {

using Settings = std::map<std::string, std::string>;
using Clock = std::chrono::steady_clock;

constexpr int kAprilTagDefaultRuns = 100;
// The paper's dynamic-tracking peaks (V-C).
constexpr double kPaperPositionPeakM = 0.05;
constexpr double kPaperVelocityPeakMs = 0.06;
constexpr double kPaperRollPeakRad = 0.009;
constexpr double kPaperPitchPeakRad = 0.014;
constexpr double kPaperHoverConvergenceS = 2.0;
// Hover convergence thresholds (stated in the report): the error stays below them from then on.
constexpr double kConvergedPositionM = 0.05;
constexpr double kConvergedVelocityMs = 0.05;
constexpr double kConvergedAttitudeRad = 0.02;
// The dynamic peaks are taken from this long after the first tag measurement (the convergence
// transient of the filter started at zero is excluded, as in the paper's reading of fig. 16-19).
constexpr double kDynamicSettleS = 3.0;
// NEES statistics exclude the initial convergence.
constexpr double kNeesStartS = 3.0;

double Elapsed(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// Chi-square quantile (Wilson & Hilferty 1931): k (1 - 2/(9k) + z sqrt(2/(9k)))^3; for the
// k = 3 N >= 6 degrees of freedom used here its relative error is below 1 %.
double ChiSquareQuantile(double k, double z) {
  const double a = 2.0 / (9.0 * k);
  return k * std::pow(1.0 - a + z * std::sqrt(a), 3);
}
constexpr double kZ975 = 1.959963984540054;

struct RunningStat {
  double sum = 0.0, max = 0.0;
  long count = 0;
  void Add(double v) {
    sum += v;
    max = std::max(max, v);
    ++count;
  }
  double Mean() const { return count ? sum / count : kNaN; }
  nlohmann::json Json() const { return {{"mean", Mean()}, {"max", count ? max : kNaN}}; }
};

struct ImageStats {
  int frames = 0;
  int visible = 0;           // tags whose page lies inside the image (3 px border)
  int visible_detected = 0;  // of those, detected
  int detections = 0;
  int false_detections = 0;  // ids not in the map, or not where the tag is
  RunningStat corner_px, pose_position_m, pose_angle_rad;
  double render_s = 0.0, detect_s = 0.0;
};

// Renders every cam0 frame of the dataset (truth pose, optional blur over the exposure), detects
// the tags, and returns them as tags0 rows; fills the detector statistics.
std::vector<TagObservation> TagsFromImages(const Dataset& d, const Settings& settings,
                                           uint64_t noise_seed, ImageStats* stats) {
  const CameraSensor& camera = d.cameras.front();
  TagRenderOptions render_options;
  render_options.supersampling = GetIntSetting(settings, "supersampling", 4);
  render_options.noise_sigma_grey = GetDoubleSetting(settings, "image_noise_grey", 2.0);
  const double exposure_s = GetDoubleSetting(settings, "exposure_s", 0.0);
  const int blur_samples = GetIntSetting(settings, "blur_samples", 5);
  TagDetectorOptions detector_options;
  detector_options.refine_edges = GetBoolSetting(settings, "refine_edges", true);
  detector_options.decimate = GetDoubleSetting(settings, "decimate", 1.0);
  const TagRenderer renderer(camera.model, d.map.tags, render_options);
  RectifiedTagDetector detector(detector_options, camera.model);
  std::vector<TagObservation> out;
  for (size_t i = 0; i < camera.frames.size(); ++i) {
    const TimeNs t = camera.frames[i].t_ns;
    std::vector<Pose> poses;
    const int n = exposure_s > 0.0 ? std::max(1, blur_samples) : 1;
    for (int k = 0; k < n; ++k) {
      const double offset = n == 1 ? 0.0 : exposure_s * ((k + 0.5) / n - 0.5);
      poses.push_back(InterpolatedTruth(d.ground_truth, t + SecondsToNs(offset)).T_W_B *
                      camera.T_B_C);
    }
    auto start = Clock::now();
    const cv::Mat image = renderer.Render(poses, SplitMix64(noise_seed + 7919 * i));
    stats->render_s += Elapsed(start);
    start = Clock::now();
    const auto detections = detector.Detect(image);
    stats->detect_s += Elapsed(start);
    ++stats->frames;

    const Pose T_C_W = (InterpolatedTruth(d.ground_truth, t).T_W_B * camera.T_B_C).Inverse();
    std::map<int, bool> visible;
    for (const auto& [id, tag] : d.map.tags) {
      TagInfo page = tag;
      page.size_m *= 12.0 / 8.0;
      bool inside = true;
      for (const auto& c : TagCornersInWorld(page)) {
        const auto uv = camera.model.Project(T_C_W * c, 0.05);
        inside = inside && uv && camera.model.IsInside(*uv, 3.0);
      }
      if (inside) visible[id] = false;
    }
    for (const auto& det : detections) {
      ++stats->detections;
      const auto tag = d.map.tags.find(det.id);
      if (tag == d.map.tags.end()) {
        ++stats->false_detections;
        continue;
      }
      const auto corners_W = TagCornersInWorld(tag->second);
      double worst = 0.0;
      std::vector<double> errors;
      for (int k = 0; k < 4; ++k) {
        const auto uv = camera.model.Project(T_C_W * corners_W[k], 0.05);
        const double e = uv ? (det.corners_px[k] - *uv).norm() : 1e9;
        worst = std::max(worst, e);
        errors.push_back(e);
      }
      if (worst > 5.0) {
        ++stats->false_detections;
        continue;
      }
      for (const double e : errors) stats->corner_px.Add(e);
      if (visible.count(det.id)) visible[det.id] = true;
      const TagPoseResult pose = EstimateTagPose(det.corners_px, tag->second.size_m, camera.model);
      if (pose.ok) {
        const Pose T_C_T = T_C_W * tag->second.T_W_T;
        stats->pose_position_m.Add((pose.T_C_T.p - T_C_T.p).norm());
        stats->pose_angle_rad.Add(RotationAngleBetween(pose.T_C_T.q, T_C_T.q));
      }
      TagObservation obs;
      obs.t_ns = t;
      obs.tag_id = det.id;
      obs.corners_px = det.corners_px;
      out.push_back(obs);
    }
    for (const auto& [id, found] : visible) {
      ++stats->visible;
      if (found) ++stats->visible_detected;
    }
    if (i % 50 == 0)
      ReportProgress("repro apriltag", fmt::format("{}: frame {}/{} rendered and detected",
                                                   d.scenario, i + 1, camera.frames.size()));
  }
  return out;
}

nlohmann::json ImageStatsJson(const ImageStats& s, bool from_images) {
  if (!from_images) return {{"source", "projected true corners + noise (images=0)"}};
  return {
      {"source", "rendered images -> libapriltag (rectified) -> tags0"},
      {"frames", s.frames},
      {"visible_tags", s.visible},
      {"visible_tags_detected", s.visible_detected},
      {"recall", s.visible ? static_cast<double>(s.visible_detected) / s.visible : kNaN},
      {"detections", s.detections},
      {"false_detections", s.false_detections},
      {"corner_error_px", s.corner_px.Json()},
      {"tag_pose_position_error_m", s.pose_position_m.Json()},
      {"tag_pose_angle_error_rad",
       {{"mean", s.pose_angle_rad.Mean()},
        {"max", s.pose_angle_rad.count ? s.pose_angle_rad.max : kNaN}}},
      {"render_s_per_frame", s.frames ? s.render_s / s.frames : kNaN},
      {"detect_s_per_frame", s.frames ? s.detect_s / s.frames : kNaN},
  };
}

// Per-stamp errors of a tag-ekf (or other) estimate against the truth.
struct ErrorSample {
  double t_s = 0.0;
  Eigen::Vector3d p = Eigen::Vector3d::Constant(kNaN);    // est - truth
  Eigen::Vector3d v = Eigen::Vector3d::Constant(kNaN);    // est - truth (NaN without velocity)
  Eigen::Vector3d rpy = Eigen::Vector3d::Constant(kNaN);  // wrapped
  double nees_p = kNaN, nees_v = kNaN, nees_a = kNaN;
};

std::vector<ErrorSample> Errors(const Estimate& estimate, const Dataset& d) {
  std::vector<ErrorSample> out;
  const QuantityTable& q = estimate.quantities;
  const int ix = q.Index("x"), iroll = q.Index("roll"), ivx = q.Index("vx");
  const TimeNs t0 = d.ground_truth.front().t_ns;
  std::map<TimeNs, const Eigen::MatrixXd*> covariances;
  for (const auto& c : estimate.covariances) covariances[c.t_ns] = &c.covariance;
  for (size_t i = 0; i < q.size(); ++i) {
    const TimeNs t = q.t_ns[i];
    if (t < d.ground_truth.front().t_ns || t > d.ground_truth.back().t_ns) continue;
    const GroundTruthState gt = InterpolatedTruth(d.ground_truth, t);
    const EulerRpy rpy = EulerFromQuaternion(gt.T_W_B.q);
    ErrorSample e;
    e.t_s = NsToSeconds(t - t0);
    const auto& row = q.rows[i];
    if (ix >= 0) e.p = Eigen::Vector3d(row[ix], row[ix + 1], row[ix + 2]) - gt.T_W_B.p;
    if (ivx >= 0) e.v = Eigen::Vector3d(row[ivx], row[ivx + 1], row[ivx + 2]) - gt.v_W;
    if (iroll >= 0)
      e.rpy =
          Eigen::Vector3d(WrapAngle(row[iroll] - rpy.roll), WrapAngle(row[iroll + 1] - rpy.pitch),
                          WrapAngle(row[iroll + 2] - rpy.yaw));
    const auto c = covariances.find(t);
    if (c != covariances.end() && estimate.covariance_names.size() == 9) {
      // Covariance order: x y z roll pitch yaw vx vy vz.
      const Eigen::MatrixXd& P = *c->second;
      e.nees_p = e.p.dot(P.block<3, 3>(0, 0).ldlt().solve(e.p));
      e.nees_a = e.rpy.dot(P.block<3, 3>(3, 3).ldlt().solve(e.rpy));
      e.nees_v = e.v.dot(P.block<3, 3>(6, 6).ldlt().solve(e.v));
    }
    out.push_back(e);
  }
  return out;
}

// The time after which metric(sample) stays below the threshold (NaN if it ends above it).
template <typename Metric>
double ConvergenceTime(const std::vector<ErrorSample>& samples, double threshold, Metric metric) {
  double t = samples.empty() ? kNaN : samples.front().t_s;
  for (const auto& s : samples) {
    if (!(metric(s) < threshold))
      t = kNaN;
    else if (std::isnan(t))
      t = s.t_s;
  }
  return t;
}

template <typename Metric>
double MeanOverLast(const std::vector<ErrorSample>& samples, double seconds, Metric metric) {
  if (samples.empty()) return kNaN;
  const double t_end = samples.back().t_s;
  double sum = 0.0;
  int n = 0;
  for (const auto& s : samples) {
    if (s.t_s >= t_end - seconds) {
      sum += metric(s);
      ++n;
    }
  }
  return n ? sum / n : kNaN;
}

double Median(std::vector<double> v) {
  v.erase(std::remove_if(v.begin(), v.end(), [](double x) { return std::isnan(x); }), v.end());
  if (v.empty()) return kNaN;
  std::sort(v.begin(), v.end());
  return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

nlohmann::json Summary(const std::vector<double>& values) {
  std::vector<double> finite;
  for (double v : values)
    if (!std::isnan(v)) finite.push_back(v);
  if (finite.empty()) return {{"mean", kNaN}, {"median", kNaN}, {"max", kNaN}, {"count", 0}};
  double sum = 0.0;
  for (double v : finite) sum += v;
  return {{"mean", sum / finite.size()},
          {"median", Median(finite)},
          {"max", *std::max_element(finite.begin(), finite.end())},
          {"count", finite.size()}};
}

std::string TagNumber(double v, int digits = 3) { return FormatNumber(v, digits); }

// ImageStats as exact JSON (a unit's result; evaluation/exact_json.h).
constexpr auto ExactFields(std::type_identity<RunningStat>) {
  return std::make_tuple(ExactField("sum", &RunningStat::sum), ExactField("max", &RunningStat::max),
                         ExactField("count", &RunningStat::count));
}
constexpr auto ExactFields(std::type_identity<ImageStats>) {
  return std::make_tuple(
      ExactField("frames", &ImageStats::frames), ExactField("visible", &ImageStats::visible),
      ExactField("visible_detected", &ImageStats::visible_detected),
      ExactField("detections", &ImageStats::detections),
      ExactField("false_detections", &ImageStats::false_detections),
      ExactField("corner_px", &ImageStats::corner_px),
      ExactField("pose_position_m", &ImageStats::pose_position_m),
      ExactField("pose_angle_rad", &ImageStats::pose_angle_rad),
      ExactField("render_s", &ImageStats::render_s), ExactField("detect_s", &ImageStats::detect_s));
}

// The reproduction's settings, checked once.
struct AprilTagSettings {
  Settings raw;  // every --set (the image pipeline reads its keys from here)
  double hover_s = 10.0, dynamic_s = 40.0;
  bool from_images = true;
  std::optional<uint64_t> hover_images_seed;  // default: the first seed
  Settings scenario;                          // handed to the tag-arena scenarios
};

AprilTagSettings ParseAprilTagSettings(const Settings& settings) {
  // Every key read here, by the image pipeline (supersampling ... decimate) or handed to the
  // scenario (processing_delay_s, corner_noise_px, camera_offset_s).
  RejectUnknownReproSettings(
      "apriltag", settings,
      {"hover_duration_s", "dynamic_duration_s", "images", "hover_images_seed", "supersampling",
       "image_noise_grey", "exposure_s", "blur_samples", "refine_edges", "decimate",
       "processing_delay_s", "corner_noise_px", "camera_offset_s"});
  AprilTagSettings out;
  out.raw = settings;
  out.hover_s = GetDoubleSetting(settings, "hover_duration_s", 10.0);
  out.dynamic_s = GetDoubleSetting(settings, "dynamic_duration_s", 40.0);
  out.from_images = GetBoolSetting(settings, "images", true);
  if (!(out.hover_s >= 3.0 && out.hover_s <= kMaxScenarioDurationS))
    throw InputError("", 0, "hover_duration_s", "must be in [3, 3600] s (kMaxScenarioDurationS)");
  if (!(out.dynamic_s >= 8.0 && out.dynamic_s <= kMaxScenarioDurationS))
    throw InputError("", 0, "dynamic_duration_s", "must be in [8, 3600] s (kMaxScenarioDurationS)");
  if (settings.count("hover_images_seed")) {
    const int seed = GetIntSetting(settings, "hover_images_seed", 0);
    if (seed < 0) throw InputError("", 0, "hover_images_seed", "must be >= 0");
    out.hover_images_seed = static_cast<uint64_t>(seed);
  }
  for (const char* key : {"processing_delay_s", "corner_noise_px", "camera_offset_s"}) {
    if (settings.count(key)) out.scenario[key] = settings.at(key);
  }
  out.scenario["projected_tags"] = out.from_images ? "0" : "1";
  return out;
}

// The hover's rendered and detected tags: the hover flight is the same for every seed (only the
// IMU noise and the filter's initial state change), so its images are rendered once per process
// and images seed (hover units of one worker share them). Rendering and detection are
// deterministic, so every worker gets the same tags.
struct HoverImages {
  std::vector<TagObservation> tags;
  ImageStats stats;
};
const HoverImages& RenderedHover(const AprilTagSettings& settings, uint64_t images_seed) {
  static std::mutex mutex;
  static std::map<std::string, HoverImages> cache;
  const std::string key = nlohmann::json(settings.raw).dump() + "@" + std::to_string(images_seed);
  const std::lock_guard<std::mutex> lock(mutex);
  const auto it = cache.find(key);
  if (it != cache.end()) return it->second;
  ScenarioOptions scenario;
  scenario.seed = images_seed;
  scenario.duration_s = settings.hover_s;
  scenario.settings = settings.scenario;
  const Dataset d = GenerateTagArenaHover(scenario);
  HoverImages images;
  images.tags = TagsFromImages(d, settings.raw, SplitMix64(images_seed), &images.stats);
  return cache.emplace(key, std::move(images)).first->second;
}

// A hover run's error samples, reduced to what the report uses (NEES and the error envelope).
nlohmann::json HoverSamplesJson(const std::vector<ErrorSample>& errors) {
  std::vector<double> t, p, v, a, np, nv, na;
  for (const auto& e : errors) {
    t.push_back(e.t_s);
    p.push_back(e.p.norm());
    v.push_back(e.v.norm());
    a.push_back(e.rpy.cwiseAbs().maxCoeff());
    np.push_back(e.nees_p);
    nv.push_back(e.nees_v);
    na.push_back(e.nees_a);
  }
  return {{"t_s", JsonNumbers(t)},          {"position_m", JsonNumbers(p)},
          {"velocity_m_s", JsonNumbers(v)}, {"attitude_rad", JsonNumbers(a)},
          {"nees_p", JsonNumbers(np)},      {"nees_v", JsonNumbers(nv)},
          {"nees_a", JsonNumbers(na)}};
}

// One hover unit: the run of `seed` with P0 matched and with P0 x0.1 (V-B), and the hover images'
// statistics.
nlohmann::json HoverUnit(const AprilTagSettings& settings, uint64_t images_seed, uint64_t seed) {
  ScenarioOptions scenario;
  scenario.seed = seed;
  scenario.duration_s = settings.hover_s;
  scenario.settings = settings.scenario;
  Dataset d = GenerateTagArenaHover(scenario);
  nlohmann::json out;
  if (settings.from_images) {
    const HoverImages& images = RenderedHover(settings, images_seed);
    d.tags = images.tags;
    out["images"] = ToExactJson(images.stats);
  }
  EvaluationOptions evaluation;
  for (const double p0_scale : {1.0, 0.1}) {
    EstimatorOptions ekf_options;
    ekf_options.Set("init", "perturbed");
    ekf_options.Set("init_seed", std::to_string(seed));
    ekf_options.Set("init_p0_scale", fmt::format("{}", p0_scale));
    // An over-confident P0 makes the first innovations look like outliers: the paper's filter has
    // no gate, so the gate is off for that variant.
    if (p0_scale != 1.0) ekf_options.Set("gate_chi2", "0");
    const EstimatorEvaluation e = RunAndEvaluate("tag-ekf", ekf_options, d, evaluation);
    if (!e.ran) throw InputError("tag-ekf did not run on the hover: " + e.skipped_reason);
    const auto errors = Errors(e.estimate, d);
    if (errors.empty()) throw InputError("tag-ekf gave no estimate on the hover");
    auto pos = [](const ErrorSample& s) { return s.p.norm(); };
    auto vel = [](const ErrorSample& s) { return s.v.norm(); };
    auto att = [](const ErrorSample& s) { return s.rpy.cwiseAbs().maxCoeff(); };
    nlohmann::json run = {
        {"initial_pos", JsonNumber(errors.front().p.norm())},
        {"t_pos", JsonNumber(ConvergenceTime(errors, kConvergedPositionM, pos))},
        {"t_vel", JsonNumber(ConvergenceTime(errors, kConvergedVelocityMs, vel))},
        {"t_att", JsonNumber(ConvergenceTime(errors, kConvergedAttitudeRad, att))},
        {"final_pos", JsonNumber(MeanOverLast(errors, 1.0, pos))},
        {"final_vel", JsonNumber(MeanOverLast(errors, 1.0, vel))},
        {"final_att", JsonNumber(MeanOverLast(errors, 1.0, att))}};
    if (p0_scale == 1.0) run["samples"] = HoverSamplesJson(errors);
    out[p0_scale == 1.0 ? "p0_matched" : "p0_confident"] = run;
  }
  return out;
}

const std::vector<std::string> kDynamicNames = {"x",  "y",    "z",     "vx", "vy",
                                                "vz", "roll", "pitch", "yaw"};

// The dynamic unit (V-C): the fast-turn flight of `seed` rendered and detected, each variant's
// peak errors after convergence; {"dynamic": table JSON, "csv", "images",
// "processing_delay_s"}.
nlohmann::json DynamicUnit(const AprilTagSettings& settings, uint64_t seed) {
  ScenarioOptions dynamic_scenario;
  dynamic_scenario.seed = seed;
  dynamic_scenario.duration_s = settings.dynamic_s;
  dynamic_scenario.settings = settings.scenario;
  Dataset dynamic = GenerateTagArenaDynamic(dynamic_scenario);
  ImageStats dynamic_image_stats;
  if (settings.from_images)
    dynamic.tags =
        TagsFromImages(dynamic, settings.raw, SplitMix64(seed + 1), &dynamic_image_stats);
  if (dynamic.tags.empty())
    throw InputError("repro apriltag: no tag detected in the dynamic flight");
  const double first_tag_s =
      NsToSeconds(dynamic.tags.front().t_ns - dynamic.ground_truth.front().t_ns);
  const double window_s = first_tag_s + kDynamicSettleS;
  struct Variant {
    std::string label, estimator;
    std::map<std::string, std::string> options;
  };
  const std::vector<Variant> variants = {
      {"tag-ekf", "tag-ekf", {}},
      {"tag-ekf (delay ignored)", "tag-ekf", {{"compensate_delay", "0"}}},
      {"tag-ekf (no tags)", "tag-ekf", {{"use_tags", "0"}}},
      // The paper's baseline: every tag, every frame on its own, the map as given.
      {"tag-pnp", "tag-pnp", {{"ransac", "0"}, {"refine_map", "0"}, {"neighbour_gate_m", "0"}}},
  };
  nlohmann::json dynamic_json = {{"first_tag_s", first_tag_s},
                                 {"window_start_s", window_s},
                                 {"duration_s", settings.dynamic_s},
                                 {"estimators", nlohmann::json::object()}};
  std::string dynamic_csv =
      "estimator,t [s],ex [m],ey [m],ez [m],evx [m/s],evy [m/s],evz [m/s],"
      "eroll [rad],epitch [rad],eyaw [rad]\n";
  EvaluationOptions evaluation;
  for (const auto& variant : variants) {
    const EstimatorEvaluation e =
        RunAndEvaluate(variant.estimator, EstimatorOptions(variant.options), dynamic, evaluation);
    if (!e.ran) throw InputError(variant.label + " did not run: " + e.skipped_reason);
    const auto errors = Errors(e.estimate, dynamic);
    if (errors.empty()) throw InputError(variant.label + " gave no estimate on the dynamic flight");
    std::map<std::string, double> peak, sum2;
    std::map<std::string, int> count;
    for (const auto& s : errors) {
      const double values[9] = {s.p.x(), s.p.y(),   s.p.z(),   s.v.x(),  s.v.y(),
                                s.v.z(), s.rpy.x(), s.rpy.y(), s.rpy.z()};
      if (variant.label == "tag-pnp" || static_cast<long>(s.t_s * 100) % 5 == 0) {
        dynamic_csv += fmt::format("{},{:.3f}", variant.label, s.t_s);
        for (double v : values) dynamic_csv += fmt::format(",{:.6g}", v);
        dynamic_csv += "\n";
      }
      if (s.t_s < window_s) continue;
      for (int k = 0; k < 9; ++k) {
        if (std::isnan(values[k])) continue;
        peak[kDynamicNames[k]] = std::max(peak[kDynamicNames[k]], std::abs(values[k]));
        sum2[kDynamicNames[k]] += values[k] * values[k];
        ++count[kDynamicNames[k]];
      }
    }
    nlohmann::json entry = {{"peak_abs_error", nlohmann::json::object()},
                            {"rmse", nlohmann::json::object()},
                            {"final_position_error_m", errors.back().p.norm()},
                            {"runtime_s", e.runtime_s}};
    for (const auto& name : kDynamicNames) {
      const bool has = count[name] > 0;
      entry["peak_abs_error"][name] = JsonNumber(has ? peak[name] : kNaN);
      entry["rmse"][name] = JsonNumber(has ? std::sqrt(sum2[name] / count[name]) : kNaN);
    }
    if (!e.estimate.failures.empty()) entry["failures"] = e.estimate.failures;
    if (!e.estimate.rejections.empty()) entry["rejections"] = e.estimate.rejections;
    dynamic_json["estimators"][variant.label] = entry;
  }
  nlohmann::json out = {{"dynamic", dynamic_json},
                        {"csv", dynamic_csv},
                        {"processing_delay_s", dynamic.scenario_info.at("processing_delay_s")}};
  if (settings.from_images) out["images"] = ToExactJson(dynamic_image_stats);
  return out;
}

constexpr const char* kHoverUnit = "hover";
constexpr const char* kDynamicUnit = "dynamic";

nlohmann::json AprilTagUnitResult(const ReproSettings& raw, const std::string& unit,
                                  uint64_t seed) {
  const AprilTagSettings settings = ParseAprilTagSettings(raw);
  if (unit == kDynamicUnit) return DynamicUnit(settings, seed);
  if (unit == kHoverUnit)
    return HoverUnit(settings, settings.hover_images_seed.value_or(seed), seed);
  throw InputError("repro apriltag: no unit '" + unit + "'");
}

struct HoverResult {
  std::vector<double> t_pos, t_vel, t_att, final_pos, final_vel, final_att, initial_pos;
};
void AddHoverRun(const nlohmann::json& run, HoverResult* r) {
  r->initial_pos.push_back(NumberFromJson(run.at("initial_pos")));
  r->t_pos.push_back(NumberFromJson(run.at("t_pos")));
  r->t_vel.push_back(NumberFromJson(run.at("t_vel")));
  r->t_att.push_back(NumberFromJson(run.at("t_att")));
  r->final_pos.push_back(NumberFromJson(run.at("final_pos")));
  r->final_vel.push_back(NumberFromJson(run.at("final_vel")));
  r->final_att.push_back(NumberFromJson(run.at("final_att")));
}

// A hover run's reduced error samples (HoverSamplesJson) back from JSON.
struct HoverSamples {
  std::vector<double> t_s, p, v, a, nees_p, nees_v, nees_a;
};
HoverSamples HoverSamplesFromJson(const nlohmann::json& j) {
  return {NumbersFromJson(j.at("t_s")),          NumbersFromJson(j.at("position_m")),
          NumbersFromJson(j.at("velocity_m_s")), NumbersFromJson(j.at("attitude_rad")),
          NumbersFromJson(j.at("nees_p")),       NumbersFromJson(j.at("nees_v")),
          NumbersFromJson(j.at("nees_a"))};
}

// The average NEES of the hover runs per block, step by step, against the 95 % band of N runs.
struct AprilTagNees {
  struct Block {
    double sum = 0.0;
    int inside = 0, count = 0;
    nlohmann::json Json() const {
      return {{"dof", 3},
              {"mean_anees", count ? sum / count : kNaN},
              {"fraction_in_band", count ? static_cast<double>(inside) / count : kNaN}};
    }
  };
  double band_lo = kNaN, band_hi = kNaN;
  Block position, velocity, attitude;
  std::string csv;
};

AprilTagNees HoverNees(const std::vector<HoverSamples>& runs, size_t steps) {
  const auto n = static_cast<double>(runs.size());
  AprilTagNees out;
  out.band_lo = ChiSquareQuantile(3.0 * n, -kZ975) / n;
  out.band_hi = ChiSquareQuantile(3.0 * n, kZ975) / n;
  out.csv = "t [s],anees_position,anees_velocity,anees_attitude,band_low,band_high\n";
  for (size_t i = 0; i < steps; ++i) {
    double p = 0.0, v = 0.0, a = 0.0;
    for (const auto& run : runs) {
      p += run.nees_p[i];
      v += run.nees_v[i];
      a += run.nees_a[i];
    }
    p /= n;
    v /= n;
    a /= n;
    const double t = runs.front().t_s[i];
    out.csv += fmt::format("{:.3f},{:.5g},{:.5g},{:.5g},{:.5g},{:.5g}\n", t, p, v, a, out.band_lo,
                           out.band_hi);
    if (t < kNeesStartS) continue;
    for (auto [block, value] :
         {std::pair{&out.position, p}, std::pair{&out.velocity, v}, std::pair{&out.attitude, a}}) {
      block->sum += value;
      block->count += 1;
      block->inside += (value >= out.band_lo && value <= out.band_hi) ? 1 : 0;
    }
  }
  return out;
}

// The hover envelope (mean and max over the runs), every fifth step.
std::string HoverEnvelopeCsv(const std::vector<HoverSamples>& runs, size_t steps) {
  std::string csv =
      "t [s],position_error_mean [m],position_error_max [m],velocity_error_mean [m/s],"
      "velocity_error_max [m/s],attitude_error_mean [rad],attitude_error_max [rad]\n";
  for (size_t i = 0; i < steps; i += 5) {
    RunningStat p, v, a;
    for (const auto& run : runs) {
      p.Add(run.p[i]);
      v.Add(run.v[i]);
      a.Add(run.a[i]);
    }
    csv += fmt::format("{:.3f},{:.5g},{:.5g},{:.5g},{:.5g},{:.5g},{:.5g}\n", runs.front().t_s[i],
                       p.Mean(), p.max, v.Mean(), v.max, a.Mean(), a.max);
  }
  return csv;
}

ReportTable AprilTagImagesTable(const ImageStats& hover, const ImageStats& dynamic) {
  ReportTable table =
      ReproTable("images", "images: the detector on the rendered frames",
                 {"flight", "frames", "visible tags", "visible tags detected", "false detections",
                  "corner error mean [px]", "corner error max [px]",
                  "tag pose position error mean [m]", "tag pose angle error mean [rad]"});
  for (const auto& [label, s] :
       {std::pair<std::string, const ImageStats*>{"hover", &hover}, {"dynamic", &dynamic}})
    table.rows.push_back({label, s->frames, s->visible, s->visible_detected, s->false_detections,
                          s->corner_px.Mean(), s->corner_px.max, s->pose_position_m.Mean(),
                          s->pose_angle_rad.Mean()});
  return table;
}

// One hover table per error (position, velocity, attitude): convergence time and final error for
// both P0 variants, and the paper's convergence time.
ReportTable AprilTagHoverTable(const std::string& error, const std::string& unit, double threshold,
                               const std::vector<std::pair<std::string, const HoverResult*>>& rows,
                               std::vector<double> HoverResult::*t,
                               std::vector<double> HoverResult::*final_error, int runs) {
  ReportTable table = ReproTable(
      "hover_" + error,
      fmt::format("hover (V-B): {} error, converged below {} {}", error, threshold, unit),
      {"P0", "converged after mean [s]", "converged after median [s]", "converged after max [s]",
       "runs converged", "final mean [" + unit + "]", "final max [" + unit + "]"});
  for (const auto& [label, r] : rows) {
    const auto s = Summary(r->*t);
    const auto f = Summary(r->*final_error);
    table.rows.push_back({label, s["mean"], s["median"], s["max"],
                          fmt::format("{}/{}", s["count"].get<int>(), runs), f["mean"], f["max"]});
  }
  table.rows.push_back({"paper",
                        error == "attitude" ? nlohmann::json("more slowly")
                                            : nlohmann::json(kPaperHoverConvergenceS),
                        nullptr, nullptr, nullptr, nullptr, nullptr});
  return table;
}

// Dynamic flight: peak |error| per quantity after convergence, and the paper's peaks.
ReportTable AprilTagDynamicTable(const nlohmann::json& dynamic) {
  ReportTable table = ReproTable(
      "dynamic",
      fmt::format("dynamic (V-C): peak |error| from {:.1f} s (first tag at {:.1f} s + {} s)",
                  dynamic.at("window_start_s").get<double>(),
                  dynamic.at("first_tag_s").get<double>(), kDynamicSettleS),
      {"estimator", "x [m]", "y [m]", "z [m]", "vx [m/s]", "vy [m/s]", "vz [m/s]", "roll [rad]",
       "pitch [rad]", "yaw [rad]", "final |p err| [m]"});
  // The estimators in the order of their names, as details holds them.
  for (const auto& [label, e] : dynamic.at("estimators").items()) {
    std::vector<nlohmann::json> row = {label};
    for (const auto& name : kDynamicNames) row.push_back(e.at("peak_abs_error").at(name));
    row.push_back(e.at("final_position_error_m"));
    table.rows.push_back(std::move(row));
  }
  table.rows.push_back({"paper (peaks)", kPaperPositionPeakM, kPaperPositionPeakM,
                        kPaperPositionPeakM, kPaperVelocityPeakMs, kPaperVelocityPeakMs,
                        kPaperVelocityPeakMs, kPaperRollPeakRad, kPaperPitchPeakRad, nullptr,
                        nullptr});
  return table;
}

ReportTable AprilTagNeesTable(const AprilTagNees& nees, int runs) {
  ReportTable table = ReproTable("nees",
                                 fmt::format("nees: hover runs, average NEES from {} s against the "
                                             "95 % chi-square band [{:.3f}, {:.3f}] of {} runs",
                                             kNeesStartS, nees.band_lo, nees.band_hi, runs),
                                 {"block", "mean ANEES (dof 3)", "fraction of time in band"});
  for (const auto& [label, block] :
       {std::pair<std::string, const AprilTagNees::Block*>{"position", &nees.position},
        {"velocity", &nees.velocity},
        {"attitude", &nees.attitude}}) {
    const nlohmann::json j = block->Json();
    table.rows.push_back({label, j["mean_anees"], j["fraction_in_band"]});
  }
  return table;
}

nlohmann::json HoverResultJson(const HoverResult& r, double p0_scale) {
  return {{"p0_scale", p0_scale},
          {"position", {{"convergence_s", Summary(r.t_pos)}, {"final_m", Summary(r.final_pos)}}},
          {"velocity", {{"convergence_s", Summary(r.t_vel)}, {"final_m_s", Summary(r.final_vel)}}},
          {"attitude", {{"convergence_s", Summary(r.t_att)}, {"final_rad", Summary(r.final_att)}}}};
}

std::string AprilTagSetup(const AprilTagSettings& settings, const ReproRuns& runs,
                          const nlohmann::json& dynamic_result, const HoverResult& hover,
                          const ImageStats& hover_images, const ImageStats& dynamic_images) {
  std::string md = fmt::format(
      "Seeds {}, {} hover runs. Tag measurements: {}. Processing delay {} s (compensated as in "
      "Fig. 3-4 unless stated).\n\n",
      runs.Seeds(), runs.runs,
      settings.from_images ? "rendered images -> libapriltag -> per-tag PnP"
                           : "projected corners + noise",
      dynamic_result.at("processing_delay_s").get<std::string>());
  const auto per_frame_ms = [](const ImageStats& s, double seconds) {
    return TagNumber(s.frames ? 1e3 * seconds / s.frames : kNaN, 1);
  };
  if (settings.from_images)
    md += fmt::format(
        "Rendering and detection took {} and {} ms per frame on the hover, {} and {} ms on the "
        "dynamic flight.\n\n",
        per_frame_ms(hover_images, hover_images.render_s),
        per_frame_ms(hover_images, hover_images.detect_s),
        per_frame_ms(dynamic_images, dynamic_images.render_s),
        per_frame_ms(dynamic_images, dynamic_images.detect_s));
  md += fmt::format(
      "**hover (V-B)**: Monte-Carlo over the filter's initial state. Mean initial position error "
      "{} m (paper: about 0.5 m). Convergence time: from then on the error stays below the "
      "threshold (position and velocity: norm of the error vector; attitude: largest of |roll|, "
      "|pitch|, |yaw| errors); final: mean over the last second. Paper: position and velocity "
      "converge in about 2 s, attitude more slowly. \"P0 matched\": the initial covariance is "
      "the spread the initial errors are drawn from; \"P0 x0.1\": standard deviations ten times "
      "too small, innovation gate off (the paper states neither P0 nor a gate).\n\n",
      TagNumber(Summary(hover.initial_pos)["mean"].get<double>(), 3));
  md +=
      "**dynamic (V-C)**: filter started at zero, truth at (0, 0, 0.08) m. The last column is the "
      "position error at the end of the flight (drift without tags).\n\n"
      "**nees**: for N runs and 3 degrees of freedom the average NEES lies in the 95 % band with "
      "95 % probability when the filter is consistent.\n";
  return md;
}

Report SummarizeAprilTag(const ReproRuns& runs) {
  const AprilTagSettings settings = ParseAprilTagSettings(runs.settings);
  const bool from_images = settings.from_images;
  const nlohmann::json& dynamic_result = runs.results.at(0).at(0);
  const std::vector<nlohmann::json>& hover_runs = runs.results.at(1);
  const ImageStats image_stats =
      from_images ? FromExactJson<ImageStats>(hover_runs.at(0).at("images")) : ImageStats{};
  const ImageStats dynamic_image_stats =
      from_images ? FromExactJson<ImageStats>(dynamic_result.at("images")) : ImageStats{};
  HoverResult hover, hover_confident;
  std::vector<HoverSamples> hover_errors;
  for (const auto& run : hover_runs) {
    AddHoverRun(run.at("p0_matched"), &hover);
    AddHoverRun(run.at("p0_confident"), &hover_confident);
    hover_errors.push_back(HoverSamplesFromJson(run.at("p0_matched").at("samples")));
  }
  size_t steps = hover_errors.front().t_s.size();
  for (const auto& run : hover_errors) steps = std::min(steps, run.t_s.size());
  const AprilTagNees nees = HoverNees(hover_errors, steps);

  nlohmann::json dynamic_json = dynamic_result.at("dynamic");
  dynamic_json["paper"] = {{"position_peak_m", kPaperPositionPeakM},
                           {"velocity_peak_m_s", kPaperVelocityPeakMs},
                           {"roll_peak_rad", kPaperRollPeakRad},
                           {"pitch_peak_rad", kPaperPitchPeakRad}};

  Report report;
  report.title = "AprilTag paper (de Almeida Barbosa et al.): reproduction";
  report.provenance.input = "tag-arena-hover, tag-arena-dynamic";
  if (from_images) report.tables.push_back(AprilTagImagesTable(image_stats, dynamic_image_stats));
  const std::vector<std::pair<std::string, const HoverResult*>> p0 = {
      {"P0 matched", &hover}, {"P0 x0.1, no gate", &hover_confident}};
  using Samples = std::vector<double> HoverResult::*;
  for (const auto& [error, unit, threshold, t, final_error] :
       {std::tuple<std::string, std::string, double, Samples, Samples>{
            "position", "m", kConvergedPositionM, &HoverResult::t_pos, &HoverResult::final_pos},
        {"velocity", "m/s", kConvergedVelocityMs, &HoverResult::t_vel, &HoverResult::final_vel},
        {"attitude", "rad", kConvergedAttitudeRad, &HoverResult::t_att, &HoverResult::final_att}})
    report.tables.push_back(
        AprilTagHoverTable(error, unit, threshold, p0, t, final_error, runs.runs));
  report.tables.push_back(AprilTagDynamicTable(dynamic_json));
  report.tables.push_back(AprilTagNeesTable(nees, runs.runs));
  report.sections.push_back({"Setup", AprilTagSetup(settings, runs, dynamic_result, hover,
                                                    image_stats, dynamic_image_stats)});
  report.sections.back().before_tables = true;
  report.files["hover_envelope.csv"] = HoverEnvelopeCsv(hover_errors, steps);
  report.files["dynamic_errors.csv"] = dynamic_result.at("csv").get<std::string>();
  report.files["nees.csv"] = nees.csv;

  const nlohmann::json hover_json = {
      {"runs", runs.runs},
      {"duration_s", settings.hover_s},
      {"initial_position_error_m", Summary(hover.initial_pos)},
      {"thresholds",
       {{"position_m", kConvergedPositionM},
        {"velocity_m_s", kConvergedVelocityMs},
        {"attitude_rad", kConvergedAttitudeRad}}},
      {"paper", {{"convergence_s", kPaperHoverConvergenceS}, {"initial_position_error_m", 0.5}}},
      {"p0_matched", HoverResultJson(hover, 1.0)},
      {"p0_confident", HoverResultJson(hover_confident, 0.1)}};
  const nlohmann::json nees_json = {{"runs", runs.runs},
                                    {"from_s", kNeesStartS},
                                    {"band_95", {nees.band_lo, nees.band_hi}},
                                    {"position", nees.position.Json()},
                                    {"velocity", nees.velocity.Json()},
                                    {"attitude", nees.attitude.Json()}};
  const nlohmann::json images = {
      {"hover", ImageStatsJson(image_stats, from_images)},
      {"dynamic", ImageStatsJson(dynamic_image_stats, from_images)},
      {"detections", image_stats.detections + dynamic_image_stats.detections}};
  report.details = {{"hover_images_seed", *settings.hover_images_seed},
                    {"tables",
                     {{"images", images},
                      {"hover", hover_json},
                      {"dynamic", dynamic_json},
                      {"nees", nees_json}}}};
  return report;
}

// Units: (dynamic, first seed), then (hover, seed) for every seed; the dynamic flight (the
// longest unit) goes first. The hover images' seed travels with the settings, so that every unit
// (here or in a worker) renders the same hover.
ReproPlan PlanAprilTag(const ReproSettings& settings, uint64_t first_seed) {
  const AprilTagSettings parsed = ParseAprilTagSettings(settings);
  ReproPlan plan{{{kDynamicUnit, 1}, {kHoverUnit}}, settings};
  if (!parsed.hover_images_seed) plan.settings["hover_images_seed"] = std::to_string(first_seed);
  return plan;
}

}  // namespace

ReproDefinition AprilTagRepro() {
  return {
      .name = "apriltag",
      .description = "AprilTag paper V: render -> detect -> EKF; hover Monte-Carlo, dynamic, NEES",
      .paper =
          "de Almeida Barbosa, Dias, dos Santos: A Visual-Inertial Navigation System "
          "Using AprilTag for Real-Time MAV Applications",
      .default_runs = kAprilTagDefaultRuns,
      .plan = PlanAprilTag,
      .unit = AprilTagUnitResult,
      .summarize = SummarizeAprilTag};
}

}  // namespace mavloc
