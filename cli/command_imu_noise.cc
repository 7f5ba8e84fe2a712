// mavloc imu-noise: IMU noise parameters measured from a log by overlapping Allan deviation
// (evaluation/imu_noise/: allan_deviation.h for the curves, noise_fit.h for white noise, bias
// instability and random walk). Input: an ASL/EuRoC dataset folder (mav0/imu0/data.csv), an IMU CSV
// with EuRoC's columns, a ROS1 bag or a PX4 ULog file (format from the file's first bytes,
// datasets/io/log_reader.h). Writes DIR/imu.yaml (Kalibr's keys), DIR/allan_deviation.csv and
// the report (report.md, report.json) into a staged folder (cli/output_folder.h) and prints the
// table. docs/commands/imu-noise.md.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>

#include "cli/commands.h"
#include "cli/option_checks.h"
#include "cli/output_folder.h"
#include "core/errors.h"
#include "core/progress.h"
#include "datasets/io/euroc_io.h"
#include "datasets/io/log_reader.h"
#include "datasets/io/ulog/ulog_reader.h"
#include "evaluation/imu_noise/allan_deviation.h"
#include "evaluation/imu_noise/imu_noise_report.h"
#include "evaluation/imu_noise/noise_fit.h"
#include "evaluation/report/report_folder.h"
#include "evaluation/report_figures.h"

namespace mavloc::cli {
namespace {

namespace fs = std::filesystem;

struct ImuNoiseArgs {
  std::string input, topic, out;
  double from_s = 0.0;  // seconds since the first IMU sample
  double to_s = std::numeric_limits<double>::infinity();
  bool force = false;
};

struct ImuNoiseInput {
  std::vector<ImuSample> samples;
  std::string source;              // what was read, for messages and imu.yaml
  std::string rostopic;            // imu.yaml's rostopic: the bag topic, else /imu0
  std::vector<std::string> notes;  // what the ULog reader dropped
};

// The IMU topic of a log when --topic is not given: ULog's sensor_combined, or a bag's only
// sensor_msgs/Imu topic.
std::string ImuNoiseDefaultTopic(const std::string& log, LogFormat format) {
  const LogSummary summary = SummarizeLog(log);
  std::vector<std::string> candidates;
  for (const LogTopicSummary& t : summary.topics) {
    if (format == LogFormat::kUlog && t.instance == 0 && t.topic == "sensor_combined")
      return t.topic;
    if (format == LogFormat::kUlog && t.topic == "vehicle_imu")
      candidates.push_back(t.instance > 0 ? fmt::format("{}:{}", t.topic, t.instance) : t.topic);
    if (format == LogFormat::kRosbag && t.type == "sensor_msgs/Imu") candidates.push_back(t.topic);
  }
  if (candidates.size() == 1) return candidates.front();
  std::string listed;
  for (const std::string& c : candidates) listed += (listed.empty() ? "" : ", ") + c;
  throw InputError(log, 0, "--topic",
                   candidates.empty()
                       ? std::string("no IMU topic in the log (sensor_msgs/Imu; ULog "
                                     "sensor_combined or vehicle_imu): see `mavloc log info`")
                       : "choose the IMU topic with --topic (candidates: " + listed + ")");
}

ImuNoiseInput ReadImuNoiseInput(const ImuNoiseArgs& args) {
  ImuNoiseInput input;
  input.rostopic = "/imu0";
  const auto no_topic = [&](const char* what) {
    if (!args.topic.empty())
      throw InputError(
          args.input, 0, "--topic",
          std::string(what) + " has one IMU stream: --topic is for ROS1 bags and PX4 ULog files");
  };
  if (fs::is_directory(args.input)) {
    no_topic("a dataset folder");
    const fs::path csv = fs::path(args.input) / "mav0" / "imu0" / "data.csv";
    if (!fs::is_regular_file(csv))
      throw InputError(args.input, 0, "",
                       "is a folder without mav0/imu0/data.csv (an ASL/EuRoC dataset folder, a "
                       "ROS1 bag, a PX4 ULog file or an IMU CSV is expected)");
    input.source = csv.string();
    input.samples = ReadImuCsv(input.source);
    return input;
  }
  if (!fs::exists(args.input)) throw InputError(args.input, 0, "", "does not exist");
  const auto format = DetectLogFormat(args.input);
  if (!format) {  // an IMU CSV (EuRoC imu0 columns; yac/Kalibr "#ts,wx,...")
    no_topic("an IMU CSV file");
    input.source = args.input;
    input.samples = ReadImuCsv(args.input);
    return input;
  }
  const std::string topic =
      args.topic.empty() ? ImuNoiseDefaultTopic(args.input, *format) : args.topic;
  input.source = args.input + ":" + topic;
  ReportProgress("imu-noise", "reading " + input.source);
  if (*format == LogFormat::kRosbag) {
    input.rostopic = topic;
    input.samples = ReadLogImu(args.input, topic);
    return input;
  }
  // "vehicle_imu:1" (the LOG:TOPIC:INSTANCE form) is the ULog reader's "vehicle_imu.1".
  std::string ulog_topic = topic;
  if (const size_t colon = ulog_topic.rfind(':'); colon != std::string::npos)
    ulog_topic[colon] = '.';
  input.samples = ReadUlogImu(args.input, ulog_topic, {}, &input.notes);
  return input;
}

// Keeps the samples within [from_s, to_s] seconds of the first one (in place: a log of 1e7
// samples is 560 MB of ImuSample).
void KeepImuNoiseWindow(const ImuNoiseArgs& args, ImuNoiseInput* input) {
  std::vector<ImuSample>& samples = input->samples;
  if (samples.empty()) throw InputError(input->source, 0, "", "holds no IMU samples");
  const TimeNs t0_ns = samples.front().t_ns;
  const double length_s = NsToSeconds(samples.back().t_ns - t0_ns);
  const auto outside = [&](const ImuSample& s) {
    const double t_s = NsToSeconds(s.t_ns - t0_ns);
    return t_s < args.from_s || t_s > args.to_s;
  };
  samples.erase(std::remove_if(samples.begin(), samples.end(), outside), samples.end());
  if (samples.empty())
    throw InputError(input->source, 0, "--from/--to",
                     fmt::format("no sample between {} s and {} s (the stream is {:.3f} s long)",
                                 args.from_s, args.to_s, length_s));
}

// The --from/--to window in words, for the report.
std::string WindowText(const ImuNoiseArgs& args) {
  if (std::isfinite(args.to_s))
    return fmt::format(", the samples from {} s to {} s after the first", args.from_s, args.to_s);
  if (args.from_s > 0.0)
    return fmt::format(", the samples from {} s after the first on", args.from_s);
  return "";
}

void RunImuNoise(const ImuNoiseArgs& args) {
  if (args.from_s < 0.0)
    throw InputError(
        fmt::format("--from {}: must be >= 0 (seconds after the first sample)", args.from_s));
  if (!(args.from_s < args.to_s))
    throw InputError(fmt::format("--from {} is not before --to {}", args.from_s, args.to_s));
  // The output folder is checked before any work and written whole (cli/output_folder.h).
  StagedFolder out(args.out, FolderKind::kReport, args.force);
  ImuNoiseInput input = ReadImuNoiseInput(args);
  KeepImuNoiseWindow(args, &input);
  ReportProgress("imu-noise", fmt::format("Allan deviation of {} samples", input.samples.size()));
  const ImuAllanDeviation curves = ComputeImuAllanDeviation(input.samples);
  if (!curves.sampling.ok)
    throw InputError(
        input.source, 0, "",
        curves.sampling.reason + (curves.sampling.samples >= kMinAllanSamples
                                      ? " (analyse an uninterrupted part with --from/--to)"
                                      : ""));
  for (const auto& [sensor, name] :
       {std::pair{&curves.gyro, "gyroscope"}, std::pair{&curves.accel, "accelerometer"}}) {
    for (int axis = 0; axis < 3; ++axis) {
      const auto& points = (*sensor)[axis].points;
      if (std::none_of(points.begin(), points.end(),
                       [](const AllanPoint& p) { return p.adev > 0.0; }))
        throw InputError(input.source, 0, fmt::format("{} {}", name, "xyz"[axis]),
                         "the series is constant: there is no noise to measure (a stuck sensor, "
                         "or simulated data without noise)");
    }
  }
  const ImuNoiseFit fit = FitImuNoise(curves);
  WriteReport(
      out.path(),
      ImuNoiseReport({input.source, input.rostopic, WindowText(args), input.notes}, fit, curves));
  const FigureOutcome figures = WriteReportFigures(out.path(), out.ForUser(out.path()));
  out.Commit();
  std::printf("%s: %s", PrintableMessage(input.source).c_str(), ImuNoiseTable(fit, curves).c_str());
  for (const std::string& note : input.notes)
    std::printf("note: %s\n", PrintableMessage(note).c_str());
  const ImuNoise kalibr = KalibrNoise(fit);
  std::printf(
      "imu.yaml: gyroscope_noise_density %s%.4e, gyroscope_random_walk %s%.4e, "
      "accelerometer_noise_density %s%.4e, accelerometer_random_walk %s%.4e\n",
      fit.gyro.white.measured ? "" : "<= ", kalibr.gyroscope_noise_density,
      fit.gyro.random_walk.measured ? "" : "<= ", kalibr.gyroscope_random_walk,
      fit.accel.white.measured ? "" : "<= ", kalibr.accelerometer_noise_density,
      fit.accel.random_walk.measured ? "" : "<= ", kalibr.accelerometer_random_walk);
  std::printf("wrote %s: report.md, report.json, imu.yaml, allan_deviation.csv\n%s\n",
              args.out.c_str(), out.ForUser(DescribeFigureOutcome(figures)).c_str());
}

}  // namespace

void RegisterImuNoise(CLI::App& app, int* exit_code) {
  auto* command = app.add_subcommand(
      "imu-noise",
      "IMU noise densities measured by Allan deviation (white noise, bias instability, random "
      "walk) -> Kalibr imu.yaml; needs a static log");
  auto args = std::make_shared<ImuNoiseArgs>();
  command
      ->add_option("input", args->input,
                   "ASL/EuRoC dataset folder (mav0/imu0/data.csv), IMU CSV, ROS1 bag or PX4 ULog")
      ->required();
  command->add_option("--topic", args->topic,
                      "IMU topic of a bag (sensor_msgs/Imu; default: the only one) or ULog "
                      "(default sensor_combined; vehicle_imu[:N])");
  command
      ->add_option("--out", args->out,
                   "Output folder: report.md, report.json, imu.yaml, allan_deviation.csv")
      ->required();
  command->add_option("--from", args->from_s, "Use samples from this many seconds after the first")
      ->check(FiniteNumber());
  command->add_option("--to", args->to_s, "Use samples up to this many seconds after the first")
      ->check(FiniteNumber());
  command->add_flag("--force", args->force, "Replace an existing --out folder (a mavloc report)");
  command->callback([args, exit_code] {
    RunImuNoise(*args);
    *exit_code = 0;
  });
}

}  // namespace mavloc::cli
