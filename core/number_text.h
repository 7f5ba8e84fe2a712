// The one strict parser of numbers written as text, used by every reader of text files, settings
// and options. The whole text must be the number: it is read with std::from_chars over its full
// length (never as a C string, which would stop at a NUL byte and read "2.1<NUL>40" as 2.1), so a
// NUL byte, text after the number, an empty text, a value beyond the range of the type and (unless
// allowed) inf or nan are refused with the reason. Accepted spellings: an optional leading '+'
// (one, not followed by a sign), decimal digits, a fraction and an exponent ("1", "-0.5", ".5",
// "1.", "1e-3"); no blanks around the number (readers trim their fields), no hexadecimal, no
// locale-dependent separators.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <type_traits>

namespace mavloc {

// Why a text is not a number of the asked kind; kOk when it is.
enum class NumberTextStatus {
  kOk,
  kEmpty,         // ""
  kNulByte,       // a NUL byte anywhere in the text
  kNotANumber,    // the text does not start with a number ("abc", "-", " 1", "0x" after '+')
  kTrailingText,  // a number followed by other characters ("1.5x", "2.1 40", "1.0" as integer)
  kOverflow,      // beyond the largest value of the type ("1e999", 2^63 as a 64-bit integer)
  kUnderflow,     // a nonzero double closer to 0 than the smallest one ("1e-400")
  kNotFinite,     // "inf", "nan" where only finite values are allowed
};

// Whether "inf", "infinity" and "nan" (any case, optionally signed) are accepted as doubles.
enum class NonFinite { kRefuse, kAllow };

template <typename T>
struct ParsedNumber {
  T value{};
  NumberTextStatus status = NumberTextStatus::kOk;
  // kNulByte: offset of the first NUL byte; kTrailingText: offset of the first character after
  // the number.
  size_t stop = 0;
  bool ok() const { return status == NumberTextStatus::kOk; }
};

ParsedNumber<double> ParseDoubleText(std::string_view text,
                                     NonFinite non_finite = NonFinite::kRefuse);
// Base-10 integers of the whole text ("17"; "17.0", "1e3" and "0x11" are not integers).
ParsedNumber<long long> ParseIntegerText(std::string_view text);
// As ParseIntegerText, without a sign other than one leading '+'; a '-' is kNotANumber.
ParsedNumber<unsigned long long> ParseUnsignedText(std::string_view text);

// DescribeNumberText for any type; overflow_clause ends the message of kOverflow ("is not finite
// (beyond the largest double, 1.8e+308)").
std::string DescribeNumberProblem(std::string_view text, NumberTextStatus status, size_t stop,
                                  std::string_view what, std::string_view overflow_clause);

// The reason as one clause of a message, quoting the text: "'1.5x' is not a number ('x' after
// '1.5')", "'1e999' is not finite (beyond the largest double, 1.8e+308)", "empty value (expected
// a number)". `what` names what was expected ("a number", "an integer", "an integer timestamp in
// nanoseconds"). The quoted text is made printable here (PrintableMessage of core/errors.h: a NUL
// byte shows as \x00, at most 200 bytes), since an exception's what() would end at a NUL byte.
template <typename T>
std::string DescribeNumberText(std::string_view text, const ParsedNumber<T>& parsed,
                               std::string_view what = "a number") {
  std::string_view overflow;
  if constexpr (std::is_same_v<T, double>)
    overflow = "is not finite (beyond the largest double, 1.8e+308)";
  else if constexpr (std::is_same_v<T, long long>)
    overflow =
        "is out of range (a 64-bit integer holds -9223372036854775808 .. "
        "9223372036854775807)";
  else
    overflow = "is out of range (beyond the largest 64-bit integer, 18446744073709551615)";
  return DescribeNumberProblem(text, parsed.status, parsed.stop, what, overflow);
}

// The text before its first blank (space or tab): the number of a value whose other words
// describe it ("1 per bearing angle"), to be parsed whole.
std::string_view FirstWord(std::string_view text);

// Parse or throw InputError(file, line, field, DescribeNumberText(...)).
double RequireDoubleText(std::string_view text, const std::string& file, long line,
                         const std::string& field, NonFinite non_finite = NonFinite::kRefuse);
long long RequireIntegerText(std::string_view text, const std::string& file, long line,
                             const std::string& field);

}  // namespace mavloc
