#include "datasets/io/ulog/ulog_scan.h"

#include <fmt/format.h>

#include <algorithm>
#include <cstring>
#include <map>
#include <memory>
#include <set>

#include "core/errors.h"
#include "core/input_limits.h"
#include "datasets/io/ulog/ulog_stream.h"

namespace mavloc::ulog {
namespace {

// Flag bits message: compat_flags[8], incompat_flags[8], appended_offsets[3] (uint64).
constexpr int kFlagBitsBytes = 8 + 8 + 3 * 8;
constexpr uint8_t kIncompatDataAppended = 0x1;
// pyulog's test for a corrupt message header (core.py, _check_packet_corruption).
constexpr int kMaxPlausibleUnknownSize = 10000;
constexpr uint64_t kProgressStepBytes = 64ull << 20;

std::string TypeName(char type) {
  if (type >= 0x20 && type < 0x7f) return fmt::format("'{}'", type);
  return fmt::format("0x{:02x}", static_cast<unsigned>(static_cast<uint8_t>(type)));
}

// "type name" key and its value bytes, as in 'I', 'P' and (after their leading bytes) 'M', 'Q'.
struct KeyValue {
  std::string type;
  std::string key;
  const uint8_t* value = nullptr;
  int value_size = 0;
};

bool ParseKeyValue(const uint8_t* data, int size, KeyValue* kv) {
  if (size < 1) return false;
  const int key_len = data[0];
  if (1 + key_len > size) return false;
  const std::string type_key(reinterpret_cast<const char*>(data + 1), key_len);
  const size_t space = type_key.find(' ');
  if (space == std::string::npos) return false;
  kv->type = type_key.substr(0, space);
  kv->key = type_key.substr(space + 1);
  kv->value = data + 1 + key_len;
  kv->value_size = size - 1 - key_len;
  return true;
}

std::string ValueAsText(const KeyValue& kv) {
  if (kv.type.rfind("char[", 0) == 0) {
    return std::string(reinterpret_cast<const char*>(kv.value), kv.value_size);
  }
  PrimitiveType type;
  if (ParsePrimitiveType(kv.type, &type) && PrimitiveSize(type) == kv.value_size) {
    const FlatField field{"", type, 0};
    const double v = ReadFieldAsDouble(kv.value, field);
    if (type == PrimitiveType::kFloat || type == PrimitiveType::kDouble)
      return fmt::format("{}", v);
    if (type == PrimitiveType::kUint64) return std::to_string(ReadUint64(kv.value));
    return fmt::format("{}", static_cast<int64_t>(v));
  }
  return fmt::format("<{} bytes>", kv.value_size);
}

class Scanner {
 public:
  Scanner(const std::string& path, ScanHandler* handler, const UlogProgress& progress)
      : path_(path), stream_(path), handler_(handler), progress_(progress) {
    info_.path = path;
    info_.version = stream_.version();
    info_.t_start_us = stream_.header_timestamp_us();
    info_.t_last_us = info_.t_start_us;
    info_.file_bytes = stream_.file_bytes();
    if (!StampNs(info_.t_start_us))
      Fail(8, fmt::format("header timestamp {} us is not a time since boot", info_.t_start_us));
  }

  UlogInfo Run() {
    ReadDefinitions();
    if (info_.data_appended && !info_.appended_offsets.empty()) {
      // As pyulog (core.py, _load_file): each segment is read up to the next appended offset,
      // then reading resumes exactly at that offset.
      for (const uint64_t offset : info_.appended_offsets) {
        stream_.SetReadLimit(offset);
        ReadData();
        if (offset > info_.file_bytes) {
          info_.notes.push_back(fmt::format(
              "appended data: the flag bits point to byte offset {} but the file has {} bytes",
              offset, info_.file_bytes));
          break;
        }
        stream_.Seek(offset);
      }
      stream_.SetReadLimit(UINT64_MAX);
    }
    ReadData();
    Finish();
    return std::move(info_);
  }

 private:
  [[noreturn]] void Fail(uint64_t offset, const std::string& message) const {
    throw InputError(path_, 0, "", fmt::format("byte offset {}: {}", offset, message));
  }

  void Progress() {
    if (progress_ && stream_.offset() >= next_progress_) {
      progress_(stream_.offset(), info_.file_bytes);
      next_progress_ = stream_.offset() + kProgressStepBytes;
    }
  }

  void NotePartial() {
    const uint64_t at = stream_.partial_offset();
    const uint64_t have = info_.file_bytes > at ? info_.file_bytes - at : 0;
    const std::string what =
        stream_.partial_declared_size() < 0
            ? fmt::format("{} of its 3 header bytes", have)
            : fmt::format("{} of its {} bytes", have, 3 + stream_.partial_declared_size());
    info_.notes.push_back(fmt::format(
        "truncated: the last message (byte offset {}) is cut short ({} present) and was "
        "ignored; the log ends abruptly (e.g. power loss or a crash while logging)",
        at, what));
  }

  static bool StartsDataSection(char type) {
    return type == 'A' || type == 'L' || type == 'C' || type == 'D' || type == 'O' || type == 'S' ||
           type == 'R';
  }

  void ReadDefinitions() {
    RawMessage m;
    while (true) {
      const uint64_t before = stream_.offset();
      if (!stream_.Next(&m)) {
        if (stream_.partial()) {
          Fail(stream_.partial_offset(),
               fmt::format("truncated in the definitions section: the message is cut short "
                           "(file size {} bytes)",
                           info_.file_bytes));
        }
        return;
      }
      if (StartsDataSection(m.type)) {
        stream_.Seek(before);
        return;
      }
      if (m.type == 'B') {
        OnFlagBits(m);
      } else if (!OnDefinitionOrInfo(m)) {
        if (IsCorruptHeader(m)) {
          Fail(m.offset, fmt::format("corrupt message header in the definitions section "
                                     "(type {}, size {})",
                                     TypeName(m.type), m.size));
        }
        NoteUnknownType(m);
      }
    }
  }

  static bool IsCorruptHeader(const RawMessage& m) {
    return m.type == 0 || m.size == 0 || m.size > kMaxPlausibleUnknownSize;
  }

  void NoteUnknownType(const RawMessage& m) {
    if (unknown_types_.insert(m.type).second) {
      info_.notes.push_back(
          fmt::format("skipped message(s) of unknown type {} (first at byte "
                      "offset {})",
                      TypeName(m.type), m.offset));
    }
  }

  void OnFlagBits(const RawMessage& m) {
    if (m.offset != kHeaderBytes) {
      info_.notes.push_back(
          fmt::format("flag bits message at byte offset {} is not the first message", m.offset));
    }
    if (m.size < kFlagBitsBytes) {
      Fail(m.offset,
           fmt::format("flag bits message has {} bytes, expected {}", m.size, kFlagBitsBytes));
    }
    const uint8_t* incompat = m.data + 8;
    if ((incompat[0] & ~kIncompatDataAppended) != 0 ||
        std::any_of(incompat + 1, incompat + 8, [](uint8_t b) { return b != 0; })) {
      Fail(m.offset, "unknown incompatible flag bits set: this ULog version cannot be parsed");
    }
    info_.data_appended = (incompat[0] & kIncompatDataAppended) != 0;
    info_.appended_offsets.clear();
    for (int i = 0; i < 3; ++i) {
      const uint64_t offset = ReadUint64(m.data + 16 + 8 * i);
      if (offset != 0) info_.appended_offsets.push_back(offset);
    }
    if (info_.data_appended) {
      std::string offsets;
      for (const uint64_t o : info_.appended_offsets) {
        offsets += fmt::format("{}{}", offsets.empty() ? "" : ", ", o);
      }
      info_.notes.push_back(fmt::format("appended data (flag DATA_APPENDED) at byte offset(s) {}",
                                        offsets.empty() ? std::string("unknown") : offsets));
    }
  }

  // 'F', 'I', 'M', 'P', 'Q' (valid in both sections). Returns false for other types.
  bool OnDefinitionOrInfo(const RawMessage& m) {
    KeyValue kv;
    switch (m.type) {
      case 'F': {
        MessageFormat format;
        std::string error;
        if (!ParseMessageFormat(std::string_view(reinterpret_cast<const char*>(m.data), m.size),
                                &format, &error)) {
          Fail(m.offset, fmt::format("malformed format message: {}", error));
        }
        formats_[format.name] = std::move(format);
        return true;
      }
      case 'I':
        if (!ParseKeyValue(m.data, m.size, &kv)) Fail(m.offset, "malformed info message");
        info_.info[kv.key] = ValueAsText(kv);
        return true;
      case 'M':
        // is_continued byte, then key and value. Multi-info (e.g. crash dumps) is not kept.
        if (m.size < 1 || !ParseKeyValue(m.data + 1, m.size - 1, &kv)) {
          Fail(m.offset, "malformed multi-info message");
        }
        return true;
      case 'P':
        if (!ParseKeyValue(m.data, m.size, &kv)) Fail(m.offset, "malformed parameter message");
        // Only the initial values; changes during the flight are not kept.
        if (!in_data_) info_.parameters[kv.key] = ValueAsText(kv);
        return true;
      case 'Q':
        // default_types bit field, then key and value.
        if (m.size < 1 || !ParseKeyValue(m.data + 1, m.size - 1, &kv)) {
          Fail(m.offset, "malformed default parameter message");
        }
        return true;
      default:
        return false;
    }
  }

  void ReadData() {
    in_data_ = true;
    RawMessage m;
    while (stream_.Next(&m)) {
      Progress();
      switch (m.type) {
        case 'D':
          OnData(m);
          break;
        case 'A':
          OnAdd(m);
          break;
        case 'R':
          if (m.size >= 2) active_[ReadUint16(m.data)] = -1;
          break;
        case 'L':
        case 'C':
          OnLogged(m);
          break;
        case 'O':
          if (m.size >= 2) info_.dropouts_ms.push_back(ReadUint16(m.data));
          break;
        case 'S':
          break;
        default:
          if (OnDefinitionOrInfoInData(m)) break;
          if (IsCorruptHeader(m)) {
            Resync(m);
          } else {
            NoteUnknownType(m);
          }
      }
    }
    if (stream_.partial() && !noted_partial_) {
      NotePartial();
      noted_partial_ = true;
    }
  }

  // Malformed info in the data section (e.g. a crash dump) is skipped with a note, not fatal.
  bool OnDefinitionOrInfoInData(const RawMessage& m) {
    try {
      return OnDefinitionOrInfo(m);
    } catch (const InputError& e) {
      ++skipped_corrupt_;
      return true;
    }
  }

  void Resync(const RawMessage& m) {
    ++resyncs_;
    if (resyncs_ == 1) {
      info_.notes.push_back(fmt::format(
          "corrupt data: impossible message header (type {}, size {}) at byte offset {}; "
          "skipped to the next sync message",
          TypeName(m.type), m.size, m.offset));
    }
    if (!stream_.SeekPastSync(m.offset + 1)) {
      info_.notes.push_back(fmt::format(
          "corrupt data: no sync message after byte offset {}; the rest of the file is ignored",
          m.offset));
      stream_.Seek(info_.file_bytes);
    }
  }

  void OnAdd(const RawMessage& m) {
    if (m.size < 3) {
      ++skipped_corrupt_;
      return;
    }
    auto sub = std::make_unique<Subscription>();
    sub->multi_id = m.data[0];
    sub->msg_id = ReadUint16(m.data + 1);
    sub->name.assign(reinterpret_cast<const char*>(m.data + 3), m.size - 3);
    while (!sub->name.empty() && sub->name.back() == '\0') sub->name.pop_back();
    std::string error;
    const FlattenStatus status =
        FlattenFormatWithin(formats_, sub->name, &flatten_work_left_, &sub->layout, &error);
    // A format beyond the limits of core/input_limits.h is a crafted file, not a damaged log.
    if (status == FlattenStatus::kOverLimit) {
      Fail(m.offset, fmt::format("subscription to '{}': {}", sub->name, error));
    }
    if (status != FlattenStatus::kOk) {
      info_.notes.push_back(fmt::format("subscription to '{}' (byte offset {}) ignored: {}",
                                        sub->name, m.offset, error));
      active_[sub->msg_id] = -1;
      return;
    }
    const bool wanted = handler_ != nullptr && handler_->WantsTopic(*sub);
    active_[sub->msg_id] = static_cast<int>(subscriptions_.size());
    subscriptions_.push_back({std::move(sub), wanted});
  }

  void OnData(const RawMessage& m) {
    if (m.size < 2) {
      ++skipped_corrupt_;
      return;
    }
    const int index = active_[ReadUint16(m.data)];
    if (index < 0) {
      ++unknown_msg_id_;
      return;
    }
    Subscription& sub = *subscriptions_[index].subscription;
    const bool wanted = subscriptions_[index].wanted;
    const int data_size = m.size - 2;
    if (data_size < sub.layout.logged_size || data_size > sub.layout.full_size) {
      ++wrong_size_;
      return;
    }
    const uint8_t* data = m.data + 2;
    uint64_t t_us = 0;
    if (sub.layout.timestamp_offset >= 0) t_us = ReadUint64(data + sub.layout.timestamp_offset);
    if (!StampNs(t_us)) {  // no log runs for a century: a corrupt message
      if (stamp_beyond_++ == 0) first_stamp_beyond_offset_ = m.offset;
      return;
    }
    if (sub.messages == 0) sub.t_first_us = t_us;
    sub.t_last_us = t_us;
    info_.t_last_us = std::max(info_.t_last_us, t_us);
    if (wanted) handler_->OnData(sub, data, sub.messages, m.offset);
    ++sub.messages;
  }

  void OnLogged(const RawMessage& m) {
    const int fixed = m.type == 'L' ? 9 : 11;  // level, [tag,] uint64 timestamp
    if (m.size < fixed) {
      ++skipped_corrupt_;
      return;
    }
    UlogLoggedString s;
    s.log_level = m.data[0];
    if (m.type == 'C') s.tag = ReadUint16(m.data + 1);
    s.t_us = ReadUint64(m.data + fixed - 8);
    s.message.assign(reinterpret_cast<const char*>(m.data + fixed), m.size - fixed);
    info_.logged_strings.push_back(std::move(s));
  }

  void Finish() {
    // Topics with data, in pyulog's order (info.py: sorted by name + str(multi_id)).
    for (const Entry& entry : subscriptions_) {
      const Subscription* sub = entry.subscription.get();
      if (sub->messages == 0) continue;
      info_.topics.push_back({sub->name, sub->multi_id, sub->layout.logged_size, sub->messages,
                              sub->t_first_us, sub->t_last_us});
    }
    std::stable_sort(info_.topics.begin(), info_.topics.end(),
                     [](const UlogTopicInfo& a, const UlogTopicInfo& b) {
                       return a.name + std::to_string(a.multi_id) <
                              b.name + std::to_string(b.multi_id);
                     });
    if (wrong_size_ > 0) {
      info_.notes.push_back(
          fmt::format("corrupt data: {} data message(s) of the wrong size skipped", wrong_size_));
    }
    if (unknown_msg_id_ > 0) {
      info_.notes.push_back(fmt::format(
          "corrupt data: {} data message(s) without a subscription skipped", unknown_msg_id_));
    }
    if (stamp_beyond_ > 0) {
      info_.notes.push_back(fmt::format(
          "corrupt data: {} data message(s) with a timestamp beyond the range (>= {} us, "
          "limits::kMaxTimestampNs = 2^62 ns, core/physical_limits.h) skipped (first at byte "
          "offset {})",
          stamp_beyond_, kMaxStampUs, first_stamp_beyond_offset_));
    }
    if (skipped_corrupt_ > 0) {
      info_.notes.push_back(
          fmt::format("corrupt data: {} malformed message(s) skipped", skipped_corrupt_));
    }
    if (progress_) progress_(info_.file_bytes, info_.file_bytes);
  }

  std::string path_;
  MessageStream stream_;
  ScanHandler* handler_;
  UlogProgress progress_;
  UlogInfo info_;
  bool in_data_ = false;
  std::map<std::string, MessageFormat> formats_;
  uint64_t flatten_work_left_ = input_limits::kMaxUlogFlattenWork;
  struct Entry {
    std::unique_ptr<Subscription> subscription;
    bool wanted = false;
  };
  std::vector<Entry> subscriptions_;
  std::vector<int> active_ = std::vector<int>(65536, -1);  // msg_id -> subscriptions_ index
  bool noted_partial_ = false;
  std::set<char> unknown_types_;
  uint64_t next_progress_ = 0;
  uint64_t wrong_size_ = 0;
  uint64_t unknown_msg_id_ = 0;
  uint64_t skipped_corrupt_ = 0;
  uint64_t stamp_beyond_ = 0;
  uint64_t first_stamp_beyond_offset_ = 0;
  uint64_t resyncs_ = 0;
};

}  // namespace

UlogInfo ScanUlog(const std::string& path, ScanHandler* handler, const UlogProgress& progress) {
  return Scanner(path, handler, progress).Run();
}

}  // namespace mavloc::ulog
