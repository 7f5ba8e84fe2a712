// ReadUlogInfo and the text layouts of pyulog's `ulog_info` and `ulog_messages` (pyulog info.py,
// messages.py), so that mavloc's listing can be compared line by line with pyulog's.
#include <fmt/format.h>

#include <algorithm>
#include <numeric>

#include "datasets/io/ulog/ulog_reader.h"
#include "datasets/io/ulog/ulog_scan.h"

namespace mavloc {
namespace {

// "H:MM:SS" of whole seconds, as pyulog prints times (divmod of int(t / 1e6)).
std::string HoursMinutesSeconds(uint64_t t_us) {
  const uint64_t s = t_us / 1000000;
  return fmt::format("{:d}:{:02d}:{:02d}", s / 3600, (s / 60) % 60, s % 60);
}

std::string LogLevelName(int level) {
  switch (level) {
    case '0':
      return "EMERGENCY";
    case '1':
      return "ALERT";
    case '2':
      return "CRITICAL";
    case '3':
      return "ERROR";
    case '4':
      return "WARNING";
    case '5':
      return "NOTICE";
    case '6':
      return "INFO";
    case '7':
      return "DEBUG";
    default:
      return "UNKNOWN";
  }
}

}  // namespace

UlogInfo ReadUlogInfo(const std::string& path) { return ulog::ScanUlog(path, nullptr, {}); }

std::string FormatUlogInfoTimeAndDropouts(const UlogInfo& info) {
  const uint64_t duration_us =
      info.t_last_us > info.t_start_us ? info.t_last_us - info.t_start_us : 0;
  std::string out =
      fmt::format("Logging start time: {}, duration: {}\n", HoursMinutesSeconds(info.t_start_us),
                  HoursMinutesSeconds(duration_us));
  if (info.dropouts_ms.empty()) {
    out += "No Dropouts\n";
  } else {
    const int64_t total_ms =
        std::accumulate(info.dropouts_ms.begin(), info.dropouts_ms.end(), int64_t{0});
    const int max_ms = *std::max_element(info.dropouts_ms.begin(), info.dropouts_ms.end());
    const int64_t mean_ms = total_ms / static_cast<int64_t>(info.dropouts_ms.size());
    out += fmt::format("Dropouts: count: {}, total duration: {:.1f} s, max: {} ms, mean: {} ms\n",
                       info.dropouts_ms.size(), static_cast<double>(total_ms) / 1000.0, max_ms,
                       mean_ms);
  }
  return out;
}

std::string FormatUlogInfoTopicTable(const UlogInfo& info) {
  std::string out = fmt::format("{:<41} {:7}, {:10}\n", "Name (multi id, message size in bytes)",
                                "number of data points", "total bytes");
  for (const UlogTopicInfo& topic : info.topics) {
    const std::string name_id =
        fmt::format("{} ({}, {})", topic.name, topic.multi_id, topic.message_size);
    out += fmt::format(" {:<40} {:7d} {:10d}\n", name_id, topic.messages,
                       topic.messages * static_cast<uint64_t>(topic.message_size));
  }
  return out;
}

std::string FormatUlogLoggedStrings(const UlogInfo& info) {
  // pyulog's ulog_messages prints the 'L' strings; on PX4 logs it drops those ending in a tab
  // (duplicates of events). Events ('event' topic) are not decoded here.
  const auto sys_name = info.info.find("sys_name");
  const bool px4 = sys_name != info.info.end() && sys_name->second == "PX4";
  std::string out;
  for (const UlogLoggedString& s : info.logged_strings) {
    if (s.tag >= 0) continue;
    if (px4 && !s.message.empty() && s.message.back() == '\t') continue;
    out += fmt::format("{} {}: {}\n", HoursMinutesSeconds(s.t_us), LogLevelName(s.log_level),
                       s.message);
  }
  return out;
}

}  // namespace mavloc
