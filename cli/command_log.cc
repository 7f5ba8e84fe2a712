// mavloc log: what a ROS1 bag or PX4 ULog file holds (`log info`), a topic as a TUM trajectory
// (`log export`), and a log as an ASL dataset folder with the chosen topics (`log import`).
// Readers: datasets/io/log_reader.h (format from the file's first bytes).
#include <fmt/format.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "cli/commands.h"
#include "cli/option_checks.h"
#include "cli/output_folder.h"
#include "core/atomic_file.h"
#include "core/errors.h"
#include "core/interrupt.h"
#include "core/progress.h"
#include "core/stamp_rate.h"
#include "datasets/io/calibration_io.h"
#include "datasets/io/euroc_io.h"
#include "datasets/io/log_reader.h"
#include "datasets/io/rosbag/rosbag_reader.h"
#include "datasets/io/tum_io.h"
#include "datasets/io/ulog/ulog_reader.h"

namespace mavloc::cli {

namespace {

namespace fs = std::filesystem;

const char* FormatName(LogFormat format) {
  return format == LogFormat::kRosbag ? "ROS1 bag" : "PX4 ULog";
}

void PrintSummary(const LogSummary& summary) {
  // Names come from the log: control bytes and invalid UTF-8 are escaped (core/errors.h), so a
  // topic holding terminal escape sequences cannot reach the terminal raw.
  const std::string path = PrintableMessage(summary.path);
  std::printf("%s: %s, %.3f s (%.9f .. %.9f)\n", path.c_str(), FormatName(summary.format),
              NsToSeconds(summary.t_end_ns - summary.t_start_ns), NsToSeconds(summary.t_start_ns),
              NsToSeconds(summary.t_end_ns));
  std::vector<std::string> names, types;
  size_t topic_width = 5, type_width = 4;
  for (const auto& t : summary.topics) {
    names.push_back(
        PrintableMessage(t.instance > 0 ? fmt::format("{}:{}", t.topic, t.instance) : t.topic));
    types.push_back(PrintableMessage(t.type));
    topic_width = std::max(topic_width, names.back().size());
    type_width = std::max(type_width, types.back().size());
  }
  std::printf("%-*s  %-*s  %10s  %10s  %12s  %12s\n", static_cast<int>(topic_width), "topic",
              static_cast<int>(type_width), "type", "messages", "rate [Hz]", "first [s]",
              "last [s]");
  for (size_t i = 0; i < summary.topics.size(); ++i) {
    const auto& t = summary.topics[i];
    const double span_s = NsToSeconds(t.t_last_ns - t.t_first_ns);
    const std::string rate =
        t.messages > 1 && span_s > 0 ? fmt::format("{:.2f}", (t.messages - 1) / span_s) : "-";
    std::printf("%-*s  %-*s  %10llu  %10s  %12.3f  %12.3f\n", static_cast<int>(topic_width),
                names[i].c_str(), static_cast<int>(type_width), types[i].c_str(),
                static_cast<unsigned long long>(t.messages), rate.c_str(),
                NsToSeconds(t.t_first_ns - summary.t_start_ns),
                NsToSeconds(t.t_last_ns - summary.t_start_ns));
  }
  for (const auto& note : summary.notes) std::printf("note: %s\n", PrintableMessage(note).c_str());
}

nlohmann::json SummaryJson(const LogSummary& summary) {
  nlohmann::json j;
  j["path"] = summary.path;
  j["format"] = summary.format == LogFormat::kRosbag ? "rosbag" : "ulog";
  j["t_start_ns"] = summary.t_start_ns;
  j["t_end_ns"] = summary.t_end_ns;
  j["topics"] = nlohmann::json::array();
  for (const auto& t : summary.topics)
    j["topics"].push_back({{"topic", t.topic},
                           {"type", t.type},
                           {"instance", t.instance},
                           {"messages", t.messages},
                           {"t_first_ns", t.t_first_ns},
                           {"t_last_ns", t.t_last_ns}});
  j["notes"] = summary.notes;
  return j;
}

// "LOG:TOPIC..." given as a topic of the log being imported: the log's path is prefixed.
LogTopicSpec TopicOf(const std::string& log, const std::string& topic) {
  const auto spec = ParseLogTopicSpec(log + ":" + topic);
  if (!spec) throw InputError(log, 0, "", "not a ROS1 bag or PX4 ULog file");
  return *spec;
}

// "TOPIC=camN" -> {TOPIC, N}; a plain TOPIC -> {TOPIC, default_camera}.
std::pair<std::string, int> TopicCamera(const std::string& item, const std::string& flag,
                                        int default_camera) {
  const size_t eq = item.rfind('=');
  if (eq == std::string::npos) return {item, default_camera};
  const std::string camera = item.substr(eq + 1);
  if (camera != "cam0" && camera != "cam1")
    throw InputError("", 0, flag, "'" + item + "': expected TOPIC=cam0 or TOPIC=cam1");
  return {item.substr(0, eq), camera[3] - '0'};
}

// A progress line on stderr about every 64 MiB of a ULog file.
UlogProgress UlogProgressLine(const std::string& path) {
  return [path](uint64_t bytes_done, uint64_t bytes_total) {
    ReportProgress(
        "ulog", fmt::format("{}: {:.0f} of {:.0f} MB", path, bytes_done / 1e6, bytes_total / 1e6));
  };
}

// Appends each of `reader_notes` not yet in `notes` as "note: ..." (two topics of one log give
// the same scan notes once).
void AddReaderNotes(const std::vector<std::string>& reader_notes, std::vector<std::string>* notes) {
  for (const std::string& note : reader_notes) {
    const std::string line = "note: " + note;
    if (std::find(notes->begin(), notes->end(), line) == notes->end()) notes->push_back(line);
  }
}

// A log's IMU topic. The ULog reader drops what PX4 marks invalid and stamps that do not increase,
// and its scan notes truncation and corrupt messages: those notes are added to `notes` (a bag's
// reader refuses instead of dropping).
std::vector<ImuSample> ReadImuTopic(const std::string& log, LogFormat format,
                                    const std::string& topic, std::vector<std::string>* notes) {
  if (format == LogFormat::kRosbag) return ReadLogImu(log, topic);
  // "vehicle_imu:1" (the LOG:TOPIC:INSTANCE form) is the ULog reader's "vehicle_imu.1".
  std::string ulog_topic = topic;
  if (const size_t colon = ulog_topic.rfind(':'); colon != std::string::npos)
    ulog_topic[colon] = '.';
  std::vector<std::string> reader_notes;
  std::vector<ImuSample> samples =
      ReadUlogImu(log, ulog_topic, UlogProgressLine(log), &reader_notes);
  AddReaderNotes(reader_notes, notes);
  return samples;
}

// A log's trajectory topic, with the ULog reader's notes added to `notes` as for ReadImuTopic.
LogTrajectory ReadTrajectoryTopic(const LogTopicSpec& spec, std::vector<std::string>* notes) {
  if (DetectLogFormat(spec.path) != LogFormat::kUlog) return ReadLogTrajectory(spec);
  // The ULog reader names later instances of a multi-instance topic "name.N".
  LogTopicSpec ulog = spec;
  if (spec.instance > 0) ulog.topic += "." + std::to_string(spec.instance);
  std::vector<std::string> reader_notes;
  LogTrajectory trajectory = ReadUlogTrajectory(ulog, UlogProgressLine(spec.path), &reader_notes);
  AddReaderNotes(reader_notes, notes);
  return trajectory;
}

// import.yaml's list items: double-quoted YAML scalars.
std::string YamlQuoted(const std::string& text) {
  std::string quoted = "\"";
  for (const char c : text) {
    if (c == '"' || c == '\\') quoted += '\\';
    quoted += c;
  }
  return quoted + "\"";
}

struct ImportArgs {
  std::string log, out, imu, gt, imu_noise;
  std::vector<std::string> tags, camera_info, images, calibration;
  bool force = false;
};

void ImportLog(const ImportArgs& args) {
  const auto format = DetectLogFormat(args.log);
  if (!format)
    throw InputError(args.log, 0, "",
                     fs::exists(args.log) ? "not a ROS1 bag or PX4 ULog file" : "does not exist");
  if (args.imu.empty() && args.gt.empty() && args.tags.empty() && args.images.empty())
    throw InputError(args.log, 0, "",
                     "nothing to import: give --imu, --gt, --tags or --images (see `mavloc log "
                     "info` for the topics)");
  Dataset dataset;
  dataset.name = fs::path(args.log).stem().string();
  std::vector<std::string> notes;
  notes.push_back("source: " + fs::absolute(args.log).string() + " (" + FormatName(*format) + ")");
  std::vector<std::string> reader_notes;  // what the readers dropped, truncation, corrupt data
  if (!args.imu.empty()) {
    ReportProgress("log import", "reading IMU topic " + args.imu);
    dataset.imu.samples = ReadImuTopic(args.log, *format, args.imu, &reader_notes);
    std::vector<TimeNs> t;
    for (const auto& s : dataset.imu.samples) t.push_back(s.t_ns);
    dataset.imu.rate_hz = MedianRateHz(t);
    notes.push_back(fmt::format("imu0: {} samples from {} (median rate {:.2f} Hz)",
                                dataset.imu.samples.size(), args.imu, dataset.imu.rate_hz));
    if (!args.imu_noise.empty()) {
      const CalibrationSource source = ReadCalibrationSource(args.imu_noise);
      if (!source.imu)
        throw InputError(args.imu_noise, 0, "", "holds no IMU noise (Kalibr/EuRoC/yac names)");
      dataset.imu.noise = source.imu->noise;
      notes.push_back("imu0 noise: " + source.imu->from);
    } else {
      notes.push_back(
          "imu0 noise: unknown (no --imu-noise): sensor.yaml holds zeros and the estimators use "
          "their own defaults (or --option KEY=VALUE)");
    }
  }
  if (!args.gt.empty()) {
    ReportProgress("log import", "reading trajectory topic " + args.gt);
    const LogTrajectory trajectory = ReadTrajectoryTopic(TopicOf(args.log, args.gt), &reader_notes);
    if (!trajectory.has_position || !trajectory.has_attitude)
      throw InputError(args.log, 0, args.gt,
                       std::string("carries no ") +
                           (trajectory.has_position ? "attitude" : "position") +
                           ": a ground-truth stream needs full poses (use it with `mavloc eval` "
                           "or `compare --reference` instead)");
    dataset.ground_truth = trajectory.states;
    notes.push_back(fmt::format(
        "state_groundtruth_estimate0: {} poses from {} ({}, {} -> {}){}", trajectory.states.size(),
        args.gt, trajectory.type, trajectory.parent_frame, trajectory.child_frame,
        trajectory.has_velocity ? "" : "; no velocity in the messages: v = 0 written"));
  }
  // Cameras: models from --calibration (camN=FILE) or --camera-info (TOPIC=camN).
  std::map<int, CameraSensor> cameras;
  auto camera = [&](int index) -> CameraSensor& {
    auto& c = cameras[index];
    c.name = "cam" + std::to_string(index);
    return c;
  };
  for (const std::string& item : args.calibration) {
    const auto [index, path] = SplitCameraPrefix(item);
    const CalibrationSource source = ReadCalibrationSource(path, index);
    for (const auto& [n, calibration] : source.cameras) {
      if (calibration.model) camera(n).model = *calibration.model;
      if (calibration.T_B_C) camera(n).T_B_C = *calibration.T_B_C;
      notes.push_back(fmt::format("cam{}: calibration from {}", n, path));
    }
  }
  for (const std::string& item : args.camera_info) {
    if (*format != LogFormat::kRosbag)
      throw InputError(args.log, 0, "--camera-info", "camera info topics exist only in ROS bags");
    const auto [topic, index] = TopicCamera(item, "--camera-info", 0);
    camera(index).model = ReadRosbagCameraInfo(args.log, topic);
    notes.push_back(fmt::format("cam{}: camera model from {}", index, topic));
  }
  const fs::path image_root = fs::path(args.out).string() + ".images-" + std::to_string(::getpid());
  // Removed if the command is interrupted (core/interrupt.h); registered before the folder exists
  // and until after RemoveOnExit has removed it.
  const TemporaryPathGuard image_root_guard(image_root.string());
  struct RemoveOnExit {
    fs::path path;
    ~RemoveOnExit() {
      std::error_code error;
      fs::remove_all(path, error);
    }
  } remove_images{image_root};
  for (const std::string& item : args.images) {
    if (*format != LogFormat::kRosbag)
      throw InputError(args.log, 0, "--images", "image topics exist only in ROS bags");
    const auto [topic, index] = TopicCamera(item, "--images", 0);
    ReportProgress("log import", "exporting images of " + topic);
    const fs::path folder = image_root / ("cam" + std::to_string(index));
    CreateOutputDirectories(folder);
    camera(index).frames = ExportRosbagImages(args.log, topic, folder.string());
    std::vector<TimeNs> t;
    for (const auto& f : camera(index).frames) t.push_back(f.t_ns);
    camera(index).rate_hz = MedianRateHz(t);
    notes.push_back(
        fmt::format("cam{}: {} images from {}", index, camera(index).frames.size(), topic));
  }
  for (const std::string& item : args.tags) {
    if (*format != LogFormat::kRosbag)
      throw InputError(args.log, 0, "--tags", "tag detection topics exist only in ROS bags");
    const auto [topic, index] = TopicCamera(item, "--tags", 0);
    const CameraModel& model = camera(index).model;
    auto tags = ReadRosbagTags(args.log, topic, index,
                               model.width() > 0 ? std::optional(model) : std::nullopt);
    notes.push_back(fmt::format("tags{}: {} tag detections from {}", index, tags.size(), topic));
    auto& target = index == 0 ? dataset.tags : dataset.tags1;
    target.insert(target.end(), tags.begin(), tags.end());
    camera(index);
  }
  for (auto& [index, c] : cameras) {
    if (c.model.width() <= 0)
      throw InputError(args.log, 0, "cam" + std::to_string(index),
                       "no camera model: give --calibration cam" + std::to_string(index) +
                           "=FILE or --camera-info TOPIC=cam" + std::to_string(index));
    dataset.cameras.push_back(c);
  }
  notes.insert(notes.end(), reader_notes.begin(), reader_notes.end());
  std::string import_yaml = "# written by mavloc log import\n";
  for (const auto& note : notes) import_yaml += "- " + YamlQuoted(note) + "\n";
  ReportProgress("log import", "writing " + args.out);
  // Its staging folder is removed if the command is interrupted (core/interrupt.h).
  const TemporaryPathGuard staging(StagingPathFor(args.out));
  WriteEurocDatasetAtomically(dataset, args.out, {{"import.yaml", import_yaml}}, args.force);
  for (const auto& note : notes) std::printf("%s\n", note.c_str());
  std::printf("wrote %s\n", args.out.c_str());
}

}  // namespace

void RegisterLog(CLI::App& app, int* exit_code) {
  auto* command = app.add_subcommand(
      "log", "ROS1 bags and PX4 ULog files: list topics, export a trajectory, import as a dataset");
  command->require_subcommand(1);

  auto* info = command->add_subcommand(
      "info", "Topics of a log: type, message count, rate, first and last stamp; notes");
  auto info_args = std::make_shared<std::pair<std::string, std::string>>();
  info->add_option("log", info_args->first, "ROS1 bag (.bag, .bag.bz2) or PX4 ULog (.ulg)")
      ->required();
  info->add_option("--json", info_args->second, "Also write the summary as JSON to this file")
      ->check(OutputFile());
  info->callback([info_args, exit_code] {
    const LogSummary summary = SummarizeLog(info_args->first);
    PrintSummary(summary);
    if (!info_args->second.empty())
      WriteFileAtomically(info_args->second, SummaryJson(summary).dump(2) + "\n");
    *exit_code = 0;
  });

  auto* to_tum = command->add_subcommand(
      "export", "A trajectory topic of a log as a TUM file (LOG:TOPIC, LOG.bag:/tf:PARENT:CHILD)");
  auto export_args = std::make_shared<std::pair<std::string, std::string>>();
  to_tum->add_option("source", export_args->first, "LOG:TOPIC")->required();
  to_tum->add_option("--out", export_args->second, "TUM file to write")
      ->check(OutputFile())
      ->required();
  to_tum->callback([export_args, exit_code] {
    const auto spec = ParseLogTopicSpec(export_args->first);
    if (!spec)
      throw InputError(export_args->first, 0, "",
                       "expected LOG:TOPIC with LOG an existing ROS1 bag or PX4 ULog file");
    std::vector<std::string> notes;  // what the ULog reader dropped, truncation, corrupt data
    const LogTrajectory trajectory = ReadTrajectoryTopic(*spec, &notes);
    std::vector<StampedPose> poses;
    for (const auto& s : trajectory.states) poses.push_back({s.t_ns, s.T_W_B});
    WriteTumTrajectory(poses, export_args->second);
    std::printf("%zu poses of %s (%s%s%s) -> %s\n", poses.size(), export_args->first.c_str(),
                trajectory.type.c_str(), trajectory.has_position ? "" : ", no position: p = 0",
                trajectory.has_attitude ? "" : ", no attitude: identity",
                export_args->second.c_str());
    for (const auto& note : notes) std::printf("%s\n", note.c_str());
    *exit_code = 0;
  });

  auto* import = command->add_subcommand(
      "import", "A log as an ASL dataset folder: IMU, ground truth, tags, images, camera models");
  auto args = std::make_shared<ImportArgs>();
  import->add_option("log", args->log, "ROS1 bag (.bag, .bag.bz2) or PX4 ULog (.ulg)")->required();
  import->add_option("--out", args->out, "Output dataset folder (must not exist or be empty)")
      ->check(OutputFolder())
      ->required();
  import->add_option("--imu", args->imu,
                     "IMU topic -> imu0 (sensor_msgs/Imu; ULog sensor_combined or vehicle_imu)");
  import->add_option("--imu-noise", args->imu_noise,
                     "IMU noise densities: Kalibr imu.yaml, EuRoC imu0/sensor.yaml or yac config");
  import->add_option("--gt", args->gt,
                     "Pose topic -> state_groundtruth_estimate0 (PoseStamped, "
                     "PoseWithCovarianceStamped, Odometry, /tf:PARENT:CHILD; ULog "
                     "vehicle_odometry...)");
  import->add_option("--tags", args->tags,
                     "Tag detection topic[=camN] -> tags0/tags1 (repeatable; needs a camera "
                     "model)");
  import->add_option("--images", args->images,
                     "Image topic[=camN] -> camN images (Image or CompressedImage; repeatable)");
  import->add_option("--camera-info", args->camera_info,
                     "sensor_msgs/CameraInfo topic[=camN] -> camN model (repeatable)");
  import->add_option("--calibration", args->calibration,
                     "[camN=]FILE_OR_DIR: camera models and T_B_C (Kalibr camchain, EuRoC, yac; "
                     "repeatable)");
  import->add_flag("--force", args->force, "Replace a non-empty --out folder");
  import->callback([args, exit_code] {
    ImportLog(*args);
  *exit_code = 0;
});
}  // namespace mavloc::cli

}  // namespace mavloc::cli
