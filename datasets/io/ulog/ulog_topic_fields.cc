#include "datasets/io/ulog/ulog_topic_fields.h"

#include <fmt/format.h>

#include <cmath>
#include <limits>
#include <map>

#include "core/errors.h"
#include "core/physical_limits.h"
#include "datasets/io/ulog/ulog_scan.h"

namespace mavloc::ulog {
namespace {

class FieldCollector : public ScanHandler {
 public:
  FieldCollector(const std::string& path, const std::string& topic, const TopicSelector& selector,
                 const std::vector<FieldRequest>& requests, const TopicRowCallback& on_row)
      : path_(path),
        topic_(topic),
        selector_(selector),
        requests_(requests),
        on_row_(on_row),
        present_(requests.size(), false),
        row_(requests.size()) {}

  bool WantsTopic(const Subscription& sub) override {
    if (sub.name != selector_.name || sub.multi_id != selector_.multi_id) return false;
    std::vector<const FlatField*>& resolved = resolved_[&sub];
    resolved.clear();
    for (size_t i = 0; i < requests_.size(); ++i) {
      const FlatField* field = sub.layout.Find(requests_[i].name);
      if (field == nullptr && requests_[i].required) {
        throw InputError(path_, 0, requests_[i].name,
                         fmt::format("topic '{}' has no field '{}' (its fields: {})", topic_,
                                     requests_[i].name, FieldList(sub.layout)));
      }
      resolved.push_back(field);
      // Present when every subscription of this instance has it.
      if (!matched_) present_[i] = field != nullptr;
      if (field == nullptr) present_[i] = false;
    }
    matched_ = true;
    return true;
  }

  void OnData(const Subscription& sub, const uint8_t* data, uint64_t /*index*/,
              uint64_t /*file_offset*/) override {
    const std::vector<const FlatField*>& resolved = resolved_[&sub];
    const uint64_t t_us =
        sub.layout.timestamp_offset >= 0 ? ReadUint64(data + sub.layout.timestamp_offset) : 0;
    for (size_t i = 0; i < resolved.size(); ++i) {
      row_[i] = resolved[i] != nullptr ? ReadFieldAsDouble(data, *resolved[i])
                                       : std::numeric_limits<double>::quiet_NaN();
    }
    on_row_(t_us, row_.data());
    ++rows_;
  }

  bool matched() const { return matched_; }
  uint64_t rows() const { return rows_; }
  const std::vector<bool>& present() const { return present_; }

 private:
  static std::string FieldList(const FlatLayout& layout) {
    std::string list;
    for (const FlatField& f : layout.fields) {
      if (f.name.rfind("_padding", 0) == 0) continue;
      list += fmt::format("{}{}", list.empty() ? "" : ", ", f.name);
    }
    return list;
  }

  const std::string& path_;
  const std::string& topic_;
  TopicSelector selector_;
  const std::vector<FieldRequest>& requests_;
  const TopicRowCallback& on_row_;
  std::vector<bool> present_;
  std::vector<double> row_;
  uint64_t rows_ = 0;
  bool matched_ = false;
  std::map<const Subscription*, std::vector<const FlatField*>> resolved_;
};

}  // namespace

TopicSelector ParseTopicSelector(const std::string& path, const std::string& topic) {
  TopicSelector selector;
  selector.name = topic;
  const size_t dot = topic.rfind('.');
  if (dot == std::string::npos) return selector;
  const std::string suffix = topic.substr(dot + 1);
  if (dot == 0 || suffix.empty() || suffix.size() > 3 ||
      suffix.find_first_not_of("0123456789") != std::string::npos || std::stoi(suffix) > 255) {
    throw InputError(path, 0, topic,
                     "a ULog topic is 'name' or 'name.N' with N the instance (multi_id 0..255)");
  }
  selector.name = topic.substr(0, dot);
  selector.multi_id = std::stoi(suffix);
  return selector;
}

std::vector<bool> ForEachTopicRow(const std::string& path, const std::string& topic,
                                  const std::vector<FieldRequest>& fields,
                                  const UlogProgress& progress, const TopicRowCallback& on_row,
                                  std::vector<std::string>* scan_notes) {
  const TopicSelector selector = ParseTopicSelector(path, topic);
  FieldCollector collector(path, topic, selector, fields, on_row);
  const UlogInfo info = ScanUlog(path, &collector, progress);
  if (!collector.matched() || collector.rows() == 0) {
    std::string available;
    for (const UlogTopicInfo& t : info.topics) {
      available += fmt::format("{}{}", available.empty() ? "" : ", ", t.name);
      if (t.multi_id > 0) available += fmt::format(".{}", t.multi_id);
    }
    throw InputError(
        path, 0, topic,
        fmt::format("{} in this log (topics with data: {})",
                    collector.matched() ? "the topic has no data messages" : "no such topic",
                    available.empty() ? "none" : available));
  }
  if (scan_notes != nullptr)
    scan_notes->insert(scan_notes->end(), info.notes.begin(), info.notes.end());
  return collector.present();
}

TopicTable ReadTopicFields(const std::string& path, const std::string& topic,
                           const std::vector<FieldRequest>& fields, const UlogProgress& progress,
                           std::vector<std::string>* scan_notes) {
  TopicTable table;
  table.topic = topic;
  for (const FieldRequest& f : fields) table.fields.push_back(f.name);
  table.present = ForEachTopicRow(
      path, topic, fields, progress,
      [&table](uint64_t t_us, const double* values) {
        table.t_us.push_back(t_us);
        table.values.insert(table.values.end(), values, values + table.fields.size());
      },
      scan_notes);
  return table;
}

void DroppedMessages::Add(const std::string& reason, uint64_t index) {
  for (Count& c : counts_) {
    if (c.reason == reason) {
      ++c.count;
      return;
    }
  }
  counts_.push_back({reason, 1, index});
}

bool DroppedMessages::DropNotIncreasing(int64_t t_ns, std::optional<int64_t> previous_ns,
                                        uint64_t index) {
  if (!previous_ns || t_ns > *previous_ns) return false;
  Add(t_ns == *previous_ns ? "with a repeated stamp (the first kept)"
                           : "with a stamp earlier than the previous message (out of order)",
      index);
  return true;
}

void DroppedMessages::AppendNotes(const std::string& topic, std::vector<std::string>* notes) const {
  if (notes == nullptr) return;
  for (const Count& c : counts_) {
    notes->push_back(fmt::format("{}: {} message(s) {} dropped (first: message {})", topic, c.count,
                                 c.reason, c.first_index));
  }
}

void RequireWithin(const std::string& path, const std::string& topic, uint64_t index,
                   const std::string& field, double value, double max_abs,
                   const std::string& unit) {
  if (std::isnan(value) || std::isinf(value)) {
    throw InputError(path, 0, field,
                     fmt::format("topic {}, message {}: {} is not finite", topic, index, value));
  }
  if (!(std::abs(value) <= max_abs)) {
    throw InputError(path, 0, field,
                     fmt::format("topic {}, message {}: {:g} {} is outside {}", topic, index, value,
                                 unit, limits::RangeText(-max_abs, max_abs, unit)));
  }
}

}  // namespace mavloc::ulog
