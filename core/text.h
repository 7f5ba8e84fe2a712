// Small string and file helpers shared by readers, reports and the sweep runner.
#pragma once

#include <string>

namespace mavloc {

// text without leading and trailing spaces, tabs, carriage returns and newlines.
std::string Trim(const std::string& text);

bool EndsWith(const std::string& text, const std::string& suffix);

// POSIX shell single quoting: ' -> '\''.
std::string ShellQuote(const std::string& text);

// The whole file as bytes; empty when it cannot be read (callers that must tell the two apart
// check the file first).
std::string ReadWholeFile(const std::string& path);

}  // namespace mavloc
