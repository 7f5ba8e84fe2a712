#include "datasets/io/trajectory_formats/trajectory_text.h"

#include <cctype>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/errors.h"
#include "core/number_text.h"
#include "core/text.h"

namespace mavloc {

namespace {

// Whether the text begins with a number ("1.5", "nan", "1.5x"), as a header word does not.
bool StartsWithNumber(const std::string& text) {
  const NumberTextStatus status = ParseDoubleText(text, NonFinite::kAllow).status;
  return status != NumberTextStatus::kEmpty && status != NumberTextStatus::kNotANumber;
}

}  // namespace

std::vector<std::string> SplitTrajectoryLine(const std::string& line, bool comma_separated) {
  std::vector<std::string> fields;
  if (comma_separated) {
    size_t start = 0;
    while (true) {
      const size_t comma = line.find(',', start);
      fields.push_back(
          Trim(line.substr(start, comma == std::string::npos ? std::string::npos : comma - start)));
      if (comma == std::string::npos) break;
      start = comma + 1;
    }
    // "t,x,...,vz," (VINS-Fusion): the empty field after the last comma is not a column.
    if (fields.size() > 1 && fields.back().empty()) fields.pop_back();
  } else {
    std::istringstream stream(line);
    std::string field;
    while (stream >> field) fields.push_back(field);
  }
  return fields;
}

TrajectoryText ReadTrajectoryText(const std::string& path) {
  namespace fs = std::filesystem;
  if (!fs::exists(path)) throw InputError(path, 0, "", "file does not exist");
  if (fs::is_directory(path)) throw InputError(path, 0, "", "is a folder, not a file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, 0, "", "cannot open file");
  TrajectoryText text;
  text.path = path;
  std::string line;
  long number = 0;
  bool header_row_checked = false;
  while (std::getline(in, line)) {
    ++number;
    if (number == 1 && line.size() >= 3 && static_cast<unsigned char>(line[0]) == 0xEF &&
        static_cast<unsigned char>(line[1]) == 0xBB &&
        static_cast<unsigned char>(line[2]) == 0xBF) {
      line.erase(0, 3);
      text.had_bom = true;
    }
    if (!line.empty() && line.back() == '\r') {
      line.pop_back();
      text.had_crlf = true;
    }
    const std::string trimmed = Trim(line);
    if (trimmed.empty()) continue;
    if (trimmed.front() == '#') {
      if (text.rows.empty()) {
        text.header_line = Trim(trimmed.substr(1));
        text.header =
            SplitTrajectoryLine(text.header_line, text.header_line.find(',') != std::string::npos);
      }
      continue;
    }
    if (text.rows.empty() && !header_row_checked) {
      header_row_checked = true;
      text.comma_separated = trimmed.find(',') != std::string::npos;
      std::vector<std::string> fields = SplitTrajectoryLine(trimmed, text.comma_separated);
      // "timestamp,x,y,z,..." without '#': a header, not data ("nan" and "inf" are numbers).
      const bool numeric = !fields.empty() && StartsWithNumber(fields[0]);
      if (!fields.empty() && !fields[0].empty() && !numeric &&
          (std::isalpha(static_cast<unsigned char>(fields[0][0])) || fields[0][0] == '%')) {
        text.header_line = trimmed;
        text.header = std::move(fields);
        continue;
      }
      text.rows.push_back({number, std::move(fields)});
      continue;
    }
    if (text.rows.empty()) text.comma_separated = trimmed.find(',') != std::string::npos;
    text.rows.push_back({number, SplitTrajectoryLine(trimmed, text.comma_separated)});
  }
  if (in.bad()) throw InputError(path, 0, "", "cannot read file");
  return text;
}

}  // namespace mavloc
