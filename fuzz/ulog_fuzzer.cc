// libFuzzer target for the PX4 ULog reader (datasets/io/ulog/ulog_reader.h): the input is a ULog
// file; its info (and pyulog-style listings) and summary are read, then every topic is read as
// IMU samples and as a trajectory, each refusing what it cannot read with an InputError.
#include <cstddef>
#include <cstdint>
#include <string>

#include "datasets/io/log_reader.h"
#include "datasets/io/ulog/ulog_reader.h"
#include "fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = mavloc::fuzz::WriteScratchFile("log.ulg", data, size);
  mavloc::fuzz::ExpectInputErrorOnly([&path] {
    const mavloc::UlogInfo info = mavloc::ReadUlogInfo(path);
    (void)mavloc::FormatUlogInfoTopicTable(info);
    (void)mavloc::FormatUlogInfoTimeAndDropouts(info);
    (void)mavloc::FormatUlogLoggedStrings(info);
  });
  mavloc::LogSummary summary;
  bool summarized = false;
  mavloc::fuzz::ExpectInputErrorOnly([&] {
    summary = mavloc::SummarizeUlog(path);
    summarized = true;
  });
  if (!summarized) return 0;
  for (const mavloc::LogTopicSummary& topic : summary.topics) {
    const std::string name =
        topic.instance > 0 ? topic.topic + "." + std::to_string(topic.instance) : topic.topic;
    mavloc::fuzz::ExpectInputErrorOnly([&] { (void)mavloc::ReadUlogImu(path, name); });
    mavloc::fuzz::ExpectInputErrorOnly([&] {
      mavloc::LogTopicSpec spec;
      spec.path = path;
      spec.topic = topic.topic;
      spec.instance = topic.instance;
      (void)mavloc::ReadUlogTrajectory(spec);
    });
  }
  return 0;
}
