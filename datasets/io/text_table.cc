#include "datasets/io/text_table.h"

#include <cmath>
#include <cstring>
#include <filesystem>

#include "core/errors.h"
#include "core/input_file.h"
#include "core/number_text.h"
#include "core/physical_limits.h"

namespace mavloc {

namespace {

constexpr const char* kBlanks = " \t\r\n";  // what Trim (core/text.h) removes
constexpr size_t kReadBlock = size_t{1} << 20;

std::string_view TrimView(std::string_view text) {
  const size_t begin = text.find_first_not_of(kBlanks);
  if (begin == std::string_view::npos) return {};
  return text.substr(begin, text.find_last_not_of(kBlanks) - begin + 1);
}

std::string TimestampBeyond(const std::string& text, const std::string& unit) {
  const bool seconds = unit == "s";
  return "timestamp " + text + " " + unit + " is beyond " +
         std::to_string(seconds ? limits::kMaxTimestampNs / kNsPerSecond
                                : limits::kMaxTimestampNs) +
         " " + unit + " (limits::kMaxTimestampNs = 2^62 ns, year 2116)";
}

}  // namespace

std::string TextTable::FieldName(size_t k) const {
  if (k < header.size() && !header[k].empty()) return header[k];
  return "column " + std::to_string(k + 1);
}

void TextTable::RequireFields(const TextRow& row, size_t count) const {
  RequireFieldCount(row.fields.size(), row.line, count);
}

void TextTable::RequireFieldCount(size_t found, long line, size_t count) const {
  if (found < count) {
    throw InputError(
        path, line, FieldName(found),
        "expected " + std::to_string(count) + " fields, found " + std::to_string(found));
  }
}

double TextTable::Number(const TextRow& row, size_t k) const {
  RequireFields(row, k + 1);
  return RequireDoubleText(row.fields[k], path, row.line, FieldName(k));
}

double TextTable::NumberIn(const TextRow& row, size_t k, double lo, double hi,
                           const std::string& unit) const {
  RequireFields(row, k + 1);
  return NumberInText(row.fields[k], row.line, k, lo, hi, unit);
}

double TextTable::NumberInText(std::string_view text, long line, size_t k, double lo, double hi,
                               const std::string& unit) const {
  const ParsedNumber<double> parsed = ParseDoubleText(text);
  if (!parsed.ok()) throw InputError(path, line, FieldName(k), DescribeNumberText(text, parsed));
  if (!(parsed.value >= lo && parsed.value <= hi))
    throw InputError(path, line, FieldName(k),
                     "'" + std::string(text) + "' is outside " + limits::RangeText(lo, hi, unit));
  return parsed.value;
}

int TextTable::Id(const TextRow& row, size_t k) const {
  RequireFields(row, k + 1);
  return IdText(row.fields[k], row.line, k);
}

int TextTable::IdText(std::string_view text, long line, size_t k) const {
  const ParsedNumber<long long> parsed = ParseIntegerText(text);
  if (parsed.status != NumberTextStatus::kOk && parsed.status != NumberTextStatus::kOverflow)
    throw InputError(path, line, FieldName(k), DescribeNumberText(text, parsed, "an integer id"));
  if (!parsed.ok() || parsed.value < 0 || parsed.value > limits::kMaxId)
    throw InputError(
        path, line, FieldName(k),
        "id " + std::string(text) + " is outside [0, " + std::to_string(limits::kMaxId) + "]");
  return static_cast<int>(parsed.value);
}

TimeNs TextTable::TimestampNs(const TextRow& row, size_t k) const {
  RequireFields(row, k + 1);
  return TimestampNsText(row.fields[k], row.line, k);
}

TimeNs TextTable::TimestampNsText(std::string_view text, long line, size_t k) const {
  const ParsedNumber<long long> parsed = ParseIntegerText(text);
  const bool negative = !text.empty() && text.front() == '-';
  if (parsed.status != NumberTextStatus::kOk && parsed.status != NumberTextStatus::kOverflow)
    throw InputError(path, line, FieldName(k),
                     DescribeNumberText(text, parsed, "an integer timestamp in nanoseconds"));
  if (negative) throw InputError(path, line, FieldName(k), "negative timestamp");
  if (!parsed.ok() || parsed.value > limits::kMaxTimestampNs)
    throw InputError(path, line, FieldName(k), TimestampBeyond(std::string(text), "ns"));
  return parsed.value;
}

TimeNs TextTable::SecondsAsNs(const TextRow& row, size_t k) const {
  RequireFields(row, k + 1);
  const std::string& text = row.fields[k];
  // Decimal seconds "S[.F]" converted exactly; scientific notation falls back to double.
  const auto dot = text.find('.');
  const std::string integer = text.substr(0, dot);
  const std::string fraction = dot == std::string::npos ? "" : text.substr(dot + 1);
  const auto digits = [](const std::string& s) {
    return s.find_first_not_of("0123456789") == std::string::npos;
  };
  if (!integer.empty() && digits(integer) && digits(fraction) && integer.size() < 11) {
    const long long whole_s = ParseIntegerText(integer).value;  // at most 10 digits: no overflow
    if (whole_s >= limits::kMaxTimestampNs / kNsPerSecond)
      throw InputError(path, row.line, FieldName(k), TimestampBeyond(text, "s"));
    std::string nanos = fraction.substr(0, 9);
    nanos.resize(9, '0');
    TimeNs t = whole_s * kNsPerSecond + ParseIntegerText(nanos).value;
    if (fraction.size() > 9 && fraction[9] >= '5') ++t;
    return t;
  }
  const double seconds = Number(row, k);
  if (seconds < 0) throw InputError(path, row.line, FieldName(k), "negative timestamp");
  if (!(seconds * 1e9 <= static_cast<double>(limits::kMaxTimestampNs)))
    throw InputError(path, row.line, FieldName(k), TimestampBeyond(text, "s"));
  return SecondsToNs(seconds);
}

void TextTable::RequireIncreasing(const std::vector<TimeNs>& t_ns,
                                  const std::vector<long>& lines) const {
  for (size_t i = 1; i < t_ns.size(); ++i) RequireAfter(t_ns[i - 1], t_ns[i], lines[i]);
}

void TextTable::RequireAfter(TimeNs previous_ns, TimeNs t_ns, long line) const {
  if (t_ns == previous_ns)
    throw InputError(path, line, FieldName(0), "duplicate timestamp " + std::to_string(t_ns));
  RequireNotBefore(previous_ns, t_ns, line);
}

void TextTable::RequireNotBefore(TimeNs previous_ns, TimeNs t_ns, long line) const {
  if (t_ns < previous_ns)
    throw InputError(path, line, FieldName(0),
                     "timestamp " + std::to_string(t_ns) + " is earlier than the previous row's");
}

TextRowReader::TextRowReader(const std::string& path, Separator separator)
    : path_(path), separator_(separator) {
  file_.reset(OpenRegularFileStream(path));  // a pipe, a device, a loop: refused, never blocks
  buffer_.resize(kReadBlock);
}

TextRowReader::~TextRowReader() = default;

bool TextRowReader::NextLine(std::string_view* line) {
  size_t searched = begin_;  // no '\n' in [begin_, searched)
  for (;;) {
    const char* start = buffer_.data() + begin_;
    const void* newline = std::memchr(buffer_.data() + searched, '\n', end_ - searched);
    if (newline != nullptr) {
      const size_t length = static_cast<size_t>(static_cast<const char*>(newline) - start);
      *line = std::string_view(start, length);
      begin_ += length + 1;
      return true;
    }
    if (eof_) {  // the last line may lack its '\n'
      if (begin_ == end_) return false;
      *line = std::string_view(start, end_ - begin_);
      begin_ = end_;
      return true;
    }
    // Keep the partial line, at the front of the buffer (grown when a line fills it), and read on.
    const size_t partial = end_ - begin_;
    if (begin_ > 0) std::memmove(buffer_.data(), start, partial);
    begin_ = 0;
    end_ = searched = partial;
    if (end_ == buffer_.size()) buffer_.resize(2 * buffer_.size());
    const size_t got = std::fread(buffer_.data() + end_, 1, buffer_.size() - end_, file_.get());
    end_ += got;
    if (got == 0) eof_ = true;  // end of file or a read error: as std::getline, the end
  }
}

void TextRowReader::Split(std::string_view text, std::vector<std::string_view>* fields) const {
  fields->clear();
  if (separator_ == Separator::kComma) {
    // Every comma separates two fields ("a,,b" has three, "a," two), each trimmed.
    for (size_t begin = 0;;) {
      const size_t comma = text.find(',', begin);
      fields->push_back(TrimView(text.substr(begin, comma - begin)));
      if (comma == std::string_view::npos) return;
      begin = comma + 1;
    }
  }
  // Words between blanks (the classic locale's isspace, as `stream >> word` splits them).
  constexpr const char* kSpaces = " \t\n\v\f\r";
  for (size_t begin = text.find_first_not_of(kSpaces); begin != std::string_view::npos;) {
    const size_t end = text.find_first_of(kSpaces, begin);
    fields->push_back(text.substr(begin, end - begin));
    begin = end == std::string_view::npos ? end : text.find_first_not_of(kSpaces, end);
  }
}

const TextRowView* TextRowReader::Next() {
  std::string_view line;
  while (NextLine(&line)) {
    ++line_;
    if (line_ == 1 && line.substr(0, 3) == "\xEF\xBB\xBF") line.remove_prefix(3);  // UTF-8 BOM
    const std::string_view trimmed = TrimView(line);
    if (trimmed.empty()) continue;
    if (trimmed.front() == '#') {
      if (!any_row_) {
        // "#timestamp [ns],w_RS_S_x ..." or "# timestamp tx ty ..."
        Split(TrimView(trimmed.substr(1)), &row_.fields);
        header_.assign(row_.fields.begin(), row_.fields.end());
      }
      continue;
    }
    any_row_ = true;
    row_.line = line_;
    Split(trimmed, &row_.fields);
    return &row_;
  }
  return nullptr;
}

TextTable ReadTextTable(const std::string& path, Separator separator, bool allow_empty) {
  TextRowReader reader(path, separator);
  TextTable table;
  table.path = path;
  while (const TextRowView* row = reader.Next())
    table.rows.push_back({row->line, {row->fields.begin(), row->fields.end()}});
  table.header = reader.header();
  if (table.rows.empty() && !allow_empty) throw InputError(path, 0, "", "file has no data rows");
  return table;
}

}  // namespace mavloc
