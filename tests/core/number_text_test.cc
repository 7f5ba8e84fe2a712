// The strict number parser every text reader uses (core/number_text.h): whole-text parsing over
// the full length (a NUL byte is refused, never read as the end of the number), the reasons it
// gives, and the InputError of the Require* helpers.
#include "core/number_text.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "core/errors.h"

namespace mavloc {
namespace {

// "2.1", a NUL byte, "40": C-string parsing reads 2.1.
const std::string kNulInside = std::string("2.1") + '\0' + "40";

struct DoubleCase {
  const char* name;
  std::string text;
  NumberTextStatus status;
  double value = 0.0;  // when status is kOk
};

class ParseDouble : public ::testing::TestWithParam<DoubleCase> {};

TEST_P(ParseDouble, StatusAndValue) {
  const DoubleCase& c = GetParam();
  const ParsedNumber<double> parsed = ParseDoubleText(c.text);
  EXPECT_EQ(parsed.status, c.status) << DescribeNumberText(c.text, parsed);
  if (c.status == NumberTextStatus::kOk) {
    EXPECT_EQ(parsed.value, c.value);
  }
}

INSTANTIATE_TEST_SUITE_P(
    Cases, ParseDouble,
    ::testing::Values(
        DoubleCase{"Plain", "1.5", NumberTextStatus::kOk, 1.5},
        DoubleCase{"Negative", "-0.25", NumberTextStatus::kOk, -0.25},
        DoubleCase{"LeadingPlus", "+2", NumberTextStatus::kOk, 2.0},
        DoubleCase{"NoIntegerPart", ".5", NumberTextStatus::kOk, 0.5},
        DoubleCase{"NoFraction", "1.", NumberTextStatus::kOk, 1.0},
        DoubleCase{"Exponent", "1e-3", NumberTextStatus::kOk, 1e-3},
        DoubleCase{"LargestDouble", "1.7976931348623157e308", NumberTextStatus::kOk,
                   std::numeric_limits<double>::max()},
        DoubleCase{"Subnormal", "4.9e-324", NumberTextStatus::kOk,
                   std::numeric_limits<double>::denorm_min()},
        DoubleCase{"ZeroWithHugeNegativeExponent", "0e-99999", NumberTextStatus::kOk, 0.0},
        DoubleCase{"Empty", "", NumberTextStatus::kEmpty},
        DoubleCase{"NulInside", kNulInside, NumberTextStatus::kNulByte},
        DoubleCase{"NulAtEnd", std::string("2.1") + '\0', NumberTextStatus::kNulByte},
        DoubleCase{"Word", "abc", NumberTextStatus::kNotANumber},
        DoubleCase{"SignAlone", "-", NumberTextStatus::kNotANumber},
        DoubleCase{"TwoSigns", "+-1", NumberTextStatus::kNotANumber},
        DoubleCase{"LeadingBlank", " 1", NumberTextStatus::kNotANumber},
        DoubleCase{"TrailingLetter", "1.5x", NumberTextStatus::kTrailingText},
        DoubleCase{"TrailingBlank", "1.5 ", NumberTextStatus::kTrailingText},
        DoubleCase{"TwoNumbers", "2.1 40", NumberTextStatus::kTrailingText},
        DoubleCase{"Hexadecimal", "0x10", NumberTextStatus::kTrailingText},
        DoubleCase{"DecimalComma", "1,5", NumberTextStatus::kTrailingText},
        DoubleCase{"ExponentWithoutDigits", "1e", NumberTextStatus::kTrailingText},
        DoubleCase{"Overflow", "1e999", NumberTextStatus::kOverflow},
        DoubleCase{"NegativeOverflow", "-1e999", NumberTextStatus::kOverflow},
        DoubleCase{"OverflowByDigits", "1" + std::string(400, '0'), NumberTextStatus::kOverflow},
        DoubleCase{"Underflow", "1e-400", NumberTextStatus::kUnderflow},
        DoubleCase{"UnderflowByDigits", "0." + std::string(400, '0') + "1",
                   NumberTextStatus::kUnderflow},
        DoubleCase{"Infinity", "inf", NumberTextStatus::kNotFinite},
        DoubleCase{"NegativeInfinity", "-Infinity", NumberTextStatus::kNotFinite},
        DoubleCase{"NaN", "nan", NumberTextStatus::kNotFinite}),
    [](const auto& test_info) { return std::string(test_info.param.name); });

TEST(ParseDoubleText, NonFiniteAllowedWhenAsked) {
  EXPECT_TRUE(std::isinf(ParseDoubleText("inf", NonFinite::kAllow).value));
  EXPECT_TRUE(std::isnan(ParseDoubleText("nan", NonFinite::kAllow).value));
  // Allowing inf does not make an overflow a number.
  EXPECT_EQ(ParseDoubleText("1e999", NonFinite::kAllow).status, NumberTextStatus::kOverflow);
}

TEST(ParseDoubleText, ReadsTheWholeLengthOfAView) {
  // A view into a longer buffer ends where the view ends, not at a NUL or at the buffer's end.
  const std::string buffer = "12.5,7";
  EXPECT_EQ(ParseDoubleText(std::string_view(buffer).substr(0, 4)).value, 12.5);
  EXPECT_EQ(ParseDoubleText(buffer).status, NumberTextStatus::kTrailingText);
}

TEST(ParseIntegerText, WholeIntegersOnly) {
  EXPECT_EQ(ParseIntegerText("17").value, 17);
  EXPECT_EQ(ParseIntegerText("-17").value, -17);
  EXPECT_EQ(ParseIntegerText("+17").value, 17);
  EXPECT_EQ(ParseIntegerText("9223372036854775807").value, std::numeric_limits<long long>::max());
  EXPECT_EQ(ParseIntegerText("17.0").status, NumberTextStatus::kTrailingText);
  EXPECT_EQ(ParseIntegerText("1e3").status, NumberTextStatus::kTrailingText);
  EXPECT_EQ(ParseIntegerText("0x11").status, NumberTextStatus::kTrailingText);
  EXPECT_EQ(ParseIntegerText(std::string("17") + '\0' + "5").status, NumberTextStatus::kNulByte);
  EXPECT_EQ(ParseIntegerText("").status, NumberTextStatus::kEmpty);
  EXPECT_EQ(ParseIntegerText("seven").status, NumberTextStatus::kNotANumber);
  EXPECT_EQ(ParseIntegerText("9223372036854775808").status, NumberTextStatus::kOverflow);
  EXPECT_EQ(ParseIntegerText("-9223372036854775809").status, NumberTextStatus::kOverflow);
}

TEST(ParseUnsignedText, NoMinusSign) {
  EXPECT_EQ(ParseUnsignedText("18446744073709551615").value,
            std::numeric_limits<unsigned long long>::max());
  EXPECT_EQ(ParseUnsignedText("18446744073709551616").status, NumberTextStatus::kOverflow);
  EXPECT_EQ(ParseUnsignedText("-1").status, NumberTextStatus::kNotANumber);
}

TEST(DescribeNumberText, SaysWhyWithTheText) {
  const auto describe = [](const std::string& text) {
    return DescribeNumberText(text, ParseDoubleText(text));
  };
  EXPECT_EQ(describe("1.5x"), "'1.5x' is not a number ('x' after '1.5')");
  // Control bytes are escaped in the message itself: an exception's what() would end at the NUL.
  EXPECT_EQ(describe(kNulInside), "'2.1\\x0040' is not a number (NUL byte at character 4)");
  EXPECT_EQ(describe(""), "empty value (expected a number)");
  EXPECT_EQ(describe("abc"), "'abc' is not a number");
  EXPECT_EQ(describe("nan"), "'nan' is not finite");
  EXPECT_EQ(describe("1e999"), "'1e999' is not finite (beyond the largest double, 1.8e+308)");
  EXPECT_NE(describe("1e-400").find("'1e-400' is out of range"), std::string::npos);
  EXPECT_EQ(DescribeNumberText("1.5", ParseIntegerText("1.5"), "an integer"),
            "'1.5' is not an integer ('.5' after '1')");
  EXPECT_NE(DescribeNumberText("9223372036854775808", ParseIntegerText("9223372036854775808"),
                               "an integer")
                .find("out of range"),
            std::string::npos);
}

TEST(RequireDoubleText, InputErrorNamesFileLineAndField) {
  EXPECT_EQ(RequireDoubleText("3.25", "f.csv", 4, "x"), 3.25);
  try {
    RequireDoubleText(kNulInside, "f.csv", 4, "x");
    FAIL() << "accepted a NUL byte";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              "f.csv:4: field 'x': '2.1\\x0040' is not a number (NUL byte at character 4)");
  }
  EXPECT_THROW(RequireIntegerText("12abc", "f.yaml", 2, "id"), InputError);
  EXPECT_EQ(RequireIntegerText("-12", "f.yaml", 2, "id"), -12);
}

TEST(FirstWord, TextBeforeTheFirstBlank) {
  EXPECT_EQ(FirstWord("1 per bearing angle"), "1");
  EXPECT_EQ(FirstWord("0.5\tpx"), "0.5");
  EXPECT_EQ(FirstWord("2.5"), "2.5");
  EXPECT_EQ(FirstWord(""), "");
}

}  // namespace
}  // namespace mavloc
