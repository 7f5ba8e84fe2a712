#include "datasets/io/ulog/ulog_format.h"

#include <fmt/format.h>

#include <algorithm>
#include <cstring>
#include <vector>

#include "core/input_limits.h"

namespace mavloc::ulog {
namespace {

struct PrimitiveName {
  std::string_view name;
  PrimitiveType type;
  int size;
};

constexpr PrimitiveName kPrimitives[] = {
    {"int8_t", PrimitiveType::kInt8, 1},   {"uint8_t", PrimitiveType::kUint8, 1},
    {"int16_t", PrimitiveType::kInt16, 2}, {"uint16_t", PrimitiveType::kUint16, 2},
    {"int32_t", PrimitiveType::kInt32, 4}, {"uint32_t", PrimitiveType::kUint32, 4},
    {"int64_t", PrimitiveType::kInt64, 8}, {"uint64_t", PrimitiveType::kUint64, 8},
    {"float", PrimitiveType::kFloat, 4},   {"double", PrimitiveType::kDouble, 8},
    {"bool", PrimitiveType::kBool, 1},     {"char", PrimitiveType::kChar, 1},
};

std::string_view TrimFormatText(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\0')) {
    s.remove_suffix(1);
  }
  return s;
}

bool ParseField(std::string_view text, FormatField* field, std::string* error) {
  const size_t space = text.find(' ');
  if (space == std::string_view::npos) {
    *error = fmt::format("field '{}' has no 'type name' form", text);
    return false;
  }
  std::string_view type = TrimFormatText(text.substr(0, space));
  const std::string_view name = TrimFormatText(text.substr(space + 1));
  if (type.empty() || name.empty()) {
    *error = fmt::format("field '{}' has an empty type or name", text);
    return false;
  }
  field->array_size = 0;
  const size_t open = type.find('[');
  if (open != std::string_view::npos) {
    const size_t close = type.find(']', open);
    if (close == std::string_view::npos || close != type.size() - 1 || close == open + 1) {
      *error = fmt::format("field '{}' has a malformed array size", text);
      return false;
    }
    int size = 0;
    for (size_t i = open + 1; i < close; ++i) {
      const char c = type[i];
      if (c < '0' || c > '9' || size > 100000) {
        *error = fmt::format("field '{}' has a malformed array size", text);
        return false;
      }
      size = size * 10 + (c - '0');
    }
    if (size <= 0) {
      *error = fmt::format("field '{}' has array size 0", text);
      return false;
    }
    field->array_size = size;
    type = type.substr(0, open);
  }
  field->type = std::string(type);
  field->name = std::string(name);
  return true;
}

// What one format expands to.
struct FormatSize {
  uint64_t fields = 0;  // flattened fields; an element of an empty nested format counts one
  uint64_t bytes = 0;
  int height = 0;  // levels of nested formats below this one
};

// "a -> b -> a"
std::string ChainText(const std::vector<std::string>& chain, const std::string& last) {
  std::string text;
  for (const std::string& name : chain) text += name + " -> ";
  return text + last;
}

// Measures a format before anything is expanded, so that a format beyond the limits of
// core/input_limits.h is refused before the work is done: each nested format is measured once
// (memoized), the formats being measured are kept on a chain that names a cycle, and every field
// visited is charged to the log's flattening work.
class FormatMeter {
  static constexpr int kMaxNesting = input_limits::kMaxUlogFormatNesting;

 public:
  FormatMeter(const std::map<std::string, MessageFormat>& formats, uint64_t* work_left,
              std::string* error)
      : formats_(formats), work_left_(work_left), error_(error) {}

  FlattenStatus Measure(const std::string& name, FormatSize* size) { return Visit(name, 0, size); }

 private:
  FlattenStatus Visit(const std::string& name, int depth, FormatSize* size) {
    if (const auto done = measured_.find(name); done != measured_.end()) {
      *size = done->second;
      return depth + size->height > kMaxNesting ? TooDeep(name) : FlattenStatus::kOk;
    }
    if (std::find(chain_.begin(), chain_.end(), name) != chain_.end()) {
      *error_ = fmt::format("format '{}' nests itself ({})", name, ChainText(chain_, name));
      return FlattenStatus::kBadDefinition;
    }
    if (depth > kMaxNesting) return TooDeep(name);
    const auto it = formats_.find(name);
    if (it == formats_.end()) {
      *error_ = fmt::format("no format definition for type '{}'", name);
      return FlattenStatus::kBadDefinition;
    }
    chain_.push_back(name);
    FormatSize total;
    for (const FormatField& field : it->second.fields) {
      FormatSize element;
      const FlattenStatus status = MeasureField(field, depth, &element);
      if (status != FlattenStatus::kOk) return status;
      const uint64_t count = field.array_size == 0 ? 1 : static_cast<uint64_t>(field.array_size);
      total.fields += count * element.fields;
      total.bytes += count * element.bytes;
      total.height = std::max(total.height, element.height);
      if (total.fields > input_limits::kMaxUlogFormatFields) {
        return OverLimit(
            fmt::format("format '{}' flattens to more than {} fields (an element of "
                        "an empty nested format counts one; limit "
                        "input_limits::kMaxUlogFormatFields)",
                        name, input_limits::kMaxUlogFormatFields));
      }
      if (total.bytes > input_limits::kMaxUlogFormatBytes) {
        return OverLimit(
            fmt::format("format '{}' is larger than a ULog message can be (more "
                        "than {} bytes; limit input_limits::kMaxUlogFormatBytes)",
                        name, input_limits::kMaxUlogFormatBytes));
      }
    }
    chain_.pop_back();
    measured_[name] = total;
    *size = total;
    return FlattenStatus::kOk;
  }

  // One element of `field`: a primitive, or a nested format (at least one field; its height
  // counts the level of `field` itself).
  FlattenStatus MeasureField(const FormatField& field, int depth, FormatSize* element) {
    if (*work_left_ == 0) return OverLog();
    --*work_left_;
    PrimitiveType type = PrimitiveType::kUint8;
    if (ParsePrimitiveType(field.type, &type)) {
      *element = {1, static_cast<uint64_t>(PrimitiveSize(type))};
      return FlattenStatus::kOk;
    }
    const FlattenStatus status = Visit(field.type, depth + 1, element);
    element->fields = std::max<uint64_t>(element->fields, 1);
    element->height += 1;
    return status;
  }

  FlattenStatus TooDeep(const std::string& name) {
    return OverLimit(
        fmt::format("format '{}' nests formats more than {} levels deep ({}; limit "
                    "input_limits::kMaxUlogFormatNesting)",
                    chain_.empty() ? name : chain_.front(), kMaxNesting, ChainText(chain_, name)));
  }

  FlattenStatus OverLimit(const std::string& message) {
    *error_ = message;
    return FlattenStatus::kOverLimit;
  }

  FlattenStatus OverLog() {
    return OverLimit(
        fmt::format("the log's formats need more than {} steps to flatten (limit "
                    "input_limits::kMaxUlogFlattenWork)",
                    input_limits::kMaxUlogFlattenWork));
  }

  const std::map<std::string, MessageFormat>& formats_;
  uint64_t* work_left_;
  std::string* error_;
  std::map<std::string, FormatSize> measured_;
  std::vector<std::string> chain_;
};

// Expands a measured format into its primitive fields (FormatMeter has checked that every type
// exists, that nothing nests itself and that the expansion is within the limits).
struct Flattener {
  const std::map<std::string, MessageFormat>& formats;
  FlatLayout* layout;
  int offset = 0;

  void Add(const std::string& prefix, const std::string& format_name) {
    for (const FormatField& field : formats.at(format_name).fields) {
      PrimitiveType type = PrimitiveType::kUint8;
      const bool primitive = ParsePrimitiveType(field.type, &type);
      const int count = field.array_size == 0 ? 1 : field.array_size;
      for (int i = 0; i < count; ++i) {
        const std::string name = field.array_size > 0
                                     ? fmt::format("{}{}[{}]", prefix, field.name, i)
                                     : fmt::format("{}{}", prefix, field.name);
        if (primitive) {
          layout->fields.push_back({name, type, offset});
          offset += PrimitiveSize(type);
        } else {
          Add(fmt::format("{}.", name), field.type);
        }
      }
    }
  }
};

}  // namespace

int PrimitiveSize(PrimitiveType type) {
  for (const PrimitiveName& p : kPrimitives) {
    if (p.type == type) return p.size;
  }
  return 0;
}

bool ParsePrimitiveType(std::string_view name, PrimitiveType* type) {
  for (const PrimitiveName& p : kPrimitives) {
    if (p.name == name) {
      *type = p.type;
      return true;
    }
  }
  return false;
}

bool ParseMessageFormat(std::string_view text, MessageFormat* format, std::string* error) {
  const size_t colon = text.find(':');
  if (colon == std::string_view::npos || colon == 0) {
    *error = "format message without 'name:' prefix";
    return false;
  }
  format->name = std::string(TrimFormatText(text.substr(0, colon)));
  format->fields.clear();
  std::string_view rest = text.substr(colon + 1);
  while (!rest.empty()) {
    const size_t semi = rest.find(';');
    const std::string_view item = TrimFormatText(rest.substr(0, semi));
    if (!item.empty()) {
      FormatField field;
      if (!ParseField(item, &field, error)) return false;
      format->fields.push_back(std::move(field));
    }
    if (semi == std::string_view::npos) break;
    rest.remove_prefix(semi + 1);
  }
  return true;
}

const FlatField* FlatLayout::Find(std::string_view name) const {
  for (const FlatField& field : fields) {
    if (field.name == name) return &field;
  }
  return nullptr;
}

FlattenStatus FlattenFormatWithin(const std::map<std::string, MessageFormat>& formats,
                                  const std::string& name, uint64_t* work_left, FlatLayout* layout,
                                  std::string* error) {
  *layout = FlatLayout();
  FormatSize size;
  const FlattenStatus status = FormatMeter(formats, work_left, error).Measure(name, &size);
  if (status != FlattenStatus::kOk) return status;
  if (size.fields > *work_left) {
    *error = fmt::format(
        "the log's formats need more than {} steps to flatten (limit "
        "input_limits::kMaxUlogFlattenWork)",
        input_limits::kMaxUlogFlattenWork);
    return FlattenStatus::kOverLimit;
  }
  *work_left -= size.fields;
  layout->fields.reserve(size.fields);
  Flattener flattener{formats, layout};
  flattener.Add("", name);
  layout->full_size = flattener.offset;
  // pyulog (core.py, _MessageAddLogged._parse_format) drops trailing padding: PX4's logger does
  // not write it, so the logged size ends at the last real field.
  while (!layout->fields.empty() && layout->fields.back().name.rfind("_padding", 0) == 0) {
    layout->fields.pop_back();
  }
  layout->logged_size = 0;
  if (!layout->fields.empty()) {
    const FlatField& last = layout->fields.back();
    layout->logged_size = last.offset + PrimitiveSize(last.type);
  }
  const FlatField* timestamp = layout->Find("timestamp");
  if (timestamp != nullptr && timestamp->type == PrimitiveType::kUint64) {
    layout->timestamp_offset = timestamp->offset;
  }
  return FlattenStatus::kOk;
}

bool FlattenFormat(const std::map<std::string, MessageFormat>& formats, const std::string& name,
                   FlatLayout* layout, std::string* error) {
  uint64_t work_left = input_limits::kMaxUlogFlattenWork;
  return FlattenFormatWithin(formats, name, &work_left, layout, error) == FlattenStatus::kOk;
}

uint64_t ReadUint64(const uint8_t* data) {
  uint64_t v = 0;
  for (int i = 7; i >= 0; --i) v = (v << 8) | data[i];
  return v;
}

std::optional<int64_t> StampNs(uint64_t t_us) {
  if (t_us >= kMaxStampUs) return std::nullopt;
  return static_cast<int64_t>(t_us) * 1000;
}

std::optional<int64_t> StampNsOfField(double t_us) {
  // kMaxStampUs is below 2^53, exact as a double.
  if (!(t_us >= 0.0 && t_us < static_cast<double>(kMaxStampUs))) return std::nullopt;
  return StampNs(static_cast<uint64_t>(t_us));
}

uint16_t ReadUint16(const uint8_t* data) { return static_cast<uint16_t>(data[0] | (data[1] << 8)); }

double ReadFieldAsDouble(const uint8_t* data, const FlatField& field) {
  const uint8_t* p = data + field.offset;
  // The host is little endian like ULog (checked in ulog_stream.cc); memcpy avoids unaligned
  // access.
  switch (field.type) {
    case PrimitiveType::kInt8:
      return static_cast<int8_t>(p[0]);
    case PrimitiveType::kUint8:
      return p[0];
    case PrimitiveType::kBool:
      return p[0] != 0 ? 1.0 : 0.0;
    case PrimitiveType::kChar:
      return static_cast<char>(p[0]);
    case PrimitiveType::kInt16: {
      int16_t v;
      std::memcpy(&v, p, 2);
      return v;
    }
    case PrimitiveType::kUint16:
      return ReadUint16(p);
    case PrimitiveType::kInt32: {
      int32_t v;
      std::memcpy(&v, p, 4);
      return v;
    }
    case PrimitiveType::kUint32: {
      uint32_t v;
      std::memcpy(&v, p, 4);
      return v;
    }
    case PrimitiveType::kInt64: {
      int64_t v;
      std::memcpy(&v, p, 8);
      return static_cast<double>(v);
    }
    case PrimitiveType::kUint64:
      return static_cast<double>(ReadUint64(p));
    case PrimitiveType::kFloat: {
      float v;
      std::memcpy(&v, p, 4);
      return v;
    }
    case PrimitiveType::kDouble: {
      double v;
      std::memcpy(&v, p, 8);
      return v;
    }
  }
  return 0.0;
}

}  // namespace mavloc::ulog
