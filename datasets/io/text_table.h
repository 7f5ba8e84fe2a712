// Line-oriented numeric text files (EuRoC CSV, TUM, mavloc extension streams): rows of fields
// separated by commas (CSV) or whitespace (TUM); '#' lines are comments (the last comment before
// the first row is taken as the header naming the fields). Every parse error names file:line and
// the field.
//
// TextRowReader streams the rows (a block-read buffer, fields as views into it: memory does not
// grow with the file); ReadTextTable keeps them all, for the readers that need the whole table.
#pragma once

#include <cstdio>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "core/time.h"

namespace mavloc {

enum class Separator { kComma, kWhitespace };

struct TextRow {
  long line = 0;                    // 1-based line number in the file
  std::vector<std::string> fields;  // trimmed
};

// A row as TextRowReader hands it out: the fields are views into the reader's buffer, valid until
// its next call of Next().
struct TextRowView {
  long line = 0;
  std::vector<std::string_view> fields;  // trimmed
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

  // The same checks on the text of field k of the row at `line` (the streaming readers', with the
  // same messages); the field's name is only built for a message.
  double NumberInText(std::string_view text, long line, size_t k, double lo, double hi,
                      const std::string& unit) const;
  TimeNs TimestampNsText(std::string_view text, long line, size_t k) const;
  int IdText(std::string_view text, long line, size_t k) const;
  void RequireFieldCount(size_t found, long line, size_t count) const;
  // Throws unless t_ns (field 0 of the row at `line`) is after previous_ns, the stamp of the row
  // before: "duplicate timestamp ..." or "timestamp ... is earlier than the previous row's".
  void RequireAfter(TimeNs previous_ns, TimeNs t_ns, long line) const;
  // The same allowing equal stamps (observation streams: several rows per stamp): throws only
  // "timestamp ... is earlier than the previous row's".
  void RequireNotBefore(TimeNs previous_ns, TimeNs t_ns, long line) const;
};

// The rows of a text file, one at a time. Lines are split at '\n' (a '\r' before it is trimmed
// with the other blanks); a UTF-8 byte order mark before the first line is dropped; blank lines
// and '#' lines are skipped, the last '#' line before the first row being the header.
class TextRowReader {
 public:
  // Throws InputError when the file does not exist, is a folder or cannot be opened.
  TextRowReader(const std::string& path, Separator separator);
  ~TextRowReader();
  TextRowReader(const TextRowReader&) = delete;
  TextRowReader& operator=(const TextRowReader&) = delete;

  // The next data row, or nullptr at the end of the file; valid until the next call.
  const TextRowView* Next();
  // The header's field names: final once Next() has returned the first row (or nullptr).
  const std::vector<std::string>& header() const { return header_; }
  const std::string& path() const { return path_; }

 private:
  bool NextLine(std::string_view* line);  // false at the end of the file
  void Split(std::string_view text, std::vector<std::string_view>* fields) const;

  std::string path_;
  Separator separator_;
  struct FileCloser {
    void operator()(std::FILE* file) const { std::fclose(file); }
  };
  std::unique_ptr<std::FILE, FileCloser> file_;
  std::vector<char> buffer_;
  size_t begin_ = 0, end_ = 0;  // unread bytes: buffer_[begin_, end_)
  bool eof_ = false;
  long line_ = 0;
  bool any_row_ = false;
  std::vector<std::string> header_;
  TextRowView row_;
};

// Reads the file (a UTF-8 byte order mark before the first line is dropped); throws InputError when
// it does not exist, cannot be read, or (unless allow_empty) has no data row.
TextTable ReadTextTable(const std::string& path, Separator separator, bool allow_empty = false);

}  // namespace mavloc
