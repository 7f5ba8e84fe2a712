// Bad input is reported by throwing InputError from the I/O layers; the CLI turns it into one line
// on stderr and exit code 2. Numerical code never throws for degenerate geometry: it returns a
// status with a reason instead (DESIGN.md, "Conventions").
#pragma once

#include <stdexcept>
#include <string>

namespace mavloc {

class InputError : public std::runtime_error {
 public:
  // what() is a C string: a NUL byte in the message (a field of a binary file) is written as the
  // text \x00, so the message does not end inside a quoted value.
  explicit InputError(const std::string& message);
  // "file:line: field 'name': message"; line <= 0 omits the line, an empty field the field, an
  // empty file the file (a value of an option: "field 'delay_s': must be >= 0").
  InputError(const std::string& file, long line, const std::string& field,
             const std::string& message);
};

// A message made fit for one line of a terminal: control bytes, DEL and
// bytes that are not valid UTF-8 become \xNN (tab \t, newline \n, carriage return \r); a message
// longer than max_bytes after escaping keeps its beginning and end around
// " ... [N bytes cut] ... " (N bytes of the message), never splitting an escape or a UTF-8
// character.
std::string PrintableMessage(const std::string& message, size_t max_bytes = 1000);

}  // namespace mavloc
