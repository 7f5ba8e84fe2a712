#include "datasets/io/aprilgrid_log_import.h"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>

#include "core/errors.h"
#include "core/rotation.h"
#include "core/stamp_rate.h"
#include "datasets/io/aprilgrid_target_io.h"
#include "datasets/io/calibration_io.h"
#include "datasets/io/euroc_io.h"

namespace fs = std::filesystem;

namespace mavloc {

namespace {

// The highest camera index a dataset can carry tags for (tags0, tags1).
constexpr int kMaxCameraIndex = 1;

enum class Provides { kEverything, kTarget, kIntrinsics, kExtrinsics, kImuNoise };

struct Source {
  Provides provides;
  CalibrationSource calibration;
};

bool Takes(const Source& s, Provides item) {
  return s.provides == Provides::kEverything || s.provides == item;
}

// Sources in the order they are consulted: specific ones first, then the general configs.
std::vector<Source> ReadSources(const AprilgridLogInputs& inputs) {
  std::vector<Source> sources;
  auto add = [&](const std::vector<std::string>& specs, Provides provides, bool prefix_allowed) {
    for (const std::string& spec : specs) {
      auto [camera, path] = SplitCameraPrefix(spec);
      if (camera && !prefix_allowed) {
        camera.reset();
        path = spec;
      }
      sources.push_back({provides, ReadCalibrationSource(path, camera)});
    }
  };
  add(inputs.target, Provides::kTarget, false);
  add(inputs.intrinsics, Provides::kIntrinsics, true);
  add(inputs.extrinsics, Provides::kExtrinsics, true);
  add(inputs.imu_noise, Provides::kImuNoise, false);
  add(inputs.configs, Provides::kEverything, true);
  return sources;
}

// The median-interval rate (core/stamp_rate.h) rounded to 0.001 Hz, as written into sensor.yaml.
double RateFromStamps(const std::vector<TimeNs>& t_ns) {
  return std::round(MedianRateHz(t_ns) * 1000.0) / 1000.0;
}

std::string PoseDifference(const Pose& a, const Pose& b) {
  return fmt::format("{:.3f} mm, {:.5f} deg", 1e3 * (a.p - b.p).norm(),
                     RotationAngleBetween(a.q, b.q) / kDeg);
}

}  // namespace

AprilgridLogImport ImportAprilgridLog(const AprilgridLogInputs& inputs) {
  AprilgridLogImport result;
  if (inputs.imu_csv.empty()) throw InputError("an IMU CSV is needed (--imu FILE)");
  if (inputs.corners.empty())
    throw InputError("at least one corner folder is needed (--corners camN=FOLDER)");

  // Corner folders by camera index.
  std::map<int, std::string> corner_folders;
  for (const std::string& spec : inputs.corners) {
    const auto [camera, folder] = SplitCameraPrefix(spec);
    const int index = camera.value_or(0);
    if (index > kMaxCameraIndex)
      throw InputError(folder, 0, "",
                       fmt::format("cam{}: a dataset carries tags of cam0 and cam1 only (tags0, "
                                   "tags1)",
                                   index));
    if (corner_folders.count(index))
      throw InputError(
          folder, 0, "",
          fmt::format("cam{} has two corner folders (also {})", index, corner_folders[index]));
    corner_folders[index] = folder;
  }

  const std::vector<Source> sources = ReadSources(inputs);
  auto where = [&](Provides item) {
    std::string names;
    for (const Source& s : sources)
      if (Takes(s, item)) names += (names.empty() ? "" : ", ") + s.calibration.path;
    return names.empty() ? std::string("no source given") : "sources: " + names;
  };

  // The target.
  std::string target_from;
  for (const Source& s : sources) {
    if (Takes(s, Provides::kTarget) && s.calibration.target) {
      result.target = *s.calibration.target;
      target_from = s.calibration.path;
      break;
    }
  }
  if (target_from.empty())
    throw InputError("no aprilgrid description (" + where(Provides::kTarget) +
                     "): give --target target.yaml (Kalibr) or a --config with calib_target (yac)");
  result.notes.push_back(fmt::format(
      "target: {}x{} aprilgrid, tag {} m, spacing {} (from {})", result.target.tag_rows,
      result.target.tag_cols, result.target.tag_size_m, result.target.tag_spacing, target_from));

  // The IMU.
  Dataset& d = result.dataset;
  d.imu.name = "imu0";
  d.imu.samples = ReadImuCsv(inputs.imu_csv);
  for (const Source& s : sources) {
    if (Takes(s, Provides::kImuNoise) && s.calibration.imu) {
      d.imu.noise = s.calibration.imu->noise;
      if (s.calibration.imu->rate_hz) d.imu.rate_hz = *s.calibration.imu->rate_hz;
      result.imu_noise_from = s.calibration.imu->from;
      break;
    }
  }
  if (result.imu_noise_from.empty())
    throw InputError(inputs.imu_csv, 0, "",
                     "no IMU noise densities (" + where(Provides::kImuNoise) +
                         "): give --imu-noise with Kalibr's imu.yaml / EuRoC's imu0 sensor.yaml "
                         "or a --config with yac's imu0 sigma_g_c, sigma_a_c, sigma_gw_c, "
                         "sigma_aw_c");
  std::vector<TimeNs> imu_t;
  imu_t.reserve(d.imu.samples.size());
  for (const auto& s : d.imu.samples) imu_t.push_back(s.t_ns);
  const double measured_imu_rate = RateFromStamps(imu_t);
  if (d.imu.rate_hz <= 0.0) d.imu.rate_hz = measured_imu_rate;
  result.notes.push_back(
      fmt::format("imu0: {} samples, {:.3f} s, {} Hz ({} Hz measured); noise from {}",
                  d.imu.samples.size(), NsToSeconds(imu_t.back() - imu_t.front()), d.imu.rate_hz,
                  measured_imu_rate, result.imu_noise_from));

  // What the sources say about each camera, first source first.
  const int last_camera = corner_folders.rbegin()->first;
  auto first = [&](int camera, Provides item, auto member) -> const CameraCalibration* {
    for (const Source& s : sources) {
      if (!Takes(s, item)) continue;
      const auto it = s.calibration.cameras.find(camera);
      if (it != s.calibration.cameras.end() && (it->second.*member)) return &it->second;
    }
    return nullptr;
  };
  std::map<int, const CameraCalibration*> direct_T_B_C, relative_T_C0_C;
  for (int n = 0; n <= last_camera; ++n) {
    direct_T_B_C[n] = first(n, Provides::kExtrinsics, &CameraCalibration::T_B_C);
    relative_T_C0_C[n] = first(n, Provides::kExtrinsics, &CameraCalibration::T_C0_C);
  }

  for (int n = 0; n <= last_camera; ++n) {
    AprilgridLogCamera report;
    report.name = fmt::format("cam{}", n);
    CameraSensor camera;
    camera.name = report.name;
    const auto folder = corner_folders.find(n);
    const CameraCalibration* model = first(n, Provides::kIntrinsics, &CameraCalibration::model);
    if (!model) {
      const std::string why =
          folder != corner_folders.end()
              ? "has corners but no intrinsics"
              : fmt::format(
                    "has no intrinsics (it is written, without frames, so that cam{} "
                    "keeps index {})",
                    last_camera, last_camera);
      throw InputError(folder != corner_folders.end() ? folder->second : report.name, 0, "",
                       fmt::format("{} {} ({}): give --intrinsics or a --config describing {}",
                                   report.name, why, where(Provides::kIntrinsics), report.name));
    }
    camera.model = *model->model;
    report.intrinsics_from = model->model_from;

    // T_B_C, in the order the header states.
    const CameraCalibration* direct = direct_T_B_C[n];
    const CameraCalibration* relative = relative_T_C0_C[n];
    if (direct) {
      camera.T_B_C = *direct->T_B_C;
      report.T_B_C_from = direct->T_B_C_from;
      report.T_B_C_known = true;
    } else if (n > 0 && relative && direct_T_B_C[0]) {
      camera.T_B_C = *direct_T_B_C[0]->T_B_C * *relative->T_C0_C;
      report.T_B_C_from = direct_T_B_C[0]->T_B_C_from + " composed with " + relative->T_C0_C_from;
      report.T_B_C_known = true;
    } else if (n > 0 && relative) {
      camera.T_B_C = *relative->T_C0_C;
      report.T_B_C_from = relative->T_C0_C_from + ", with B guessed at cam0";
      result.notes.push_back(fmt::format(
          "{}: T_B_C unknown; written as its pose in cam0 (B guessed at cam0, a coarse guess)",
          report.name));
    } else {
      camera.T_B_C = Pose();
      report.T_B_C_from = "unknown: identity (a coarse guess)";
      result.notes.push_back(
          fmt::format("{}: T_B_C unknown ({}); identity written (a coarse guess)", report.name,
                      where(Provides::kExtrinsics)));
    }
    // Two calibrations of the stereo pair: say how far apart they are.
    if (n > 0 && direct && direct_T_B_C[0] && relative) {
      const Pose from_body = direct_T_B_C[0]->T_B_C->Inverse() * *direct->T_B_C;
      result.notes.push_back(fmt::format("{}: pose in cam0 from the two T_B_C vs {}: {} apart",
                                         report.name, relative->T_C0_C_from,
                                         PoseDifference(from_body, *relative->T_C0_C)));
    }

    if (folder != corner_folders.end()) {
      report.corners_folder = folder->second;
      AprilgridCornerFileOptions options;
      options.camera = n;
      options.image_size = Eigen::Vector2i(camera.model.width(), camera.model.height());
      AprilgridCornerLog log = ReadAprilgridCornerFolder(folder->second, result.target, options);
      report.stats = log.stats;
      camera.frames.reserve(log.frames_ns.size());
      for (TimeNs t : log.frames_ns) camera.frames.push_back({t, ""});
      const auto inside = std::count_if(log.frames_ns.begin(), log.frames_ns.end(), [&](TimeNs t) {
        return t >= imu_t.front() && t <= imu_t.back();
      });
      if (inside == 0)
        throw InputError(folder->second, 0, "",
                         fmt::format("no frame ({} .. {}) lies within the IMU's time range "
                                     "({} .. {} of {})",
                                     log.frames_ns.front(), log.frames_ns.back(), imu_t.front(),
                                     imu_t.back(), inputs.imu_csv));
      if (inside < static_cast<long>(log.frames_ns.size()))
        result.notes.push_back(fmt::format("{}: {} of {} frames lie outside the IMU's time range",
                                           report.name, log.frames_ns.size() - inside,
                                           log.frames_ns.size()));
      const double measured_rate = RateFromStamps(log.frames_ns);
      const CameraCalibration* rate = first(n, Provides::kIntrinsics, &CameraCalibration::rate_hz);
      camera.rate_hz = rate ? *rate->rate_hz : measured_rate;
      (n == 0 ? d.tags : d.tags1) = std::move(log.tags);
    } else {
      const CameraCalibration* rate = first(n, Provides::kIntrinsics, &CameraCalibration::rate_hz);
      camera.rate_hz = rate ? *rate->rate_hz : 0.0;
      result.notes.push_back(fmt::format(
          "{}: no corners; written (calibration only) to keep camera indices", report.name));
    }
    result.notes.push_back(fmt::format("{}: intrinsics from {}; T_B_C from {}", report.name,
                                       report.intrinsics_from, report.T_B_C_from));
    d.cameras.push_back(std::move(camera));
    result.cameras.push_back(report);
  }

  d.map.frame = MapFrame::kBoard;
  d.map.tags = AprilgridTags(result.target);
  d.map.parameters = AprilgridMapParameters(result.target);
  return result;
}

std::string AprilgridLogImport::ImportYaml() const {
  YAML::Emitter out;
  out.SetDoublePrecision(15);
  out << YAML::Comment("mavloc import-aprilgrid: where this dataset came from") << YAML::BeginMap;
  out << YAML::Key << "target" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key
      << "tag_rows" << YAML::Value << target.tag_rows << YAML::Key << "tag_cols" << YAML::Value
      << target.tag_cols << YAML::Key << "tag_size" << YAML::Value << target.tag_size_m << YAML::Key
      << "tag_spacing" << YAML::Value << target.tag_spacing << YAML::EndMap;
  out << YAML::Key << "imu_noise_from" << YAML::Value << imu_noise_from;
  out << YAML::Key << "cameras" << YAML::Value << YAML::BeginMap;
  for (const AprilgridLogCamera& c : cameras) {
    out << YAML::Key << c.name << YAML::Value << YAML::BeginMap;
    out << YAML::Key << "corners" << YAML::Value << c.corners_folder;
    out << YAML::Key << "frames" << YAML::Value << c.stats.frames;
    out << YAML::Key << "empty_frames" << YAML::Value << c.stats.empty_frames;
    out << YAML::Key << "tags" << YAML::Value << c.stats.tags;
    out << YAML::Key << "corners_read" << YAML::Value << c.stats.corners;
    out << YAML::Key << "incomplete_tags_skipped" << YAML::Value << c.stats.incomplete_tags;
    out << YAML::Key << "intrinsics_from" << YAML::Value << c.intrinsics_from;
    out << YAML::Key << "T_B_C_from" << YAML::Value << c.T_B_C_from;
    out << YAML::Key << "T_B_C_known" << YAML::Value << c.T_B_C_known;
    out << YAML::EndMap;
  }
  out << YAML::EndMap;
  out << YAML::Key << "notes" << YAML::Value << YAML::BeginSeq;
  for (const std::string& note : notes) out << note;
  out << YAML::EndSeq << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

}  // namespace mavloc
