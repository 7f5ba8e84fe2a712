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
// The file is read whole with block reads into one buffer; a row is its line number and where its
// text lies in the buffer, and its fields are views into the buffer made when they are asked for
// (no string per line or per field: a million-row file costs its bytes plus 24 bytes a row).
#pragma once

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
  std::unique_ptr<char[]> storage;  // the file's contents (not zero-filled before the read)
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

// Throws InputError (file) when the file does not exist, is a folder, or cannot be read; an empty
// result (no rows) is returned as is, the readers decide.
TrajectoryText ReadTrajectoryText(const std::string& path);

// Splits one line (already without '\r') as described above: the fields as views into `line`.
void SplitTrajectoryFields(std::string_view line, bool comma_separated,
                           std::vector<std::string_view>* fields);
// The same as strings.
std::vector<std::string> SplitTrajectoryLine(std::string_view line, bool comma_separated);

}  // namespace mavloc
