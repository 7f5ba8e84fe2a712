#include "datasets/io/trajectory_formats/trajectory_text.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>

#include "core/errors.h"
#include "core/number_text.h"

namespace mavloc {

namespace {

// Blanks trimmed from a line and from a comma-separated field (core/text.h Trim's set).
constexpr std::string_view kTrajectoryTrimmed = " \t\r\n";

std::string_view TrimTrajectoryView(std::string_view text) {
  const size_t begin = text.find_first_not_of(kTrajectoryTrimmed);
  if (begin == std::string_view::npos) return {};
  const size_t end = text.find_last_not_of(kTrajectoryTrimmed);
  return text.substr(begin, end - begin + 1);
}

// The separators of whitespace rows: what `std::istream >> std::string` skips in the C locale.
bool IsTrajectorySpace(char c) {
  return c == ' ' || c == '\t' || c == '\n' || c == '\v' || c == '\f' || c == '\r';
}

// Whether the text begins with a number ("1.5", "nan", "1.5x"), as a header word does not.
bool StartsWithNumber(std::string_view text) {
  const NumberTextStatus status = ParseDoubleText(text, NonFinite::kAllow).status;
  return status != NumberTextStatus::kEmpty && status != NumberTextStatus::kNotANumber;
}

// The whole file, read in blocks into *storage (sized from the file's size, grown when the file
// holds more); returns the number of bytes read. Throws InputError (file) when the file cannot be
// opened or read.
size_t ReadTrajectoryBytes(const std::string& path, std::unique_ptr<char[]>* storage) {
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> file(std::fopen(path.c_str(), "rb"),
                                                       &std::fclose);
  if (!file) throw InputError(path, 0, "", "cannot open file");
  std::error_code size_error;
  const auto file_size = std::filesystem::file_size(path, size_error);
  constexpr size_t kBlockBytes = size_t{1} << 20;
  size_t capacity = size_error ? kBlockBytes : static_cast<size_t>(file_size) + 1;
  *storage = std::unique_ptr<char[]>(new char[capacity]);
  size_t used = 0;
  while (true) {
    if (used == capacity) {
      const size_t grown = 2 * capacity;
      std::unique_ptr<char[]> larger(new char[grown]);
      std::memcpy(larger.get(), storage->get(), used);
      *storage = std::move(larger);
      capacity = grown;
    }
    const size_t want = std::min(kBlockBytes, capacity - used);
    const size_t got = std::fread(storage->get() + used, 1, want, file.get());
    used += got;
    if (got < want) break;
  }
  if (std::ferror(file.get())) throw InputError(path, 0, "", "cannot read file");
  return used;
}

}  // namespace

void SplitTrajectoryFields(std::string_view line, bool comma_separated,
                           std::vector<std::string_view>* fields) {
  fields->clear();
  if (comma_separated) {
    size_t start = 0;
    while (true) {
      const size_t comma = line.find(',', start);
      fields->push_back(TrimTrajectoryView(line.substr(
          start, comma == std::string_view::npos ? std::string_view::npos : comma - start)));
      if (comma == std::string_view::npos) break;
      start = comma + 1;
    }
    // "t,x,...,vz," (VINS-Fusion): the empty field after the last comma is not a column.
    if (fields->size() > 1 && fields->back().empty()) fields->pop_back();
    return;
  }
  const size_t n = line.size();
  size_t i = 0;
  while (true) {
    while (i < n && IsTrajectorySpace(line[i])) ++i;
    if (i == n) break;
    const size_t begin = i;
    while (i < n && !IsTrajectorySpace(line[i])) ++i;
    fields->push_back(line.substr(begin, i - begin));
  }
}

std::vector<std::string> SplitTrajectoryLine(std::string_view line, bool comma_separated) {
  std::vector<std::string_view> views;
  SplitTrajectoryFields(line, comma_separated, &views);
  return std::vector<std::string>(views.begin(), views.end());
}

void TrajectoryText::Fields(const TrajectoryRow& row, std::vector<std::string_view>* fields) const {
  SplitTrajectoryFields(RowText(row), comma_separated, fields);
}

std::vector<std::string_view> TrajectoryText::Fields(const TrajectoryRow& row) const {
  std::vector<std::string_view> fields;
  Fields(row, &fields);
  return fields;
}

TrajectoryText ReadTrajectoryText(const std::string& path) {
  namespace fs = std::filesystem;
  if (!fs::exists(path)) throw InputError(path, 0, "", "file does not exist");
  if (fs::is_directory(path)) throw InputError(path, 0, "", "is a folder, not a file");
  TrajectoryText text;
  text.path = path;
  const size_t size = ReadTrajectoryBytes(path, &text.storage);
  text.bytes = std::string_view(text.storage.get(), size);
  const std::string_view bytes = text.bytes;
  if (!bytes.empty()) text.rows.reserve(bytes.size() / 64);
  std::vector<std::string_view> fields;
  long number = 0;
  bool header_row_checked = false;
  size_t line_begin = 0;
  // Lines as std::getline gives them: split at '\n', the last one without a '\n' included, none
  // after a final '\n'.
  while (line_begin < bytes.size()) {
    const void* newline = std::memchr(bytes.data() + line_begin, '\n', bytes.size() - line_begin);
    const size_t line_end =
        newline == nullptr ? bytes.size()
                           : static_cast<size_t>(static_cast<const char*>(newline) - bytes.data());
    std::string_view line = bytes.substr(line_begin, line_end - line_begin);
    line_begin = line_end + 1;
    ++number;
    if (number == 1 && line.size() >= 3 && static_cast<unsigned char>(line[0]) == 0xEF &&
        static_cast<unsigned char>(line[1]) == 0xBB &&
        static_cast<unsigned char>(line[2]) == 0xBF) {
      line.remove_prefix(3);
      text.had_bom = true;
    }
    if (!line.empty() && line.back() == '\r') {
      line.remove_suffix(1);
      text.had_crlf = true;
    }
    const std::string_view trimmed = TrimTrajectoryView(line);
    if (trimmed.empty()) continue;
    if (trimmed.front() == '#') {
      if (text.rows.empty()) {
        text.header_line = std::string(TrimTrajectoryView(trimmed.substr(1)));
        text.header =
            SplitTrajectoryLine(text.header_line, text.header_line.find(',') != std::string::npos);
      }
      continue;
    }
    const TrajectoryRow row{number, static_cast<size_t>(trimmed.data() - bytes.data()),
                            trimmed.size()};
    if (text.rows.empty() && !header_row_checked) {
      header_row_checked = true;
      text.comma_separated = trimmed.find(',') != std::string_view::npos;
      SplitTrajectoryFields(trimmed, text.comma_separated, &fields);
      // "timestamp,x,y,z,..." without '#': a header, not data ("nan" and "inf" are numbers).
      const bool numeric = !fields.empty() && StartsWithNumber(fields[0]);
      if (!fields.empty() && !fields[0].empty() && !numeric &&
          (std::isalpha(static_cast<unsigned char>(fields[0][0])) || fields[0][0] == '%')) {
        text.header_line = std::string(trimmed);
        text.header.assign(fields.begin(), fields.end());
        continue;
      }
      text.rows.push_back(row);
      continue;
    }
    if (text.rows.empty()) text.comma_separated = trimmed.find(',') != std::string_view::npos;
    text.rows.push_back(row);
  }
  return text;
}

}  // namespace mavloc
