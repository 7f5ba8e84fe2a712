// A CSV field (RFC 4180): as it is, or in double quotes with quotes doubled when it holds a comma,
// a quote or a line break.
#pragma once

#include <string>

namespace mavloc {

inline std::string CsvField(const std::string& text) {
  if (text.find_first_of(",\"\n\r") == std::string::npos) return text;
  std::string quoted = "\"";
  for (const char c : text) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + "\"";
}

}  // namespace mavloc
