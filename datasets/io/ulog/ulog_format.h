// ULog message formats ('F' messages, "name:type field;type[N] field;...") and their flattening
// into primitive fields with byte offsets (spec: docs.px4.io/main/en/dev_log/ulog_file_format.html,
// "Format Message"). Nested types are other formats of the same log; arrays of primitives and of
// nested types are expanded element by element, named as pyulog names them ("gyro_rad[0]",
// "esc[1].esc_rpm"). Fields named "_padding*" are kept for offsets; trailing ones are left out of
// the logged size (PX4's logger does not write them).
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/physical_limits.h"

namespace mavloc::ulog {

enum class PrimitiveType {
  kInt8,
  kUint8,
  kInt16,
  kUint16,
  kInt32,
  kUint32,
  kInt64,
  kUint64,
  kFloat,
  kDouble,
  kBool,
  kChar
};

// Size in bytes, or 0 when `type` is not one of the spec's primitive type names.
int PrimitiveSize(PrimitiveType type);
bool ParsePrimitiveType(std::string_view name, PrimitiveType* type);

struct FormatField {
  std::string type;    // "float", "uint8_t", or a nested format name
  int array_size = 0;  // 0: scalar; N: type[N]
  std::string name;
};

struct MessageFormat {
  std::string name;
  std::vector<FormatField> fields;
};

// Parses the text of an 'F' message. Returns false with `error` set on malformed text.
bool ParseMessageFormat(std::string_view text, MessageFormat* format, std::string* error);

struct FlatField {
  std::string name;  // "timestamp", "q[3]", "esc[1].esc_rpm"
  PrimitiveType type = PrimitiveType::kUint8;
  int offset = 0;  // bytes from the start of the message payload (after the msg_id)
};

// One topic's fields, flattened.
struct FlatLayout {
  std::vector<FlatField> fields;  // in file order, trailing "_padding" fields removed
  int logged_size = 0;            // bytes without trailing padding (pyulog's message size)
  int full_size = 0;              // bytes including trailing padding
  int timestamp_offset = -1;      // of the top-level uint64 "timestamp", -1 when absent

  const FlatField* Find(std::string_view name) const;
};

enum class FlattenStatus {
  kOk,
  kBadDefinition,  // a nested type without a format, or a format that nests itself
  kOverLimit,      // beyond a limit of core/input_limits.h: nothing was expanded
};

// Flattens format `name` using `formats` for nested types. The format is measured first (each
// nested format once) and refused before anything is expanded or allocated when it nests deeper
// than input_limits::kMaxUlogFormatNesting, flattens to more than kMaxUlogFormatFields fields (an
// element of an empty nested format counting one) or kMaxUlogFormatBytes bytes, or when the
// fields measured and the fields flattened exceed `work_left`, the flattening work left for the
// whole log (start it at input_limits::kMaxUlogFlattenWork; it is decreased by both). `error`
// names the format and the limit, the missing type, or the cycle ("a -> b -> a").
FlattenStatus FlattenFormatWithin(const std::map<std::string, MessageFormat>& formats,
                                  const std::string& name, uint64_t* work_left, FlatLayout* layout,
                                  std::string* error);
// The same for one format on its own (a fresh kMaxUlogFlattenWork); false on any failure.
bool FlattenFormat(const std::map<std::string, MessageFormat>& formats, const std::string& name,
                   FlatLayout* layout, std::string* error);

// Decodes one primitive field at `data + field.offset` (little endian) as a double.
double ReadFieldAsDouble(const uint8_t* data, const FlatField& field);
uint64_t ReadUint64(const uint8_t* data);
uint16_t ReadUint16(const uint8_t* data);

// A ULog stamp (microseconds since boot) as mavloc's int64 nanoseconds, 1000 * t_us; nullopt for a
// stamp no log can hold (kMaxStampUs and above: beyond limits::kMaxTimestampNs, 2^62 ns or about
// 146 years, core/physical_limits.h, which every other reader applies) and, for a stamp read from
// a floating-point field (timestamp_sample), for NaN or negative values.
constexpr uint64_t kMaxStampUs = static_cast<uint64_t>(limits::kMaxTimestampNs / 1000) + 1;
std::optional<int64_t> StampNs(uint64_t t_us);
std::optional<int64_t> StampNsOfField(double t_us);

}  // namespace mavloc::ulog
