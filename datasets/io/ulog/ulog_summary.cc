// SummarizeUlog: the ULog side of mavloc's log summary (datasets/io/log_reader.h).
#include <fmt/format.h>

#include <algorithm>
#include <numeric>

#include "datasets/io/ulog/ulog_reader.h"

namespace mavloc {

LogSummary SummarizeUlog(const std::string& path) {
  const UlogInfo info = ReadUlogInfo(path);
  LogSummary summary;
  summary.path = path;
  summary.format = LogFormat::kUlog;
  summary.t_start_ns = static_cast<TimeNs>(info.t_start_us) * 1000;
  summary.t_end_ns = static_cast<TimeNs>(info.t_last_us) * 1000;
  for (const UlogTopicInfo& topic : info.topics) {
    LogTopicSummary t;
    t.topic = topic.name;
    t.type = topic.name;  // a ULog topic's message format carries the topic's name
    t.instance = topic.multi_id;
    t.messages = topic.messages;
    t.t_first_ns = static_cast<TimeNs>(topic.t_first_us) * 1000;
    t.t_last_ns = static_cast<TimeNs>(topic.t_last_us) * 1000;
    summary.topics.push_back(std::move(t));
  }
  std::sort(summary.topics.begin(), summary.topics.end(),
            [](const LogTopicSummary& a, const LogTopicSummary& b) {
              return a.topic != b.topic ? a.topic < b.topic : a.instance < b.instance;
            });
  if (!info.dropouts_ms.empty()) {
    const int64_t total_ms =
        std::accumulate(info.dropouts_ms.begin(), info.dropouts_ms.end(), int64_t{0});
    summary.notes.push_back(
        fmt::format("dropouts: count {}, total {} ms, max {} ms", info.dropouts_ms.size(), total_ms,
                    *std::max_element(info.dropouts_ms.begin(), info.dropouts_ms.end())));
  }
  for (const std::string& note : info.notes) summary.notes.push_back(note);
  return summary;
}

}  // namespace mavloc
