#include "datasets/io/ulog/ulog_format.h"

#include <fmt/format.h>

#include <cstring>

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

// Nested formats deeper than this are treated as a self-reference (PX4 nests 2-3 levels).
constexpr int kMaxNesting = 16;

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

struct Flattener {
  const std::map<std::string, MessageFormat>& formats;
  FlatLayout* layout;
  std::string* error;
  int offset = 0;

  bool Add(const std::string& prefix, const std::string& format_name, int depth) {
    if (depth > kMaxNesting) {
      *error = fmt::format("format '{}' nests itself", format_name);
      return false;
    }
    const auto it = formats.find(format_name);
    if (it == formats.end()) {
      *error = fmt::format("no format definition for type '{}'", format_name);
      return false;
    }
    for (const FormatField& field : it->second.fields) {
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
        } else if (!Add(fmt::format("{}.", name), field.type, depth + 1)) {
          return false;
        }
        if (offset > 65535) {
          *error = fmt::format("format '{}' is larger than a ULog message can be", format_name);
          return false;
        }
      }
    }
    return true;
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

bool FlattenFormat(const std::map<std::string, MessageFormat>& formats, const std::string& name,
                   FlatLayout* layout, std::string* error) {
  *layout = FlatLayout();
  Flattener flattener{formats, layout, error};
  if (!flattener.Add("", name, 0)) return false;
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
  return true;
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
