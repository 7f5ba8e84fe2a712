// The text layer under every trajectory reader: a file split into numbered rows of fields, with the
// leniencies of the tools whose files mavloc reads (evo's file_interface.csv_read_matrix, OpenVINS
// ov_eval's Loader, the TUM RGB-D tools):
// - a UTF-8 byte order mark at the start is skipped (evo: has_utf8_bom);
// - CRLF line endings are accepted (the '\r' is dropped);
// - blank lines and lines whose first non-blank character is '#' are skipped; the last '#' line
//   before the first data row is kept as the header naming the columns ("#timestamp,x,y,...",
//   "# timestamp tx ty tz qx qy qz qw", OpenVINS' "# timestamp(s) q p v ..."). A first row whose
//   first field is a word (a CSV header without '#', or rostopic's "%time,field...") is taken as
//   the header too;
// - separators: when the first data row has a comma, every row is split at commas (fields trimmed
//   of spaces and tabs; one trailing empty field, as VINS-Fusion's "...,vz," writes, is dropped);
//   otherwise at runs of spaces and tabs (evo splits at single spaces only; mavloc accepts more).
// TrajectoryRowStream reads a file in blocks and hands out its data rows one at a time (memory
// independent of the file's length: the readers of trajectory_reader.cc parse each row as it
// comes). ReadTrajectoryText keeps every row: a row is its line number and where its text lies in
// one buffer, and its fields are views into the buffer made when they are asked for (no string per
// line or per field: a million-row file costs its bytes plus 24 bytes a row).
#pragma once

#include <cstdio>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace mavloc {

// One data row: its line and where its text (trimmed of blanks) lies in TrajectoryText::bytes.
struct TrajectoryRow {
  long line = 0;  // 1-based line number in the file
  size_t begin = 0;
  size_t size = 0;
};

struct TrajectoryText {
  std::string path;
  std::vector<std::string> header;  // names from the header line (empty when there is none)
  std::string header_line;          // the header as written (without '#')
  std::string storage;              // the data rows' texts, one after the other
  std::string_view bytes;           // view of storage
  std::vector<TrajectoryRow> rows;
  bool comma_separated = false;
  bool had_bom = false;
  bool had_crlf = false;

  std::string_view RowText(const TrajectoryRow& row) const {
    return std::string_view(bytes).substr(row.begin, row.size);
  }
  // The row's fields (trimmed), views into `bytes`; *fields is cleared first (its capacity is
  // reused, so a loop over the rows allocates nothing).
  void Fields(const TrajectoryRow& row, std::vector<std::string_view>* fields) const;
  std::vector<std::string_view> Fields(const TrajectoryRow& row) const;
};

// The data rows of a file, one at a time, by the rules above. The header, the separator and the
// BOM are known once the first row has been returned (the header is the last '#' line before it);
// had_crlf() covers the lines read so far.
class TrajectoryRowStream {
 public:
  // Throws InputError (file) when the file does not exist, is a folder, or cannot be opened.
  explicit TrajectoryRowStream(const std::string& path);
  // The next data row: its 1-based line number and its text (trimmed of blanks, without '\r'),
  // valid until the next call. False at the end of the file. Throws InputError (file) when the
  // file cannot be read.
  bool Next(long* line, std::string_view* text);

  const std::string& path() const { return path_; }
  const std::vector<std::string>& header() const { return header_; }
  const std::string& header_line() const { return header_line_; }
  bool comma_separated() const { return comma_separated_; }
  bool had_bom() const { return had_bom_; }
  bool had_crlf() const { return had_crlf_; }

 private:
  bool NextLine(std::string_view* line);  // the next raw line (without '\n'); false at the end
  bool Refill();                          // more bytes after the unread ones; false at the end

  std::string path_;
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> file_;
  std::vector<char> buffer_;
  size_t begin_ = 0, end_ = 0;  // the unread bytes: buffer_[begin_, end_)
  size_t scanned_ = 0;          // buffer_[begin_, scanned_) holds no '\n'
  bool at_eof_ = false;
  long number_ = 0;  // lines read so far
  bool first_row_seen_ = false, header_row_checked_ = false;
  std::vector<std::string> header_;
  std::string header_line_;
  bool comma_separated_ = false, had_bom_ = false, had_crlf_ = false;
};

// Throws InputError (file) when the file does not exist, is a folder, or cannot be read; an empty
// result (no rows) is returned as is, the readers decide.
TrajectoryText ReadTrajectoryText(const std::string& path);

// Splits one line (already without '\r') as described above: the fields as views into `line`.
void SplitTrajectoryFields(std::string_view line, bool comma_separated,
                           std::vector<std::string_view>* fields);
// The same as strings.
std::vector<std::string> SplitTrajectoryLine(std::string_view line, bool comma_separated);

}  // namespace mavloc
