// Line-oriented numeric text files (EuRoC CSV, TUM, mavloc extension streams): rows of fields
// separated by commas (CSV) or whitespace (TUM); '#' lines are comments (the last comment before
// the first row is taken as the header naming the fields). Every parse error names file:line and
// the field.
#pragma once

#include <string>
#include <vector>

#include "core/time.h"

namespace mavloc {

enum class Separator { kComma, kWhitespace };

struct TextRow {
  long line = 0;                    // 1-based line number in the file
  std::vector<std::string> fields;  // trimmed
};

struct TextTable {
  std::string path;
  std::vector<std::string> header;  // field names from the header comment (may be empty)
  std::vector<TextRow> rows;

  // Name of field k for messages: the header's name, or "column k+1".
  std::string FieldName(size_t k) const;
  // Parses field k of a row as a finite double / as an integer nanosecond timestamp / as seconds
  // converted exactly to nanoseconds (decimal text, no binary rounding); timestamps must lie in
  // [0, limits::kMaxTimestampNs]. Throw InputError.
  double Number(const TextRow& row, size_t k) const;
  // Number within [lo, hi] (a sanity range of core/physical_limits.h), else InputError.
  double NumberIn(const TextRow& row, size_t k, double lo, double hi,
                  const std::string& unit) const;
  // An id written as an integer ("17"; not "17.0", "1.5" or "1e308") in [0, limits::kMaxId].
  int Id(const TextRow& row, size_t k) const;
  TimeNs TimestampNs(const TextRow& row, size_t k) const;
  TimeNs SecondsAsNs(const TextRow& row, size_t k) const;
  // Throws unless the row has at least `count` fields.
  void RequireFields(const TextRow& row, size_t count) const;
  // Throws at the first row whose timestamp is not strictly greater than the previous one.
  void RequireIncreasing(const std::vector<TimeNs>& t_ns, const std::vector<long>& lines) const;
};

// Reads the file (a UTF-8 byte order mark before the first line is dropped); throws InputError when
// it does not exist, cannot be read, or (unless allow_empty) has no data row.
TextTable ReadTextTable(const std::string& path, Separator separator, bool allow_empty = false);

}  // namespace mavloc
