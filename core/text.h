// Small string and file helpers shared by readers, reports and the sweep runner.
#pragma once

#include <string>

namespace mavloc {

// text without leading and trailing spaces, tabs, carriage returns and newlines.
std::string Trim(const std::string& text);

bool EndsWith(const std::string& text, const std::string& suffix);

// POSIX shell single quoting: ' -> '\''.
std::string ShellQuote(const std::string& text);

// The whole file as bytes; empty when it cannot be read or is not a regular file (a named pipe
// is never opened: core/input_file.h). Callers that must tell the two apart use ReadRegularFile.
std::string ReadWholeFile(const std::string& path);

}  // namespace mavloc
