// mavloc imu-noise: IMU noise parameters measured from a log by overlapping Allan deviation
// (evaluation/imu_noise/: allan_deviation.h for the curves, noise_fit.h for white noise, bias
// instability and random walk). Input: an ASL/EuRoC dataset folder (mav0/imu0/data.csv), an IMU CSV
// with EuRoC's columns, a ROS1 bag or a PX4 ULog file (format from the file's first bytes,
// datasets/io/log_reader.h). Writes DIR/imu.yaml (Kalibr's keys), DIR/allan_deviation.csv and
// the report (report.md, report.json) into a staged folder (cli/output_folder.h) and prints the
// table. The log is streamed twice (evaluation/imu_noise/allan_streaming.h: the sampling check and
// the means, then the curves), never held: memory is bounded by --max-tau, not by the log's
// length. docs/commands/imu-noise.md.
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
#include "evaluation/imu_noise/allan_deviation.h"
#include "evaluation/imu_noise/allan_streaming.h"
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
  double max_tau_s = kImuNoiseDefaultMaxTau_s;
  bool force = false;
};

using ImuVisitor = std::function<void(const ImuSample&)>;

struct ImuNoiseInput {
  // One pass over the input's IMU samples, in file order; `notes` (when not null) gets what the
  // ULog reader dropped.
  std::function<void(const ImuVisitor& visit, std::vector<std::string>* notes)> read;
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

ImuNoiseInput OpenImuNoiseInput(const ImuNoiseArgs& args) {
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
    input.read = [path = input.source](const ImuVisitor& visit, std::vector<std::string>*) {
      ForEachImuCsvSample(path, visit);
    };
    return input;
  }
  if (!fs::exists(args.input)) throw InputError(args.input, 0, "", "does not exist");
  const auto format = DetectLogFormat(args.input);
  if (!format) {  // an IMU CSV (EuRoC imu0 columns; yac/Kalibr "#ts,wx,...")
    no_topic("an IMU CSV file");
    input.source = args.input;
    input.read = [path = args.input](const ImuVisitor& visit, std::vector<std::string>*) {
      ForEachImuCsvSample(path, visit);
    };
    return input;
  }
  const std::string topic =
      args.topic.empty() ? ImuNoiseDefaultTopic(args.input, *format) : args.topic;
  input.source = args.input + ":" + topic;
  if (*format == LogFormat::kRosbag) input.rostopic = topic;
  input.read = [path = args.input, topic](const ImuVisitor& visit,
                                          std::vector<std::string>* notes) {
    ForEachLogImuSample(path, topic, visit, notes);
  };
  return input;
}

// What a pass over the input saw: all samples, and those within [from_s, to_s] seconds of the
// first one.
struct ImuNoiseWindow {
  size_t samples = 0, kept = 0;
  TimeNs first_ns = 0, last_ns = 0;
};

// The samples of the --from/--to window, one pass per call; *window describes the last pass and
// input->notes gets its notes.
ImuSamplePass WindowedPass(const ImuNoiseArgs& args, ImuNoiseInput* input, ImuNoiseWindow* window) {
  return [&args, input, window](const ImuVisitor& visit) {
    *window = {};
    input->notes.clear();
    input->read(
        [&](const ImuSample& s) {
          if (window->samples++ == 0) window->first_ns = s.t_ns;
          window->last_ns = s.t_ns;
          const double t_s = NsToSeconds(s.t_ns - window->first_ns);
          if (t_s < args.from_s || t_s > args.to_s) return;
          ++window->kept;
          visit(s);
        },
        &input->notes);
  };
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
  if (!(args.max_tau_s > 0.0))
    throw InputError(fmt::format("--max-tau {}: must be > 0 (seconds)", args.max_tau_s));
  // The output folder is checked before any work and written whole (cli/output_folder.h).
  StagedFolder out(args.out, FolderKind::kReport, args.force);
  ImuNoiseInput input = OpenImuNoiseInput(args);
  ImuNoiseWindow window;
  int pass = 0;
  const ImuSamplePass windowed = WindowedPass(args, &input, &window);
  AllanOptions options;
  options.max_tau_s = args.max_tau_s;
  const ImuAllanDeviation curves = ComputeImuAllanDeviationStreaming(
      [&](const ImuVisitor& visit) {
        ReportProgress("imu-noise", ++pass == 1 ? "reading " + input.source +
                                                      " (pass 1 of 2: sampling check and means)"
                                                : fmt::format("pass 2 of 2: Allan deviation of "
                                                              "{} samples",
                                                              window.kept));
        windowed(visit);
      },
      options);
  if (window.samples == 0) throw InputError(input.source, 0, "", "holds no IMU samples");
  if (window.kept == 0)
    throw InputError(
        input.source, 0, "--from/--to",
        fmt::format("no sample between {} s and {} s (the stream is {:.3f} s long)", args.from_s,
                    args.to_s, NsToSeconds(window.last_ns - window.first_ns)));
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
      if (points.size() < 2)
        throw InputError(
            input.source, 0, "--max-tau",
            fmt::format("{} s leaves {} cluster size(s) at {:.3f} Hz: the curve needs at least two "
                        "(raise --max-tau)",
                        args.max_tau_s, points.size(), curves.sampling.rate_hz));
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
      ->check(OutputFolder())
      ->required();
  command->add_option("--from", args->from_s, "Use samples from this many seconds after the first")
      ->check(FiniteNumber());
  command->add_option("--to", args->to_s, "Use samples up to this many seconds after the first")
      ->check(FiniteNumber());
  command
      ->add_option("--max-tau", args->max_tau_s,
                   fmt::format("Longest cluster time [s] (default {:g}; also at most a quarter of "
                               "the log): memory is about 96 bytes x rate x this",
                               kImuNoiseDefaultMaxTau_s))
      ->check(FiniteNumber());
  command->add_flag("--force", args->force, "Replace an existing --out folder (a mavloc report)");
  command->callback([args, exit_code] {
    RunImuNoise(*args);
    *exit_code = 0;
  });
}

}  // namespace mavloc::cli
