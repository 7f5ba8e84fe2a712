#include "core/number_text.h"

#include <charconv>
#include <cmath>
#include <system_error>

#include "core/errors.h"

namespace mavloc {

namespace {

// The text without one leading '+' (from_chars takes only '-'); `ok` is false when the '+' is
// followed by another sign or by nothing.
struct WithoutPlus {
  std::string_view body;
  size_t offset = 0;  // characters dropped from the front
  bool ok = true;
};

WithoutPlus DropPlus(std::string_view text) {
  if (text.empty() || text.front() != '+') return {text, 0, true};
  const std::string_view body = text.substr(1);
  const bool ok = !body.empty() && body.front() != '+' && body.front() != '-';
  return {body, 1, ok};
}

// Checks shared by every type: an empty text, NUL bytes. False (with the status set) when the
// text cannot be a number.
template <typename T>
bool Precheck(std::string_view text, ParsedNumber<T>* out) {
  if (text.empty()) {
    out->status = NumberTextStatus::kEmpty;
    return false;
  }
  if (const size_t nul = text.find('\0'); nul != std::string_view::npos) {
    out->status = NumberTextStatus::kNulByte;
    out->stop = nul;
    return false;
  }
  return true;
}

// The decimal exponent of the leading digit of a valid decimal number ("123" -> 2, "0.05" -> -2,
// "1e999" -> 999), saturated far beyond any double's range; used to tell an overflow from an
// underflow once from_chars has reported the number out of range.
long long LeadingDigitExponent(std::string_view number) {
  size_t i = !number.empty() && number.front() == '-' ? 1 : 0;
  long long integer_digits = 0, leading_fraction_zeros = 0;
  bool in_fraction = false, nonzero_seen = false;
  for (; i < number.size() && number[i] != 'e' && number[i] != 'E'; ++i) {
    const char c = number[i];
    if (c == '.') {
      in_fraction = true;
      continue;
    }
    if (!nonzero_seen && c == '0') {
      if (in_fraction) ++leading_fraction_zeros;
      continue;
    }
    nonzero_seen = true;
    if (!in_fraction) ++integer_digits;
  }
  long long exponent = 0;
  if (i < number.size()) {
    std::string_view digits = number.substr(i + 1);
    const bool negative = !digits.empty() && digits.front() == '-';
    if (!digits.empty() && (digits.front() == '-' || digits.front() == '+'))
      digits.remove_prefix(1);
    constexpr long long kSaturated = 1'000'000'000'000LL;
    const auto [end, error] =
        std::from_chars(digits.data(), digits.data() + digits.size(), exponent);
    if (error == std::errc::result_out_of_range || exponent > kSaturated) exponent = kSaturated;
    if (negative) exponent = -exponent;
  }
  return integer_digits > 0 ? exponent + integer_digits - 1 : exponent - leading_fraction_zeros - 1;
}

template <typename T>
ParsedNumber<T> ParseWholeInteger(std::string_view text) {
  ParsedNumber<T> out;
  if (!Precheck(text, &out)) return out;
  const WithoutPlus u = DropPlus(text);
  if (!u.ok) {
    out.status = NumberTextStatus::kNotANumber;
    return out;
  }
  const char* first = u.body.data();
  const char* last = first + u.body.size();
  const auto [end, error] = std::from_chars(first, last, out.value, 10);
  if (error == std::errc::invalid_argument) {
    out.status = NumberTextStatus::kNotANumber;
  } else if (end != last) {
    out.status = NumberTextStatus::kTrailingText;
    out.stop = u.offset + static_cast<size_t>(end - first);
  } else if (error == std::errc::result_out_of_range) {
    out.status = NumberTextStatus::kOverflow;
  }
  if (!out.ok()) out.value = T{};
  return out;
}

// Text for a message: control bytes escaped here already, because an exception's what() ends at
// the first NUL byte; long texts keep their beginning and end.
std::string Shown(std::string_view text) {
  constexpr size_t kMaxShownBytes = 200;
  return PrintableMessage(std::string(text), kMaxShownBytes);
}

}  // namespace

ParsedNumber<double> ParseDoubleText(std::string_view text, NonFinite non_finite) {
  ParsedNumber<double> out;
  if (!Precheck(text, &out)) return out;
  const WithoutPlus u = DropPlus(text);
  if (!u.ok) {
    out.status = NumberTextStatus::kNotANumber;
    return out;
  }
  const char* first = u.body.data();
  const char* last = first + u.body.size();
  const auto [end, error] = std::from_chars(first, last, out.value, std::chars_format::general);
  if (error == std::errc::invalid_argument) {
    out.status = NumberTextStatus::kNotANumber;
  } else if (end != last) {
    out.status = NumberTextStatus::kTrailingText;
    out.stop = u.offset + static_cast<size_t>(end - first);
  } else if (error == std::errc::result_out_of_range) {
    out.status = LeadingDigitExponent(u.body) >= 0 ? NumberTextStatus::kOverflow
                                                   : NumberTextStatus::kUnderflow;
  } else if (!std::isfinite(out.value) && non_finite == NonFinite::kRefuse) {
    out.status = NumberTextStatus::kNotFinite;
  }
  if (!out.ok()) out.value = 0.0;
  return out;
}

ParsedNumber<long long> ParseIntegerText(std::string_view text) {
  return ParseWholeInteger<long long>(text);
}

ParsedNumber<unsigned long long> ParseUnsignedText(std::string_view text) {
  return ParseWholeInteger<unsigned long long>(text);
}

std::string DescribeNumberProblem(std::string_view text, NumberTextStatus status, size_t stop,
                                  std::string_view what, std::string_view overflow_clause) {
  const std::string quoted = "'" + Shown(text) + "'";
  const std::string is_not = quoted + " is not " + std::string(what);
  switch (status) {
    case NumberTextStatus::kOk:
      return "";
    case NumberTextStatus::kEmpty:
      return "empty value (expected " + std::string(what) + ")";
    case NumberTextStatus::kNulByte:
      return is_not + " (NUL byte at character " + std::to_string(stop + 1) + ")";
    case NumberTextStatus::kNotANumber:
      return is_not;
    case NumberTextStatus::kTrailingText:
      return is_not + " ('" + Shown(text.substr(stop)) + "' after '" + Shown(text.substr(0, stop)) +
             "')";
    case NumberTextStatus::kOverflow:
      return quoted + " " + std::string(overflow_clause);
    case NumberTextStatus::kUnderflow:
      return quoted +
             " is out of range (not 0, but closer to 0 than the smallest double, 4.9e-324)";
    case NumberTextStatus::kNotFinite:
      return quoted + " is not finite";
  }
  return is_not;
}

std::string_view FirstWord(std::string_view text) {
  return text.substr(0, text.find_first_of(" \t"));
}

double RequireDoubleText(std::string_view text, const std::string& file, long line,
                         const std::string& field, NonFinite non_finite) {
  const ParsedNumber<double> parsed = ParseDoubleText(text, non_finite);
  if (!parsed.ok()) throw InputError(file, line, field, DescribeNumberText(text, parsed));
  return parsed.value;
}

long long RequireIntegerText(std::string_view text, const std::string& file, long line,
                             const std::string& field) {
  const ParsedNumber<long long> parsed = ParseIntegerText(text);
  if (!parsed.ok())
    throw InputError(file, line, field, DescribeNumberText(text, parsed, "an integer"));
  return parsed.value;
}

}  // namespace mavloc
