#include "datasets/io/trajectory_formats/trajectory_text.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>

#include "core/errors.h"
#include "core/input_file.h"
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

TrajectoryRowStream::TrajectoryRowStream(const std::string& path)
    : path_(path), file_(nullptr, &std::fclose) {
  file_.reset(OpenRegularFileStream(path));  // a pipe, a device, a loop: refused, never blocks
  buffer_.resize(size_t{1} << 20);
}

bool TrajectoryRowStream::Refill() {
  if (at_eof_) return false;
  if (begin_ > 0) {  // keep the unread bytes, at the front
    std::memmove(buffer_.data(), buffer_.data() + begin_, end_ - begin_);
    end_ -= begin_;
    scanned_ -= begin_;
    begin_ = 0;
  }
  if (end_ == buffer_.size()) buffer_.resize(2 * buffer_.size());  // a line longer than the buffer
  const size_t want = buffer_.size() - end_;
  const size_t got = std::fread(buffer_.data() + end_, 1, want, file_.get());
  end_ += got;
  if (got < want) {
    if (std::ferror(file_.get())) throw InputError(path_, 0, "", "cannot read file");
    at_eof_ = true;
  }
  return got > 0;
}

// Lines as std::getline gives them: split at '\n', the last one without a '\n' included, none after
// a final '\n'.
bool TrajectoryRowStream::NextLine(std::string_view* line) {
  while (true) {
    const void* newline = std::memchr(buffer_.data() + scanned_, '\n', end_ - scanned_);
    if (newline != nullptr) {
      const size_t at = static_cast<size_t>(static_cast<const char*>(newline) - buffer_.data());
      *line = std::string_view(buffer_.data() + begin_, at - begin_);
      begin_ = scanned_ = at + 1;
      return true;
    }
    scanned_ = end_;
    if (!Refill()) break;
  }
  if (begin_ == end_) return false;
  *line = std::string_view(buffer_.data() + begin_, end_ - begin_);
  begin_ = scanned_ = end_;
  return true;
}

bool TrajectoryRowStream::Next(long* line_number, std::string_view* text) {
  std::string_view line;
  std::vector<std::string_view> fields;
  while (NextLine(&line)) {
    ++number_;
    if (number_ == 1 && line.size() >= 3 && static_cast<unsigned char>(line[0]) == 0xEF &&
        static_cast<unsigned char>(line[1]) == 0xBB &&
        static_cast<unsigned char>(line[2]) == 0xBF) {
      line.remove_prefix(3);
      had_bom_ = true;
    }
    if (!line.empty() && line.back() == '\r') {
      line.remove_suffix(1);
      had_crlf_ = true;
    }
    const std::string_view trimmed = TrimTrajectoryView(line);
    if (trimmed.empty()) continue;
    if (trimmed.front() == '#') {
      if (!first_row_seen_) {
        header_line_ = std::string(TrimTrajectoryView(trimmed.substr(1)));
        header_ = SplitTrajectoryLine(header_line_, header_line_.find(',') != std::string::npos);
      }
      continue;
    }
    if (!first_row_seen_) {
      comma_separated_ = trimmed.find(',') != std::string_view::npos;
      if (!header_row_checked_) {
        header_row_checked_ = true;
        SplitTrajectoryFields(trimmed, comma_separated_, &fields);
        // "timestamp,x,y,z,..." without '#': a header, not data ("nan" and "inf" are numbers).
        const bool numeric = !fields.empty() && StartsWithNumber(fields[0]);
        if (!fields.empty() && !fields[0].empty() && !numeric &&
            (std::isalpha(static_cast<unsigned char>(fields[0][0])) || fields[0][0] == '%')) {
          header_line_ = std::string(trimmed);
          header_.assign(fields.begin(), fields.end());
          continue;
        }
      }
      first_row_seen_ = true;
    }
    *line_number = number_;
    *text = trimmed;
    return true;
  }
  return false;
}

TrajectoryText ReadTrajectoryText(const std::string& path) {
  TrajectoryRowStream stream(path);
  TrajectoryText text;
  text.path = path;
  long line = 0;
  std::string_view row_text;
  while (stream.Next(&line, &row_text)) {
    text.rows.push_back(TrajectoryRow{line, text.storage.size(), row_text.size()});
    text.storage.append(row_text);
  }
  text.bytes = text.storage;
  text.header = stream.header();
  text.header_line = stream.header_line();
  text.comma_separated = stream.comma_separated();
  text.had_bom = stream.had_bom();
  text.had_crlf = stream.had_crlf();
  return text;
}

}  // namespace mavloc
