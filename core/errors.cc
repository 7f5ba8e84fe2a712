#include "core/errors.h"

#include <algorithm>
#include <cstdio>
#include <sstream>
#include <vector>

namespace mavloc {

namespace {
std::string Format(const std::string& file, long line, const std::string& field,
                   const std::string& message) {
  std::ostringstream text;
  if (!file.empty()) {
    text << file;
    if (line > 0) text << ':' << line;
    text << ": ";
  }
  if (!field.empty()) text << "field '" << field << "': ";
  text << message;
  return text.str();
}
// Length of the valid UTF-8 sequence starting at text[i] (RFC 3629: no overlong forms, no
// surrogates, at most U+10FFFF), or 0 when the byte does not start one.
size_t Utf8SequenceLength(const std::string& text, size_t i) {
  const auto byte = [&](size_t k) { return static_cast<unsigned char>(text[k]); };
  const unsigned char b0 = byte(i);
  size_t length = 0;
  unsigned char low = 0x80, high = 0xBF;  // allowed range of the second byte
  if (b0 >= 0xC2 && b0 <= 0xDF) {
    length = 2;
  } else if (b0 >= 0xE0 && b0 <= 0xEF) {
    length = 3;
    if (b0 == 0xE0) low = 0xA0;
    if (b0 == 0xED) high = 0x9F;
  } else if (b0 >= 0xF0 && b0 <= 0xF4) {
    length = 4;
    if (b0 == 0xF0) low = 0x90;
    if (b0 == 0xF4) high = 0x8F;
  } else {
    return 0;
  }
  if (i + length > text.size()) return 0;
  if (byte(i + 1) < low || byte(i + 1) > high) return 0;
  for (size_t k = 2; k < length; ++k)
    if (byte(i + k) < 0x80 || byte(i + k) > 0xBF) return 0;
  return length;
}

}  // namespace

namespace {

struct EscapedUnit {
  std::string text;        // as printed
  size_t input_bytes = 0;  // bytes of the message it stands for
};

// One unit per character of message[begin, end).
std::vector<EscapedUnit> EscapeUnits(const std::string& message, size_t begin, size_t end) {
  std::vector<EscapedUnit> units;
  units.reserve(end - begin);
  for (size_t i = begin; i < end;) {
    const unsigned char c = static_cast<unsigned char>(message[i]);
    EscapedUnit unit;
    unit.input_bytes = 1;
    if (c >= 0x20 && c < 0x7F) {
      unit.text.assign(1, static_cast<char>(c));
    } else if (c == '\t' || c == '\n' || c == '\r') {
      unit.text.assign({'\\', c == '\t' ? 't' : c == '\n' ? 'n' : 'r'});
    } else if (const size_t length = c >= 0x80 ? Utf8SequenceLength(message, i) : 0;
               length > 0 && i + length <= end) {
      unit.text = message.substr(i, length);
      unit.input_bytes = length;
    } else {
      char hex[5];
      std::snprintf(hex, sizeof(hex), "\\x%02X", c);
      unit.text = hex;
    }
    i += unit.input_bytes;
    units.push_back(std::move(unit));
  }
  return units;
}

}  // namespace

std::string PrintableMessage(const std::string& message, size_t max_bytes) {
  const size_t n = message.size();
  std::string out;
  // Every input byte prints as at least one byte: a message that fits after escaping is at most
  // max_bytes long, and a cut one only needs its first and last max_bytes (+ one character).
  if (n <= 2 * max_bytes + 8) {
    const auto units = EscapeUnits(message, 0, n);
    size_t printed = 0;
    for (const auto& unit : units) printed += unit.text.size();
    if (printed <= max_bytes) {
      for (const auto& unit : units) out += unit.text;
      return out;
    }
  }
  const size_t head_budget = max_bytes * 3 / 4, tail_budget = max_bytes - head_budget;
  const auto head_units = EscapeUnits(message, 0, std::min(n, max_bytes + 4));
  // The tail region may start inside a character; only its last tail_budget bytes are used.
  const size_t tail_begin = n > max_bytes + 4 ? n - max_bytes - 4 : 0;
  const auto tail_units = EscapeUnits(message, tail_begin, n);
  size_t head = 0, head_printed = 0, head_input = 0;
  while (head < head_units.size() && head_printed + head_units[head].text.size() <= head_budget) {
    head_printed += head_units[head].text.size();
    head_input += head_units[head++].input_bytes;
  }
  size_t tail = tail_units.size(), tail_printed = 0, tail_input = 0;
  while (tail > 0 && tail_printed + tail_units[tail - 1].text.size() <= tail_budget &&
         head_input + tail_input + tail_units[tail - 1].input_bytes <= n) {
    tail_printed += tail_units[tail - 1].text.size();
    tail_input += tail_units[--tail].input_bytes;
  }
  for (size_t k = 0; k < head; ++k) out += head_units[k].text;
  out += " ... [" + std::to_string(n - head_input - tail_input) + " bytes cut] ... ";
  for (size_t k = tail; k < tail_units.size(); ++k) out += tail_units[k].text;
  return out;
}

namespace {

std::string WithoutNul(const std::string& text) {
  if (text.find('\0') == std::string::npos) return text;
  std::string out;
  out.reserve(text.size() + 8);
  for (const char c : text) {
    if (c == '\0')
      out += "\\x00";
    else
      out += c;
  }
  return out;
}

}  // namespace

InputError::InputError(const std::string& message) : std::runtime_error(WithoutNul(message)) {}

InputError::InputError(const std::string& file, long line, const std::string& field,
                       const std::string& message)
    : std::runtime_error(WithoutNul(Format(file, line, field, message))) {}

}  // namespace mavloc
