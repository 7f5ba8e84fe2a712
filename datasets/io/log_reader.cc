#include "datasets/io/log_reader.h"

#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

#include "core/errors.h"
#include "core/number_text.h"
#include "core/progress.h"
#include "datasets/io/rosbag/rosbag_reader.h"
#include "datasets/io/ulog/ulog_reader.h"

namespace mavloc {

namespace {

// ROS bag format 2.0 starts with the version line "#ROSBAG V2.0\n"; ULog with the magic
// "ULog" 0x01 0x12 0x35 (PX4 ULog file format, "File Header"). A whole-file bzip2 of a bag
// ("BZh") is a bag too: the bag reader decompresses it.
std::optional<LogFormat> FormatFromMagic(const std::string& head) {
  if (head.rfind("#ROSBAG V2.0", 0) == 0) return LogFormat::kRosbag;
  if (head.size() >= 7 && head.compare(0, 4, "ULog") == 0 && head[4] == '\x01' &&
      head[5] == '\x12' && head[6] == '\x35')
    return LogFormat::kUlog;
  if (head.rfind("BZh", 0) == 0) return LogFormat::kRosbag;
  return std::nullopt;
}

// "a:b::c" -> {"a", "b", "", "c"}: empty items kept, so that a missing frame name is reported.
std::vector<std::string> SplitColons(const std::string& text) {
  std::vector<std::string> parts;
  size_t begin = 0;
  for (size_t colon = text.find(':'); colon != std::string::npos; colon = text.find(':', begin)) {
    parts.push_back(text.substr(begin, colon - begin));
    begin = colon + 1;
  }
  parts.push_back(text.substr(begin));
  return parts;
}

// A progress line on stderr about every 64 MiB of a ULog file (the reader calls back).
UlogProgress UlogProgressLine(const std::string& path) {
  return [path](uint64_t bytes_done, uint64_t bytes_total) {
    ReportProgress(
        "ulog", fmt::format("{}: {:.0f} of {:.0f} MB", path, bytes_done / 1e6, bytes_total / 1e6));
  };
}

int ParseInstance(const std::string& spec, const std::string& text) {
  const ParsedNumber<long long> value = ParseIntegerText(text);
  if (!value.ok() || value.value < 0 || value.value > 255)
    throw InputError(spec, 0, "instance",
                     "'" + text + "' is not a ULog multi-instance index (0..255)");
  return static_cast<int>(value.value);
}

}  // namespace

std::optional<LogFormat> DetectLogFormat(const std::string& path) {
  std::error_code error;
  if (!std::filesystem::is_regular_file(path, error)) return std::nullopt;
  std::ifstream in(path, std::ios::binary);
  if (!in) return std::nullopt;
  std::string head(16, '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<size_t>(in.gcount()));
  return FormatFromMagic(head);
}

std::optional<LogTopicSpec> ParseLogTopicSpec(const std::string& spec) {
  // The path is the shortest prefix before a ':' that is a log file: topic names hold no path.
  for (size_t colon = spec.find(':'); colon != std::string::npos;
       colon = spec.find(':', colon + 1)) {
    const std::string path = spec.substr(0, colon);
    const auto format = DetectLogFormat(path);
    if (!format) continue;
    LogTopicSpec result;
    result.path = path;
    const auto parts = SplitColons(spec.substr(colon + 1));
    if (parts.empty() || parts[0].empty())
      throw InputError(spec, 0, "topic", "no topic after '" + path + ":'");
    result.topic = parts[0];
    if (*format == LogFormat::kUlog) {
      if (parts.size() > 2)
        throw InputError(spec, 0, "topic", "expected LOG.ulg:TOPIC or LOG.ulg:TOPIC:INSTANCE");
      if (parts.size() == 2) result.instance = ParseInstance(spec, parts[1]);
    } else {
      if (parts.size() != 1 && parts.size() != 3)
        throw InputError(spec, 0, "topic",
                         "expected LOG.bag:TOPIC or LOG.bag:/tf:PARENT_FRAME:CHILD_FRAME");
      if (parts.size() == 3) {
        result.tf_parent = parts[1];
        result.tf_child = parts[2];
        if (result.tf_parent.empty() || result.tf_child.empty())
          throw InputError(spec, 0, "topic", "empty tf frame name");
      }
    }
    return result;
  }
  return std::nullopt;
}

LogSummary SummarizeLog(const std::string& path) {
  const auto format = DetectLogFormat(path);
  if (!format)
    throw InputError(path, 0, "",
                     std::filesystem::exists(path)
                         ? "not a ROS1 bag (#ROSBAG V2.0) or PX4 ULog file (magic 'ULog')"
                         : "file does not exist");
  return *format == LogFormat::kRosbag ? SummarizeRosbag(path) : SummarizeUlog(path);
}

std::vector<ImuSample> ReadLogImu(const std::string& path, const std::string& topic) {
  std::vector<ImuSample> samples;
  ForEachLogImuSample(path, topic, [&samples](const ImuSample& s) { samples.push_back(s); });
  return samples;
}

void ForEachLogImuSample(const std::string& path, const std::string& topic,
                         const std::function<void(const ImuSample&)>& visit,
                         std::vector<std::string>* notes) {
  const auto format = DetectLogFormat(path);
  if (!format) throw InputError(path, 0, "", "not a ROS1 bag or PX4 ULog file");
  if (*format == LogFormat::kRosbag) return ForEachRosbagImuSample(path, topic, visit);
  // "vehicle_imu:1" (the LOG:TOPIC:INSTANCE form) is the ULog reader's "vehicle_imu.1".
  std::string ulog_topic = topic;
  if (const size_t colon = ulog_topic.rfind(':'); colon != std::string::npos)
    ulog_topic[colon] = '.';
  ForEachUlogImuSample(path, ulog_topic, visit, UlogProgressLine(path), notes);
}

LogTrajectory ReadLogTrajectory(const LogTopicSpec& spec) {
  const auto format = DetectLogFormat(spec.path);
  if (!format) throw InputError(spec.path, 0, "", "not a ROS1 bag or PX4 ULog file");
  if (*format == LogFormat::kRosbag) return ReadRosbagTrajectory(spec);
  // The ULog reader names later instances of a multi-instance topic "name.N".
  LogTopicSpec ulog = spec;
  if (spec.instance > 0) ulog.topic += "." + std::to_string(spec.instance);
  std::vector<std::string> notes;
  LogTrajectory trajectory = ReadUlogTrajectory(ulog, UlogProgressLine(spec.path), &notes);
  for (std::string& note : notes)  // the reader may repeat a scan note; keep each once
    if (std::find(trajectory.notes.begin(), trajectory.notes.end(), note) == trajectory.notes.end())
      trajectory.notes.push_back(std::move(note));
  return trajectory;
}

}  // namespace mavloc
