// The requested fields of one ULog topic instance, read in one streaming pass: only these values
// are kept (memory grows with the topic's message count times the number of fields, not with the
// log's size).
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "datasets/io/ulog/ulog_reader.h"

namespace mavloc::ulog {

// "sensor_combined" (multi_id 0) or "vehicle_imu.1" (multi_id 1); see ulog_reader.h.
struct TopicSelector {
  std::string name;
  int multi_id = 0;
};
// Throws InputError (naming `path`) on a malformed instance suffix.
TopicSelector ParseTopicSelector(const std::string& path, const std::string& topic);

struct FieldRequest {
  std::string name;  // flattened name as in ulog_format.h: "q[0]", "timestamp_sample"
  bool required = true;
};

struct TopicTable {
  std::string topic;  // as selected ("vehicle_imu.1")
  std::vector<std::string> fields;
  std::vector<bool> present;   // per field: in the topic's format
  std::vector<uint64_t> t_us;  // the message's "timestamp" field
  std::vector<double> values;  // row-major, fields.size() per message; NaN when not present

  size_t rows() const { return t_us.size(); }
  double at(size_t row, size_t field) const { return values[row * fields.size() + field]; }
  bool has(size_t field) const { return present[field]; }
};

// Throws InputError naming the file and the topic when the topic instance is not in the log (the
// message lists the log's topics), has no data messages, or lacks a required field. When
// `scan_notes` is not null, the scan's notes (UlogInfo::notes: truncation, corrupt messages) are
// appended to it.
TopicTable ReadTopicFields(const std::string& path, const std::string& topic,
                           const std::vector<FieldRequest>& fields, const UlogProgress& progress,
                           std::vector<std::string>* scan_notes = nullptr);

// The streaming form: `on_row` gets each message's timestamp and its requested values (NaN for
// absent fields) as they are read, so nothing of the topic is kept here. Returns per field
// whether the topic has it; throws as ReadTopicFields.
using TopicRowCallback = std::function<void(uint64_t t_us, const double* values)>;
std::vector<bool> ForEachTopicRow(const std::string& path, const std::string& topic,
                                  const std::vector<FieldRequest>& fields,
                                  const UlogProgress& progress, const TopicRowCallback& on_row,
                                  std::vector<std::string>* scan_notes = nullptr);

// Messages a reader drops rather than refuses (PX4's own invalid markers, corrupt stamps, stamps
// not after the previous message), counted per reason so the user gets one note per reason:
// "sensor_combined: 3 message(s) with a repeated stamp dropped (first: message 10)".
class DroppedMessages {
 public:
  void Add(const std::string& reason, uint64_t index);
  // A stamp equal to or earlier than the previous kept one: Add()s the reason and returns true.
  bool DropNotIncreasing(int64_t t_ns, std::optional<int64_t> previous_ns, uint64_t index);
  void AppendNotes(const std::string& topic, std::vector<std::string>* notes) const;

 private:
  struct Count {
    std::string reason;
    uint64_t count = 0;
    uint64_t first_index = 0;
  };
  std::vector<Count> counts_;  // in the order of each reason's first drop
};

// Refuses a finite value no MAV logs, or a non-finite one: InputError naming the file, the field
// and the topic's message index ("topic sensor_combined, message 10: 3e+38 rad/s is outside
// [-100, 100] rad/s (sanity range, core/physical_limits.h)").
void RequireWithin(const std::string& path, const std::string& topic, uint64_t index,
                   const std::string& field, double value, double max_abs, const std::string& unit);

}  // namespace mavloc::ulog
