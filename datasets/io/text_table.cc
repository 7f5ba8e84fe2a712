#include "datasets/io/text_table.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/errors.h"
#include "core/number_text.h"
#include "core/physical_limits.h"
#include "core/text.h"

namespace mavloc {

namespace {

std::vector<std::string> Split(const std::string& line, Separator separator) {
  std::vector<std::string> fields;
  if (separator == Separator::kComma) {
    std::stringstream stream(line);
    std::string field;
    while (std::getline(stream, field, ',')) fields.push_back(Trim(field));
    if (!line.empty() && line.back() == ',') fields.push_back("");
  } else {
    std::istringstream stream(line);
    std::string field;
    while (stream >> field) fields.push_back(field);
  }
  return fields;
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
  if (row.fields.size() < count) {
    throw InputError(path, row.line, FieldName(row.fields.size()),
                     "expected " + std::to_string(count) + " fields, found " +
                         std::to_string(row.fields.size()));
  }
}

double TextTable::Number(const TextRow& row, size_t k) const {
  RequireFields(row, k + 1);
  return RequireDoubleText(row.fields[k], path, row.line, FieldName(k));
}

double TextTable::NumberIn(const TextRow& row, size_t k, double lo, double hi,
                           const std::string& unit) const {
  const double value = Number(row, k);
  if (!(value >= lo && value <= hi))
    throw InputError(path, row.line, FieldName(k),
                     "'" + row.fields[k] + "' is outside " + limits::RangeText(lo, hi, unit));
  return value;
}

int TextTable::Id(const TextRow& row, size_t k) const {
  RequireFields(row, k + 1);
  const std::string& text = row.fields[k];
  const ParsedNumber<long long> parsed = ParseIntegerText(text);
  if (parsed.status != NumberTextStatus::kOk && parsed.status != NumberTextStatus::kOverflow)
    throw InputError(path, row.line, FieldName(k),
                     DescribeNumberText(text, parsed, "an integer id"));
  if (!parsed.ok() || parsed.value < 0 || parsed.value > limits::kMaxId)
    throw InputError(path, row.line, FieldName(k),
                     "id " + text + " is outside [0, " + std::to_string(limits::kMaxId) + "]");
  return static_cast<int>(parsed.value);
}

TimeNs TextTable::TimestampNs(const TextRow& row, size_t k) const {
  RequireFields(row, k + 1);
  const std::string& text = row.fields[k];
  const ParsedNumber<long long> parsed = ParseIntegerText(text);
  const bool negative = !text.empty() && text.front() == '-';
  if (parsed.status != NumberTextStatus::kOk && parsed.status != NumberTextStatus::kOverflow)
    throw InputError(path, row.line, FieldName(k),
                     DescribeNumberText(text, parsed, "an integer timestamp in nanoseconds"));
  if (negative) throw InputError(path, row.line, FieldName(k), "negative timestamp");
  if (!parsed.ok() || parsed.value > limits::kMaxTimestampNs)
    throw InputError(path, row.line, FieldName(k), TimestampBeyond(text, "ns"));
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
  for (size_t i = 1; i < t_ns.size(); ++i) {
    if (t_ns[i] == t_ns[i - 1])
      throw InputError(path, lines[i], FieldName(0),
                       "duplicate timestamp " + std::to_string(t_ns[i]));
    if (t_ns[i] < t_ns[i - 1])
      throw InputError(
          path, lines[i], FieldName(0),
          "timestamp " + std::to_string(t_ns[i]) + " is earlier than the previous row's");
  }
}

TextTable ReadTextTable(const std::string& path, Separator separator, bool allow_empty) {
  if (!std::filesystem::exists(path)) throw InputError(path, 0, "", "file does not exist");
  if (std::filesystem::is_directory(path)) throw InputError(path, 0, "", "is a folder, not a file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, 0, "", "cannot open file");
  TextTable table;
  table.path = path;
  std::string line;
  long number = 0;
  while (std::getline(in, line)) {
    ++number;
    if (number == 1 && line.rfind("\xEF\xBB\xBF", 0) == 0) line.erase(0, 3);  // UTF-8 BOM
    const std::string trimmed = Trim(line);
    if (trimmed.empty()) continue;
    if (trimmed.front() == '#') {
      if (table.rows.empty()) {
        // "#timestamp [ns],w_RS_S_x ..." or "# timestamp tx ty ..."
        std::string body = Trim(trimmed.substr(1));
        table.header = Split(body, separator);
      }
      continue;
    }
    table.rows.push_back({number, Split(trimmed, separator)});
  }
  if (table.rows.empty() && !allow_empty) throw InputError(path, 0, "", "file has no data rows");
  return table;
}

}  // namespace mavloc
