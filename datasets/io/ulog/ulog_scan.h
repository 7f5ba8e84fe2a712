// One pass over a ULog file: definitions (flag bits 'B', formats 'F', info 'I' / 'M', parameters
// 'P' / 'Q') and data (subscriptions 'A' / 'R', data 'D', logged strings 'L' / 'C', sync 'S',
// dropouts 'O'), including the appended-data segments the flag bits point to. Everything but the
// topic data goes into UlogInfo; the data of the topics a handler asks for is handed to it message
// by message and never stored here (spec: docs.px4.io/main/en/dev_log/ulog_file_format.html;
// behaviour on corrupt data follows pyulog's core.py: a data message of the wrong size or with an
// unknown msg_id is skipped, an impossible message header resynchronises at the next sync
// message).
#pragma once

#include <cstdint>
#include <string>

#include "datasets/io/ulog/ulog_format.h"
#include "datasets/io/ulog/ulog_reader.h"

namespace mavloc::ulog {

struct Subscription {
  std::string name;
  int multi_id = 0;
  int msg_id = 0;
  FlatLayout layout;
  uint64_t messages = 0;  // valid data messages so far
  uint64_t t_first_us = 0;
  uint64_t t_last_us = 0;
};

class ScanHandler {
 public:
  virtual ~ScanHandler() = default;
  // Called once per 'A' message; return true to receive this subscription's data.
  virtual bool WantsTopic(const Subscription& subscription) = 0;
  // One data message of a wanted subscription: `data` has subscription.layout.logged_size bytes
  // or more (the payload after the msg_id); `index` counts this subscription's messages from 0.
  virtual void OnData(const Subscription& subscription, const uint8_t* data, uint64_t index,
                      uint64_t file_offset) = 0;
};

// Scans `path`; `handler` and `progress` may be null / empty. Throws InputError as described in
// ulog_reader.h (not ULog, cut header or definitions, unknown incompatible flags, malformed
// definitions).
UlogInfo ScanUlog(const std::string& path, ScanHandler* handler, const UlogProgress& progress);

}  // namespace mavloc::ulog
