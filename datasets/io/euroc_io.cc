#include "datasets/io/euroc_io.h"

#include <fmt/format.h>
#include <unistd.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <sstream>

#include "core/atomic_file.h"
#include "core/errors.h"
#include "core/interrupt.h"
#include "core/number_text.h"
#include "core/physical_limits.h"
#include "core/rotation.h"
#include "datasets/io/calibration_io.h"
#include "datasets/io/text_table.h"
#include "datasets/io/tum_io.h"
#include "datasets/io/yaml_util.h"

namespace fs = std::filesystem;

namespace mavloc {

namespace {

// Stream file names inside <root>/mav0 (DESIGN.md).
constexpr const char* kImu = "imu0";
constexpr const char* kGroundTruth = "state_groundtruth_estimate0";
constexpr const char* kFeatures = "features0";
constexpr const char* kFeatures1 = "features1";
constexpr const char* kLaser = "laser0";
constexpr const char* kTags = "tags0";
constexpr const char* kTags1 = "tags1";
constexpr const char* kTruthQuantities = "truth_quantities0";

std::vector<TimeNs> Stamps(const TextTable& table, std::vector<long>* lines) {
  std::vector<TimeNs> t;
  for (const auto& row : table.rows) {
    t.push_back(table.TimestampNs(row, 0));
    lines->push_back(row.line);
  }
  return t;
}

// rate_hz: 0 means "not stated" (mavloc writes it for imported logs whose rate is unknown).
double RateHz(const YAML::Node& yaml, const std::string& path) {
  return YamlDoubleIn(yaml, "rate_hz", path, 0.0, limits::kMaxRate_hz, "Hz");
}

// An image size in whole pixels, [1, limits::kMaxResolution_px].
int ResolutionPx(const YAML::Node& yaml, double value, const char* which, const std::string& path) {
  if (!(value >= 1.0 && value <= limits::kMaxResolution_px && value == std::floor(value)))
    throw InputError(path, YamlLine(yaml["resolution"]), "resolution",
                     fmt::format("{} {:g} is not a whole number of pixels in [1, {}]", which, value,
                                 limits::kMaxResolution_px));
  return static_cast<int>(value);
}

ImuSensor ReadImu(const fs::path& folder) {
  ImuSensor imu;
  imu.name = folder.filename().string();
  const std::string yaml_path = (folder / "sensor.yaml").string();
  if (fs::exists(yaml_path)) {
    const YAML::Node yaml = LoadYamlMap(yaml_path);
    if (yaml["T_BS"]) imu.T_B_S = YamlRigidTransform(yaml, "T_BS", yaml_path);
    if (yaml["rate_hz"]) imu.rate_hz = RateHz(yaml, yaml_path);
    auto optional = [&](const char* key, double max, const char* unit, double* out) {
      if (yaml[key]) *out = YamlDoubleIn(yaml, key, yaml_path, 0.0, max, unit);
    };
    using limits::kMaxAccelNoise, limits::kMaxGyroNoise;
    optional("gyroscope_noise_density", kMaxGyroNoise, "rad/s/sqrt(Hz)",
             &imu.noise.gyroscope_noise_density);
    optional("gyroscope_random_walk", kMaxGyroNoise, "rad/s^2/sqrt(Hz)",
             &imu.noise.gyroscope_random_walk);
    optional("accelerometer_noise_density", kMaxAccelNoise, "m/s^2/sqrt(Hz)",
             &imu.noise.accelerometer_noise_density);
    optional("accelerometer_random_walk", kMaxAccelNoise, "m/s^3/sqrt(Hz)",
             &imu.noise.accelerometer_random_walk);
    auto optional_sigma = [&](const char* key, double max, const char* unit,
                              std::optional<double>* out) {
      if (yaml[key]) *out = YamlDoubleIn(yaml, key, yaml_path, 0.0, max, unit);
    };
    optional_sigma("gyroscope_bias_sigma", limits::kMaxGyroBias_rad_s, "rad/s",
                   &imu.gyroscope_bias_sigma);
    optional_sigma("accelerometer_bias_sigma", limits::kMaxAccelBias_m_s2, "m/s^2",
                   &imu.accelerometer_bias_sigma);
  }
  imu.samples = ReadImuCsv((folder / "data.csv").string());
  return imu;
}

// An image of cam*/data.csv is a file of cam*/data/: a plain name, so that no row reaches outside
// the dataset ("../../etc/passwd", "/etc/passwd") or names the folder itself ("", ".").
void RequirePlainFileName(const TextTable& table, const TextRow& row, size_t k) {
  const std::string& name = row.fields[k];
  const std::string shown = PrintableMessage(name, 200);  // what() would end at a NUL byte
  std::string why;
  if (name.empty())
    why = "empty image file name";
  else if (name == "." || name == "..")
    why = "'" + name + "' is a folder, not an image file name";
  else if (name.find_first_of(std::string("/\\\0", 3)) != std::string::npos)
    why = "'" + shown +
          "' is not a plain file name (no '/', '\\' or NUL byte: images are files of "
          "the camera's data/ folder)";
  if (!why.empty()) throw InputError(table.path, row.line, table.FieldName(k), why);
}

CameraSensor ReadCamera(const fs::path& folder) {
  CameraSensor camera;
  camera.name = folder.filename().string();
  const std::string yaml_path = (folder / "sensor.yaml").string();
  const YAML::Node yaml = LoadYamlMap(yaml_path);
  camera.T_B_C = YamlRigidTransform(yaml, "T_BS", yaml_path);
  if (yaml["rate_hz"]) camera.rate_hz = RateHz(yaml, yaml_path);
  const auto resolution = YamlDoubles(yaml, "resolution", yaml_path, 2);
  const int width_px = ResolutionPx(yaml, resolution[0], "width", yaml_path);
  const int height_px = ResolutionPx(yaml, resolution[1], "height", yaml_path);
  const auto intrinsics = YamlDoubles(yaml, "intrinsics", yaml_path, 4);
  CheckIntrinsicsRange(yaml, "intrinsics", "intrinsics", yaml_path, intrinsics);
  if (yaml["camera_model"] && YamlString(yaml, "camera_model", yaml_path) != "pinhole")
    throw InputError(yaml_path, YamlLine(yaml["camera_model"]), "camera_model",
                     "only 'pinhole' is supported");
  DistortionModel model = DistortionModel::kNone;
  std::array<double, 4> coefficients{0, 0, 0, 0};
  if (yaml["distortion_model"]) {
    const std::string name = YamlString(yaml, "distortion_model", yaml_path);
    const auto parsed = ParseDistortionModel(name);
    if (!parsed)
      throw InputError(yaml_path, YamlLine(yaml["distortion_model"]), "distortion_model",
                       "unknown model '" + name + "' (radial-tangential, equidistant or none)");
    model = *parsed;
    if (model != DistortionModel::kNone) {
      const auto k = YamlDoubles(yaml, "distortion_coefficients", yaml_path);
      // Exactly 4: a fifth coefficient (k3 of OpenCV's 5-term radial-tangential model) has no
      // place in the models mavloc supports, and dropping it would change the projection.
      if (k.size() != 4)
        throw InputError(
            yaml_path, YamlLine(yaml["distortion_coefficients"]), "distortion_coefficients",
            fmt::format("expected 4 values ({}), got {}",
                        model == DistortionModel::kEquidistant ? "k1 k2 k3 k4" : "k1 k2 p1 p2",
                        k.size()));
      CheckDistortionRange(yaml, "distortion_coefficients", "distortion_coefficients", yaml_path,
                           k);
      std::copy_n(k.begin(), 4, coefficients.begin());
    }
  }
  camera.model =
      CameraModel(width_px, height_px,
                  Eigen::Vector4d(intrinsics[0], intrinsics[1], intrinsics[2], intrinsics[3]),
                  model, coefficients);
  const std::string csv = (folder / "data.csv").string();
  if (!fs::exists(csv)) return camera;  // calibration only
  const TextTable table = ReadTextTable(csv, Separator::kComma, /*allow_empty=*/true);
  std::vector<long> lines;
  const std::vector<TimeNs> t = Stamps(table, &lines);
  table.RequireIncreasing(t, lines);
  for (size_t i = 0; i < table.rows.size(); ++i) {
    table.RequireFields(table.rows[i], 2);
    RequirePlainFileName(table, table.rows[i], 1);
    const fs::path image = folder / "data" / table.rows[i].fields[1];
    camera.frames.push_back({t[i], image.string()});
    std::error_code error;  // a name the file system cannot hold (too long) is missing, not fatal
    if (!fs::exists(image, error)) camera.missing_images.push_back(image.string());
  }
  return camera;
}

// Fields k and k+1 of a row, each within +-max_abs.
Eigen::Vector2d Vector2In(const TextTable& table, const TextRow& row, size_t k, double max_abs,
                          const char* unit) {
  return {table.NumberIn(row, k, -max_abs, max_abs, unit),
          table.NumberIn(row, k + 1, -max_abs, max_abs, unit)};
}

// Streamed row by row, as the features (an hour at 200 Hz is 720,000 rows of 17 fields).
std::vector<GroundTruthState> ReadGroundTruthCsv(const std::string& path) {
  TextRowReader reader(path, Separator::kComma);
  TextTable columns;  // the header and path, for the messages
  columns.path = path;
  std::vector<GroundTruthState> states;
  while (const TextRowView* row = reader.Next()) {
    if (states.empty()) columns.header = reader.header();
    const long line = row->line;
    const TimeNs t_ns = columns.TimestampNsText(row->fields[0], line, 0);
    if (!states.empty()) columns.RequireAfter(states.back().t_ns, t_ns, line);
    columns.RequireFieldCount(row->fields.size(), line, 8);
    const auto number = [&](size_t k, double max_abs, const char* unit) {
      return columns.NumberInText(row->fields[k], line, k, -max_abs, max_abs, unit);
    };
    const auto vector3 = [&](size_t k, double max_abs, const char* unit) {
      return Eigen::Vector3d(number(k, max_abs, unit), number(k + 1, max_abs, unit),
                             number(k + 2, max_abs, unit));
    };
    const auto plain = [&](size_t k) {
      return RequireDoubleText(row->fields[k], path, line, columns.FieldName(k));
    };
    GroundTruthState s;
    s.t_ns = t_ns;
    s.T_W_B.p = vector3(1, limits::kMaxPosition_m, "m");
    const Eigen::Quaterniond q = QuaternionFromWxyz(plain(4), plain(5), plain(6), plain(7));
    if (!(std::abs(q.norm() - 1.0) <= limits::kUnitNormTolerance))
      throw InputError(path, line, columns.FieldName(4),
                       fmt::format("quaternion is not unit length (|q| = {:.6g}; accepted and "
                                   "normalised within 1 +- {})",
                                   q.norm(), limits::kUnitNormTolerance));
    s.T_W_B.q = q.normalized();
    // Pose-only rows (8 fields) leave v_W and the biases zero; IMU estimators that need the
    // initial velocity detect that (imu-dead-reckoning says so).
    if (row->fields.size() > 8) {
      columns.RequireFieldCount(row->fields.size(), line, 17);
      s.v_W = vector3(8, limits::kMaxSpeed_m_s, "m/s");
      s.b_g = vector3(11, limits::kMaxGyroBias_rad_s, "rad/s");
      s.b_a = vector3(14, limits::kMaxAccelBias_m_s2, "m/s^2");
    }
    states.push_back(s);
  }
  if (states.empty()) throw InputError(path, 0, "", "file has no data rows");
  return states;
}

// Observation streams are time-ordered; several rows may share a stamp (one per landmark/tag), but
// a stamp never goes back.
void RequireNonDecreasing(const TextTable& table, const std::vector<TimeNs>& t,
                          const std::vector<long>& lines) {
  for (size_t i = 1; i < t.size(); ++i) table.RequireNotBefore(t[i - 1], t[i], lines[i]);
}

// Streamed row by row (an hour of features at 20 Hz is millions of rows: held as text they took
// about ten times the memory of the observations).
std::vector<FeatureObservation> ReadFeatures(const std::string& path, int camera,
                                             std::vector<long>* lines_out) {
  TextRowReader reader(path, Separator::kComma);
  TextTable columns;  // the header and path, for the messages
  columns.path = path;
  std::vector<long>& lines = *lines_out;
  std::vector<FeatureObservation> out;
  const double max_xy = limits::kMaxNormalizedCoordinate;
  while (const TextRowView* row = reader.Next()) {
    if (out.empty()) columns.header = reader.header();
    const TimeNs t_ns = columns.TimestampNsText(row->fields[0], row->line, 0);
    if (!out.empty()) columns.RequireNotBefore(out.back().t_ns, t_ns, row->line);
    columns.RequireFieldCount(row->fields.size(), row->line, 4);
    out.push_back({t_ns,
                   columns.IdText(row->fields[1], row->line, 1),
                   {columns.NumberInText(row->fields[2], row->line, 2, -max_xy, max_xy, ""),
                    columns.NumberInText(row->fields[3], row->line, 3, -max_xy, max_xy, "")},
                   camera});
    lines.push_back(row->line);
  }
  return out;
}

std::vector<LaserObservation> ReadLaser(const std::string& path) {
  const TextTable table = ReadTextTable(path, Separator::kComma, true);
  std::vector<long> lines;
  const auto t = Stamps(table, &lines);
  table.RequireIncreasing(t, lines);
  std::vector<LaserObservation> out;
  for (size_t i = 0; i < table.rows.size(); ++i) {
    table.RequireFields(table.rows[i], 3);
    out.push_back({t[i], Vector2In(table, table.rows[i], 1, limits::kMaxNormalizedCoordinate, "")});
  }
  return out;
}

std::vector<TagObservation> ReadTags(const std::string& path, int camera,
                                     std::vector<long>* lines_out) {
  const TextTable table = ReadTextTable(path, Separator::kComma, true);
  std::vector<long>& lines = *lines_out;
  const auto t = Stamps(table, &lines);
  RequireNonDecreasing(table, t, lines);
  std::vector<TagObservation> out;
  for (size_t i = 0; i < table.rows.size(); ++i) {
    const TextRow& row = table.rows[i];
    table.RequireFields(row, 10);
    TagObservation obs;
    obs.t_ns = t[i];
    obs.camera = camera;
    obs.tag_id = table.Id(row, 1);
    for (int k = 0; k < 4; ++k)
      obs.corners_px[k] = Vector2In(table, row, 2 + 2 * k, limits::kMaxPixelCoordinate, "px");
    out.push_back(obs);
  }
  return out;
}

// Header fields "name [unit]" -> name, unit.
QuantityTable ReadTruthQuantities(const std::string& path) {
  const TextTable table = ReadTextTable(path, Separator::kComma, true);
  // The header names the quantities: without it the columns mean nothing, so a missing or short
  // header is an error rather than a silently dropped file.
  if (table.header.size() < 2)
    throw InputError(path, 1, "header",
                     "missing: the first line must name the columns, e.g. '#timestamp [ns],d [m]'");
  std::vector<std::string> names, units;
  for (size_t k = 1; k < table.header.size(); ++k) {
    const std::string& field = table.header[k];
    const auto open = field.find('[');
    const auto close = field.find(']');
    std::string name = field.substr(0, open);
    while (!name.empty() && name.back() == ' ') name.pop_back();
    if (name.empty())
      throw InputError(path, 1, "column " + std::to_string(k + 1),
                       fmt::format("header column {} has no quantity name ('{}'); every column "
                                   "after the timestamp names one, e.g. 'd [m]'",
                                   k + 1, field));
    if (std::find(names.begin(), names.end(), name) != names.end())
      throw InputError(path, 1, table.FieldName(k),
                       "quantity '" + name + "' is named twice in the header");
    names.push_back(name);
    units.push_back(open != std::string::npos && close != std::string::npos
                        ? field.substr(open + 1, close - open - 1)
                        : StandardUnit(name));
  }
  QuantityTable quantities(names, units);
  std::vector<long> lines;
  const auto t = Stamps(table, &lines);
  table.RequireIncreasing(t, lines);
  for (size_t i = 0; i < table.rows.size(); ++i) {
    table.RequireFields(table.rows[i], names.size() + 1);
    if (table.rows[i].fields.size() > names.size() + 1)
      throw InputError(path, table.rows[i].line, table.FieldName(names.size() + 1),
                       fmt::format("row has {} fields but the header names {}",
                                   table.rows[i].fields.size(), names.size() + 1));
    std::vector<double> values;
    for (size_t k = 0; k < names.size(); ++k)
      values.push_back(table.NumberIn(table.rows[i], k + 1, -limits::kMaxQuantityMagnitude,
                                      limits::kMaxQuantityMagnitude, units[k]));
    quantities.Append(t[i], values);
  }
  return quantities;
}

Eigen::Vector3d Vector3(const YAML::Node& node, const std::string& field, const std::string& path,
                        double max_abs, const char* unit) {
  const auto v = YamlDoubles(node, field, path, 3);
  for (double x : v) {
    if (!(std::abs(x) <= max_abs))
      throw InputError(
          path, YamlLine(node[field]), field,
          fmt::format("{:g} is outside {}", x, limits::RangeText(-max_abs, max_abs, unit)));
  }
  return {v[0], v[1], v[2]};
}

// A unit vector or quaternion written with few decimals: normalised within
// limits::kUnitNormTolerance, refused beyond (a zero quaternion or normal is not a direction).
template <typename Vector>
Vector UnitNormalised(const Vector& v, const YAML::Node& node, const std::string& field,
                      const std::string& path) {
  if (!(std::abs(v.norm() - 1.0) <= limits::kUnitNormTolerance))
    throw InputError(path, YamlLine(node[field]), field,
                     fmt::format("not unit length (norm {:.6g}; accepted and normalised within "
                                 "1 +- {})",
                                 v.norm(), limits::kUnitNormTolerance));
  return v.normalized();
}

// An id of a list item, unique within the list.
int UniqueId(const YAML::Node& item, const std::string& path, const char* list,
             std::map<int, long>* lines_by_id) {
  const int id = static_cast<int>(YamlInteger(item, "id", path, 0, limits::kMaxId));
  const auto [it, inserted] = lines_by_id->emplace(id, YamlLine(item));
  if (!inserted)
    throw InputError(path, YamlLine(item), "id",
                     fmt::format("{} id {} is repeated (first on line {})", list, id, it->second));
  return id;
}

YAML::Node ListItemMap(const YAML::Node& item, const std::string& path, const char* list) {
  if (!item.IsMap())
    throw InputError(path, YamlLine(item), list,
                     "each entry must be a map such as {id: 0, ...}, found a value that is not");
  return item;
}

WorldMap ReadMap(const std::string& path) {
  WorldMap map;
  const YAML::Node yaml = LoadYamlMap(path);
  if (yaml["frame"]) {
    const std::string name = YamlString(yaml, "frame", path);
    if (name == "world") {
      map.frame = MapFrame::kWorld;
    } else if (name == "board") {
      map.frame = MapFrame::kBoard;
    } else {
      throw InputError(path, YamlLine(yaml["frame"]), "frame",
                       "'" + name + "' is not a map frame (world or board)");
    }
  }
  if (yaml["landmarks"]) {
    std::map<int, long> lines_by_id;
    for (const auto& item : YamlListField(yaml, "landmarks", path)) {
      ListItemMap(item, path, "landmarks");
      const int id = UniqueId(item, path, "landmark", &lines_by_id);
      map.landmarks_W[id] = Vector3(item, "p_W", path, limits::kMaxPosition_m, "m");
    }
  }
  if (yaml["tags"]) {
    std::map<int, long> lines_by_id;
    for (const auto& item : YamlListField(yaml, "tags", path)) {
      ListItemMap(item, path, "tags");
      TagInfo tag;
      tag.id = UniqueId(item, path, "tag", &lines_by_id);
      tag.size_m = YamlDoubleIn(item, "size_m", path, 0.0, limits::kMaxTagSize_m, "m");
      if (!(tag.size_m > 0))
        throw InputError(path, YamlLine(item["size_m"]), "size_m", "must be > 0");
      const auto q = YamlDoubles(item, "q_W_T", path, 4);
      tag.T_W_T =
          Pose(UnitNormalised(QuaternionFromWxyz(q[0], q[1], q[2], q[3]), item, "q_W_T", path),
               Vector3(item, "p_W", path, limits::kMaxPosition_m, "m"));
      map.tags[tag.id] = tag;
    }
  }
  if (yaml["plane"]) {
    const YAML::Node plane = YamlMapField(yaml, "plane", path);
    Plane p;
    p.n_W = UnitNormalised(Vector3(plane, "n_W", path, 1.0 + limits::kUnitNormTolerance, ""), plane,
                           "n_W", path);
    p.d_m = YamlDoubleIn(plane, "d_m", path, -limits::kMaxPosition_m, limits::kMaxPosition_m, "m");
    map.plane = p;
  }
  if (yaml["parameters"]) {
    for (const auto& item : YamlMapField(yaml, "parameters", path)) {
      const std::string key = YamlKey(item.first, path, "parameters");
      map.parameters[key] = YamlDouble(yaml["parameters"], key, path);
    }
  }
  return map;
}

// The scenario.yaml values an estimator reads as numbers (the smoother's measurement noise, the
// tag EKF's processing delay), with their ranges: checked here, once, so that "-1", "lots" or
// ".nan" is refused with the line instead of becoming a default or a clamp.
// A value is its leading number; words after it describe it ("1 per bearing angle (...)").
struct ScenarioNumberField {
  const char* key;
  double lo, hi;
  const char* unit;
};
constexpr ScenarioNumberField kScenarioNumberFields[] = {
    {"pixel_noise_px", 0.0, limits::kMaxPixelCoordinate, "px"},
    {"corner_noise_px", 0.0, limits::kMaxPixelCoordinate, "px"},
    {"bearing_noise_deg", 0.0, limits::kMaxAngleNoise_deg, "deg"},
    {"laser_noise_deg", 0.0, limits::kMaxAngleNoise_deg, "deg"},
    {"processing_delay_s", 0.0, limits::kMaxProcessingDelay_s, "s"},
};

void CheckScenarioNumber(const YAML::Node& yaml, const ScenarioNumberField& field,
                         const std::string& text, const std::string& path) {
  const long line = YamlLine(yaml[field.key]);
  const ParsedNumber<double> parsed = ParseDoubleText(FirstWord(text));
  if (!parsed.ok())
    throw InputError(
        path, line, field.key,
        DescribeNumberText(text, parsed, "a finite number") + " (an estimator reads it)");
  const double value = parsed.value;
  if (!(value >= field.lo && value <= field.hi))
    throw InputError(path, line, field.key,
                     fmt::format("{:g} is outside {}", value,
                                 limits::RangeText(field.lo, field.hi, field.unit)));
}

std::map<std::string, std::string> ReadScenarioInfo(const std::string& path) {
  std::map<std::string, std::string> info;
  const YAML::Node yaml = LoadYamlMap(path);
  for (const auto& item : yaml) {
    const std::string key = YamlKey(item.first, path);
    info[key] = YamlString(yaml, key, path);
  }
  for (const auto& field : kScenarioNumberFields)
    if (const auto it = info.find(field.key); it != info.end())
      CheckScenarioNumber(yaml, field, it->second, path);
  return info;
}

// yaml-cpp's own exceptions (a conversion that slipped through the typed helpers) become an
// InputError naming the file and line, never "internal error".
template <typename Function>
auto NamingFile(const std::string& path, Function read) {
  try {
    return read();
  } catch (const YAML::Exception& e) {
    throw InputError(path, e.mark.line >= 0 ? e.mark.line + 1 : 0, "", e.msg);
  }
}

// Features must name landmarks of the map when the map lists landmarks (otherwise the smoother and
// the landmark estimators would drop out of the comparison without a word).
void RequireFeaturesInMap(const Dataset& d, const std::vector<FeatureObservation>& features,
                          const std::string& features_path, const std::vector<long>& lines) {
  if (d.map.landmarks_W.empty()) return;
  for (size_t i = 0; i < features.size(); ++i) {
    if (d.map.landmarks_W.count(features[i].landmark_id) == 0)
      throw InputError(
          features_path, lines[i], "landmark_id",
          fmt::format("landmark {} is not in map.yaml ({} landmarks, ids {}..{})",
                      features[i].landmark_id, d.map.landmarks_W.size(),
                      d.map.landmarks_W.begin()->first, d.map.landmarks_W.rbegin()->first));
  }
}

// A tag stream none of whose detections names a tag of the map's tags (a map whose tags have other
// ids than the detector's family and numbering) would leave every tag estimator without a pose and
// without a word. Some unknown ids are normal in real logs (tags that were not surveyed): the
// estimators count them ("tag not in map").
void RequireTagsInMap(const Dataset& d, const std::vector<TagObservation>& tags,
                      const std::string& tags_path, const std::vector<long>& lines) {
  if (d.map.tags.empty() || tags.empty()) return;
  for (const auto& obs : tags)
    if (d.map.tags.count(obs.tag_id) != 0) return;
  throw InputError(tags_path, lines.front(), "tag_id",
                   fmt::format("none of the {} detections names a tag of map.yaml (first id {}; "
                               "map: {} tags, ids {}..{})",
                               tags.size(), tags.front().tag_id, d.map.tags.size(),
                               d.map.tags.begin()->first, d.map.tags.rbegin()->first));
}

// ---- writing ----

std::string Num(double x) { return fmt::format("{:.15g}", x); }

std::string TransformYaml(const Pose& T) {
  const Eigen::Matrix4d M = T.Matrix();
  std::string data;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) data += (data.empty() ? "" : ", ") + Num(M(r, c));
  return "T_BS:\n  cols: 4\n  rows: 4\n  data: [" + data + "]\n";
}

void WriteImu(const ImuSensor& imu, const fs::path& folder) {
  CreateOutputDirectories(folder);
  std::string yaml = "sensor_type: imu\ncomment: written by mavloc\n" + TransformYaml(imu.T_B_S);
  yaml += "rate_hz: " + Num(imu.rate_hz) + "\n";
  yaml += "gyroscope_noise_density: " + Num(imu.noise.gyroscope_noise_density) + "\n";
  yaml += "gyroscope_random_walk: " + Num(imu.noise.gyroscope_random_walk) + "\n";
  yaml += "accelerometer_noise_density: " + Num(imu.noise.accelerometer_noise_density) + "\n";
  yaml += "accelerometer_random_walk: " + Num(imu.noise.accelerometer_random_walk) + "\n";
  if (imu.gyroscope_bias_sigma)
    yaml += "gyroscope_bias_sigma: " + Num(*imu.gyroscope_bias_sigma) + "\n";
  if (imu.accelerometer_bias_sigma)
    yaml += "accelerometer_bias_sigma: " + Num(*imu.accelerometer_bias_sigma) + "\n";
  WriteFileAtomically((folder / "sensor.yaml").string(), yaml);
  std::string csv =
      "#timestamp [ns],w_RS_S_x [rad s^-1],w_RS_S_y [rad s^-1],w_RS_S_z [rad s^-1],"
      "a_RS_S_x [m s^-2],a_RS_S_y [m s^-2],a_RS_S_z [m s^-2]\n";
  for (const auto& s : imu.samples) {
    csv += fmt::format("{},{},{},{},{},{},{}\n", s.t_ns, Num(s.gyro_rad_s.x()),
                       Num(s.gyro_rad_s.y()), Num(s.gyro_rad_s.z()), Num(s.accel_m_s2.x()),
                       Num(s.accel_m_s2.y()), Num(s.accel_m_s2.z()));
  }
  WriteFileAtomically((folder / "data.csv").string(), csv);
}

void WriteCamera(const CameraSensor& camera, const fs::path& folder) {
  CreateOutputDirectories(folder / "data");
  const CameraModel& m = camera.model;
  std::string yaml =
      "sensor_type: camera\ncomment: written by mavloc\n" + TransformYaml(camera.T_B_C);
  yaml += "rate_hz: " + Num(camera.rate_hz) + "\n";
  yaml += fmt::format("resolution: [{}, {}]\n", m.width(), m.height());
  yaml += "camera_model: pinhole\n";
  yaml += fmt::format("intrinsics: [{}, {}, {}, {}] #fu, fv, cu, cv\n", Num(m.fu()), Num(m.fv()),
                      Num(m.cu()), Num(m.cv()));
  yaml += "distortion_model: " + DistortionModelName(m.distortion_model()) + "\n";
  const auto& k = m.distortion();
  yaml += fmt::format("distortion_coefficients: [{}, {}, {}, {}]\n", Num(k[0]), Num(k[1]),
                      Num(k[2]), Num(k[3]));
  WriteFileAtomically((folder / "sensor.yaml").string(), yaml);
  std::string csv = "#timestamp [ns],filename\n";
  for (const auto& frame : camera.frames) {
    const fs::path source(frame.image_path);
    const std::string file_name =
        source.has_filename() ? source.filename().string() : std::to_string(frame.t_ns) + ".png";
    const fs::path target = folder / "data" / file_name;
    std::error_code error;
    if (!frame.image_path.empty() && fs::exists(source) && !fs::equivalent(source, target, error))
      fs::copy_file(source, target, fs::copy_options::overwrite_existing);
    csv += fmt::format("{},{}\n", frame.t_ns, file_name);
  }
  WriteFileAtomically((folder / "data.csv").string(), csv);
}

void WriteGroundTruth(const std::vector<GroundTruthState>& states, const fs::path& folder) {
  CreateOutputDirectories(folder);
  std::string csv =
      "#timestamp, p_RS_R_x [m], p_RS_R_y [m], p_RS_R_z [m], q_RS_w [], q_RS_x [], q_RS_y [], "
      "q_RS_z [], v_RS_R_x [m s^-1], v_RS_R_y [m s^-1], v_RS_R_z [m s^-1], b_w_RS_S_x [rad s^-1], "
      "b_w_RS_S_y [rad s^-1], b_w_RS_S_z [rad s^-1], b_a_RS_S_x [m s^-2], b_a_RS_S_y [m s^-2], "
      "b_a_RS_S_z [m s^-2]\n";
  for (const auto& s : states) {
    const auto& q = s.T_W_B.q;
    csv += fmt::format("{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}\n", s.t_ns,
                       Num(s.T_W_B.p.x()), Num(s.T_W_B.p.y()), Num(s.T_W_B.p.z()), Num(q.w()),
                       Num(q.x()), Num(q.y()), Num(q.z()), Num(s.v_W.x()), Num(s.v_W.y()),
                       Num(s.v_W.z()), Num(s.b_g.x()), Num(s.b_g.y()), Num(s.b_g.z()),
                       Num(s.b_a.x()), Num(s.b_a.y()), Num(s.b_a.z()));
  }
  WriteFileAtomically((folder / "data.csv").string(), csv);
}

void WriteFeatures(const std::vector<FeatureObservation>& features, const fs::path& folder) {
  if (features.empty()) return;
  CreateOutputDirectories(folder);
  WriteFileAtomically((folder / "data.csv").string(), FeaturesCsv(features));
}

void WriteExtensions(const Dataset& d, const fs::path& mav0) {
  WriteFeatures(d.features, mav0 / kFeatures);
  WriteFeatures(d.features1, mav0 / kFeatures1);
  if (!d.laser.empty()) {
    CreateOutputDirectories(mav0 / kLaser);
    std::string csv = "#timestamp [ns],x [normalized],y [normalized]\n";
    for (const auto& l : d.laser)
      csv += fmt::format("{},{},{}\n", l.t_ns, Num(l.xy.x()), Num(l.xy.y()));
    WriteFileAtomically((mav0 / kLaser / "data.csv").string(), csv);
  }
  if (!d.tags.empty()) {
    CreateOutputDirectories(mav0 / kTags);
    WriteFileAtomically((mav0 / kTags / "data.csv").string(), TagsCsv(d.tags));
  }
  if (!d.tags1.empty()) {
    CreateOutputDirectories(mav0 / kTags1);
    WriteFileAtomically((mav0 / kTags1 / "data.csv").string(), TagsCsv(d.tags1));
  }
  const QuantityTable& q = d.truth_quantities;
  if (!q.empty()) {
    CreateOutputDirectories(mav0 / kTruthQuantities);
    std::string csv = "#timestamp [ns]";
    for (size_t k = 0; k < q.names.size(); ++k) csv += "," + q.names[k] + " [" + q.units[k] + "]";
    csv += "\n";
    for (size_t i = 0; i < q.size(); ++i) {
      csv += std::to_string(q.t_ns[i]);
      for (double v : q.rows[i]) csv += fmt::format(",{}", Num(v));
      csv += "\n";
    }
    WriteFileAtomically((mav0 / kTruthQuantities / "data.csv").string(), csv);
  }
}

std::string Vec(const Eigen::Vector3d& v) {
  return fmt::format("[{}, {}, {}]", Num(v.x()), Num(v.y()), Num(v.z()));
}

void WriteMap(const WorldMap& map, const std::string& path) {
  std::string yaml = "# mavloc world map: what the world is known to contain (frames: DESIGN.md)\n";
  if (map.frame == MapFrame::kBoard)
    yaml += "frame: board  # coordinates in the board frame M; gravity in M unknown\n";
  if (!map.landmarks_W.empty()) {
    yaml += "landmarks:\n";
    for (const auto& [id, p] : map.landmarks_W)
      yaml += fmt::format("  - {{id: {}, p_W: {}}}\n", id, Vec(p));
  }
  if (!map.tags.empty()) {
    yaml += "tags:  # tag frame: centre, x right, y up, z out of the tag; q_W_T as [w, x, y, z]\n";
    for (const auto& [id, tag] : map.tags) {
      const auto& q = tag.T_W_T.q;
      yaml += fmt::format("  - {{id: {}, size_m: {}, p_W: {}, q_W_T: [{}, {}, {}, {}]}}\n", id,
                          Num(tag.size_m), Vec(tag.T_W_T.p), Num(q.w()), Num(q.x()), Num(q.y()),
                          Num(q.z()));
    }
  }
  if (map.plane) {
    yaml += fmt::format("plane: {{n_W: {}, d_m: {}}}  # n_W . p_W = d_m\n", Vec(map.plane->n_W),
                        Num(map.plane->d_m));
  }
  if (!map.parameters.empty()) {
    yaml += "parameters:\n";
    for (const auto& [key, value] : map.parameters) yaml += "  " + key + ": " + Num(value) + "\n";
  }
  WriteFileAtomically(path, yaml);
}

void WriteScenarioInfo(const Dataset& d, const std::string& path) {
  if (d.scenario.empty() && d.scenario_info.empty()) return;  // a logged or imported dataset
  YAML::Emitter out;
  out << YAML::BeginMap;
  if (!d.scenario.empty()) out << YAML::Key << "scenario" << YAML::Value << d.scenario;
  for (const auto& [key, value] : d.scenario_info) {
    if (key == "scenario") continue;
    out << YAML::Key << key << YAML::Value << value;
  }
  out << YAML::EndMap;
  WriteFileAtomically(
      path, std::string("# how this synthetic dataset was made (mavloc simulate)\n") + out.c_str() +
                "\n");
}

}  // namespace

std::string FeaturesCsv(const std::vector<FeatureObservation>& features) {
  std::string csv = "#timestamp [ns],landmark_id,x [normalized],y [normalized]\n";
  for (const auto& f : features)
    csv += fmt::format("{},{},{},{}\n", f.t_ns, f.landmark_id, Num(f.xy.x()), Num(f.xy.y()));
  return csv;
}

std::string TagsCsv(const std::vector<TagObservation>& tags) {
  std::string csv =
      "#timestamp [ns],tag_id,u0 [px],v0 [px],u1 [px],v1 [px],u2 [px],v2 [px],u3 [px],v3 [px]\n";
  for (const auto& t : tags) {
    csv += fmt::format("{},{}", t.t_ns, t.tag_id);
    for (const auto& c : t.corners_px) csv += fmt::format(",{},{}", Num(c.x()), Num(c.y()));
    csv += "\n";
  }
  return csv;
}

Dataset ReadEurocDataset(const std::string& root, const EurocReadOptions& options) {
  if (!fs::is_directory(root)) throw InputError(root, 0, "", "dataset folder does not exist");
  const fs::path mav0 = fs::path(root) / "mav0";
  if (!fs::is_directory(mav0))
    throw InputError(root, 0, "", "not an ASL/EuRoC dataset: no mav0/ folder inside");
  Dataset d;
  d.root = fs::weakly_canonical(root).string();
  d.name = fs::path(d.root).filename().string();
  const auto yaml_of = [](const fs::path& folder) { return (folder / "sensor.yaml").string(); };
  // No imu0 folder: a log without an IMU (e.g. TagSLAM's tag logs); IMU estimators say so.
  if (fs::exists(mav0 / kImu) && !fs::is_directory(mav0 / kImu))
    throw InputError((mav0 / kImu).string(), 0, "",
                     "is not a folder (an IMU stream is a folder with data.csv and sensor.yaml)");
  if (fs::is_directory(mav0 / kImu))
    d.imu = NamingFile(yaml_of(mav0 / kImu), [&] { return ReadImu(mav0 / kImu); });
  if (options.load_cameras) {
    std::vector<fs::path> camera_folders;
    for (const auto& entry : fs::directory_iterator(mav0)) {
      const std::string name = entry.path().filename().string();
      if (!entry.is_directory() || name.rfind("cam", 0) != 0) continue;
      if (fs::exists(entry.path() / "sensor.yaml")) {
        camera_folders.push_back(entry.path());
      } else if (fs::exists(entry.path() / "data.csv")) {
        // Frames without a calibration cannot be used by any estimator: say so, never skip them.
        throw InputError((entry.path() / "sensor.yaml").string(), 0, "",
                         "missing: " + name +
                             "/ has data.csv but no sensor.yaml (the camera's "
                             "intrinsics and T_BS)");
      }
    }
    std::sort(camera_folders.begin(), camera_folders.end());
    for (const auto& folder : camera_folders)
      d.cameras.push_back(NamingFile(yaml_of(folder), [&] { return ReadCamera(folder); }));
  }
  const auto stream = [&](const char* name) { return (mav0 / name / "data.csv").string(); };
  if (fs::exists(stream(kGroundTruth))) d.ground_truth = ReadGroundTruthCsv(stream(kGroundTruth));
  std::vector<long> feature_lines;
  if (fs::exists(stream(kFeatures)))
    d.features = ReadFeatures(stream(kFeatures), 0, &feature_lines);
  std::vector<long> feature1_lines;
  if (fs::exists(stream(kFeatures1)))
    d.features1 = ReadFeatures(stream(kFeatures1), 1, &feature1_lines);
  if (!d.features1.empty() && options.load_cameras && d.Camera("cam1") == nullptr)
    throw InputError(
        stream(kFeatures1), 0, "",
        "features of cam1 (features1), but there is no cam1/ folder with a sensor.yaml");
  if (fs::exists(stream(kLaser))) d.laser = ReadLaser(stream(kLaser));
  std::vector<long> tag_lines, tag1_lines;
  if (fs::exists(stream(kTags))) d.tags = ReadTags(stream(kTags), 0, &tag_lines);
  if (fs::exists(stream(kTags1))) d.tags1 = ReadTags(stream(kTags1), 1, &tag1_lines);
  if (!d.tags1.empty() && options.load_cameras && d.Camera("cam1") == nullptr)
    throw InputError(stream(kTags1), 0, "",
                     "detections of cam1 (tags1), but there is no cam1/ folder with a sensor.yaml");
  if (fs::exists(stream(kTruthQuantities)))
    d.truth_quantities = ReadTruthQuantities(stream(kTruthQuantities));
  const std::string map_path = (fs::path(root) / "map.yaml").string();
  if (fs::exists(map_path)) d.map = NamingFile(map_path, [&] { return ReadMap(map_path); });
  RequireFeaturesInMap(d, d.features, stream(kFeatures), feature_lines);
  RequireFeaturesInMap(d, d.features1, stream(kFeatures1), feature1_lines);
  RequireTagsInMap(d, d.tags, stream(kTags), tag_lines);
  RequireTagsInMap(d, d.tags1, stream(kTags1), tag1_lines);
  const std::string scenario_path = (fs::path(root) / "scenario.yaml").string();
  if (fs::exists(scenario_path)) {
    d.scenario_info = NamingFile(scenario_path, [&] { return ReadScenarioInfo(scenario_path); });
    if (d.scenario_info.count("scenario")) d.scenario = d.scenario_info["scenario"];
  }
  return d;
}

void WriteEurocDataset(const Dataset& d, const std::string& root) {
  const fs::path mav0 = fs::path(root) / "mav0";
  std::error_code error;
  CreateOutputDirectories(mav0, error);
  if (error) throw InputError(root, 0, "", "cannot create folder: " + error.message());
  if (!d.imu.samples.empty()) WriteImu(d.imu, mav0 / kImu);
  for (const auto& camera : d.cameras) WriteCamera(camera, mav0 / camera.name);
  if (!d.ground_truth.empty()) WriteGroundTruth(d.ground_truth, mav0 / kGroundTruth);
  WriteExtensions(d, mav0);
  WriteMap(d.map, (fs::path(root) / "map.yaml").string());
  WriteScenarioInfo(d, (fs::path(root) / "scenario.yaml").string());
}

void WriteEurocDatasetAtomically(const Dataset& d, const std::string& root,
                                 const std::map<std::string, std::string>& extra_files,
                                 bool replace) {
  fs::path target = fs::absolute(root).lexically_normal();
  if (target.has_parent_path() && target.filename().empty()) target = target.parent_path();  // "d/"
  const fs::path parent = target.parent_path();
  if (!fs::is_directory(parent))
    throw InputError(root, 0, "",
                     "output's parent folder '" + parent.string() + "' does not exist");
  std::error_code error;
  const bool exists = fs::exists(target);
  if (exists && !fs::is_directory(target))
    throw InputError(root, 0, "", "exists and is not a folder");
  if (exists && !fs::is_empty(target, error) && !replace)
    throw InputError(root, 0, "",
                     "folder exists and is not empty (choose another, or replace it: --force)");
  const std::string suffix = std::to_string(::getpid());
  const fs::path temporary = target.string() + ".tmp-" + suffix;
  fs::remove_all(temporary, error);
  try {
    CreateOutputDirectories(temporary);
    WriteEurocDataset(d, temporary.string());
    for (const auto& [relative, contents] : extra_files) {
      const fs::path file = temporary / relative;
      CreateOutputDirectories(file.parent_path());
      WriteFileAtomically(file.string(), contents);
    }
    const fs::path old = target.string() + ".old-" + suffix;
    if (exists) fs::rename(target, old);
    fs::rename(temporary, target);
    if (exists) fs::remove_all(old);
  } catch (const fs::filesystem_error& e) {
    fs::remove_all(temporary, error);
    throw InputError(root, 0, "", std::string("cannot write the dataset: ") + e.what());
  } catch (...) {
    fs::remove_all(temporary, error);
    throw;
  }
}

// The IMU header, when it names the columns, must name the gyroscope first (EuRoC: w_RS_S_x ..,
// then a_RS_S_x ..): a file with the accelerometer first would otherwise be read as a gyroscope of
// 9.81 rad/s. Names that say neither (a header of another tool) are not judged.
void RequireImuColumnOrder(const TextTable& table) {
  if (table.header.size() < 7) return;
  const auto kind = [](std::string name) {
    std::transform(name.begin(), name.end(), name.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    const auto has = [&](const char* part) { return name.find(part) != std::string::npos; };
    if (has("gyr") || has("omega") || has("angular")) return 'w';  // ROS: angular_velocity.x
    if (has("acc") || has("linear")) return 'a';                   // ROS: linear_acceleration.x
    if (name.rfind('w', 0) == 0) return 'w';                       // EuRoC w_RS_S_x, yac wx
    if (name.rfind('a', 0) == 0) return 'a';                       // EuRoC a_RS_S_x, yac ax
    return '?';
  };
  for (size_t k = 1; k <= 6; ++k) {
    const char expected = k <= 3 ? 'w' : 'a';
    const char found = kind(table.header[k]);
    if (found != '?' && found != expected)
      throw InputError(
          table.path, 1, table.FieldName(k),
          fmt::format("column {} must be the {} (EuRoC order: timestamp, w_RS_S_x/y/z "
                      "[rad/s], a_RS_S_x/y/z [m/s^2]); the header names '{}'",
                      k + 1, expected == 'w' ? "gyroscope" : "accelerometer", table.header[k]));
  }
}

void ForEachImuCsvSample(const std::string& path,
                         const std::function<void(const ImuSample&)>& visit) {
  TextRowReader reader(path, Separator::kComma);
  TextTable columns;  // the header and path, for RequireImuColumnOrder and the messages
  columns.path = path;
  const auto within = [&](const TextRowView& row, size_t k, double max_abs, const char* unit) {
    return columns.NumberInText(row.fields[k], row.line, k, -max_abs, max_abs, unit);
  };
  ImuSample s;
  bool first = true;
  while (const TextRowView* row = reader.Next()) {
    if (first) {
      columns.header = reader.header();
      RequireImuColumnOrder(columns);
    }
    const TimeNs t_ns = columns.TimestampNsText(row->fields[0], row->line, 0);
    if (!first) columns.RequireAfter(s.t_ns, t_ns, row->line);
    first = false;
    columns.RequireFieldCount(row->fields.size(), row->line, 7);
    if (row->fields.size() > 7)
      throw InputError(path, row->line, columns.FieldName(7),
                       fmt::format("row has {} fields; an IMU row has 7 (timestamp, gyroscope x y "
                                   "z, accelerometer x y z)",
                                   row->fields.size()));
    s.t_ns = t_ns;
    for (int i = 0; i < 3; ++i) {
      s.gyro_rad_s[i] = within(*row, 1 + i, limits::kMaxAngularRate_rad_s, "rad/s");
    }
    for (int i = 0; i < 3; ++i) {
      s.accel_m_s2[i] = within(*row, 4 + i, limits::kMaxSpecificForce_m_s2, "m/s^2");
    }
    visit(s);
  }
  if (first) throw InputError(path, 0, "", "file has no data rows");
}

std::vector<ImuSample> ReadImuCsv(const std::string& path) {
  std::vector<ImuSample> samples;
  ForEachImuCsvSample(path, [&samples](const ImuSample& s) { samples.push_back(s); });
  return samples;
}

std::vector<GroundTruthState> ReadTrajectoryFile(const std::string& path,
                                                 TrajectoryReadReport* report) {
  // Any format ReadTrajectory detects (TUM, EuRoC/ASL, KITTI); repeated stamps keep the first row.
  LoadedTrajectory loaded = ReadTrajectory(path);
  if (report != nullptr) *report = loaded.report;
  return loaded.States();
}

}  // namespace mavloc
