// PrintableMessage (core/errors.h): every error line stays one readable line whatever the input
// held: control bytes and invalid UTF-8 escaped, valid UTF-8 kept, long messages cut in the middle
// without splitting an escape or a character; an InputError without a file does not start with
// ": ", and a NUL byte in its message does not end it.
#include "core/errors.h"

#include <gtest/gtest.h>

namespace mavloc {
namespace {

TEST(PrintableMessage, PlainTextIsUnchanged) {
  EXPECT_EQ(PrintableMessage("a.csv:3: field 'x': not a number"),
            "a.csv:3: field 'x': not a number");
}

TEST(PrintableMessage, ControlBytesAndInvalidUtf8AreEscaped) {
  const std::string raw = std::string("a\tb\nc\rd") + '\x01' + '\x7f' + '\0' + "e" + '\xff' +
                          '\xc3' + "(";  // 0xC3 followed by '(' is not a UTF-8 character
  EXPECT_EQ(PrintableMessage(raw), "a\\tb\\nc\\rd\\x01\\x7F\\x00e\\xFF\\xC3(");
}

TEST(PrintableMessage, ValidUtf8IsKept) {
  const std::string text =
      "Gr\xc3\xb6\xc3\x9f"
      "e \xe2\x80\x94 \xf0\x9f\x9a\x81";  // Größe — 🚁
  EXPECT_EQ(PrintableMessage(text), text);
  // Overlong encodings and UTF-16 surrogates are not valid UTF-8.
  EXPECT_EQ(PrintableMessage("\xc0\xaf"), "\\xC0\\xAF");
  EXPECT_EQ(PrintableMessage("\xed\xa0\x80"), "\\xED\\xA0\\x80");
}

TEST(PrintableMessage, LongMessagesAreCutInTheMiddle) {
  const std::string field(10'000'000, '7');
  const std::string message = "t.txt:2: field 'tx': '" + field + "' is not a number";
  const std::string out = PrintableMessage(message, 1000);
  EXPECT_LE(out.size(), 1000u + 40u);
  EXPECT_EQ(out.rfind("t.txt:2: field 'tx': '", 0), 0u) << out.substr(0, 40);
  EXPECT_NE(out.find("' is not a number"), std::string::npos);
  EXPECT_NE(out.find(" bytes cut] ... "), std::string::npos);
  // The number of cut bytes is what is missing.
  const size_t open = out.find(" ... ["), close = out.find(" bytes cut]");
  const size_t cut = std::stoul(out.substr(open + 6, close - open - 6));
  const size_t kept = out.size() - (out.find("] ... ") + 6 - open);
  EXPECT_EQ(cut + kept, message.size());
}

TEST(PrintableMessage, CuttingNeverSplitsAnEscapeOrACharacter) {
  std::string message;
  for (int i = 0; i < 3000; ++i) message += i % 2 ? "\x01" : "\xc3\xa9";  // \x01 and é
  const std::string out = PrintableMessage(message, 101);
  const size_t open = out.find(" ... [");
  ASSERT_NE(open, std::string::npos);
  const std::string head = out.substr(0, open);
  // The head is whole units: "é" (2 bytes) and "\x01" (4 bytes) alternate.
  std::string expected;
  for (int i = 0; expected.size() < head.size(); ++i) expected += i % 2 ? "\\x01" : "\xc3\xa9";
  EXPECT_EQ(head, expected);
}

// ---- InputError: the message a user reads is the whole message

TEST(InputError, AnOptionWithoutAFileIsNotAnEmptyName) {
  // Was ": field 'delay_s': must be >= 0".
  EXPECT_STREQ(InputError("", 0, "delay_s", "must be >= 0").what(),
               "field 'delay_s': must be >= 0");
  EXPECT_STREQ(InputError("a.csv", 3, "x", "bad").what(), "a.csv:3: field 'x': bad");
  EXPECT_STREQ(InputError("a.csv", 0, "", "bad").what(), "a.csv: bad");
}

TEST(InputError, ANulByteDoesNotEndTheMessage) {
  // what() is a C string: a ULog format "uint64_t\0timestamp" ended the line inside its quote.
  const std::string field("uint64_t\0timestamp", 18);
  const InputError error("log.ulg", 0, "", "field '" + field + "' has no 'type name' form");
  EXPECT_STREQ(error.what(), "log.ulg: field 'uint64_t\\x00timestamp' has no 'type name' form");
  EXPECT_STREQ(InputError(std::string("a\0b", 3)).what(), "a\\x00b");
}

}  // namespace
}  // namespace mavloc
