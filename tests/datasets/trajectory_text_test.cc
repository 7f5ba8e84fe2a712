// The text layer under the trajectory readers (datasets/io/trajectory_formats/trajectory_text.h):
// one block read of the file, rows as spans of its bytes, fields as views made on demand. Its
// rows, line numbers, fields, header and flags are checked against a line-by-line reference
// (std::getline and std::istringstream, the way the layer was written before it read blocks) on
// the variants real files have: CRLF, a byte order mark, comments and blank lines anywhere, tabs
// and runs of blanks, comma rows with blanks and a trailing comma, headers without '#', a
// truncated last line, no final newline; and through ReadTrajectory, the stamps and numbers that
// the fast paths parse (exponents, fractions past nanoseconds, a leading '+') and the messages of
// rows that do not parse (file:line and field).
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <fstream>
#include <sstream>

#include "core/errors.h"
#include "core/number_text.h"
#include "core/text.h"
#include "datasets/io/trajectory_formats/trajectory_format.h"
#include "datasets/io/trajectory_formats/trajectory_text.h"
#include "tests/test_support.h"

namespace mavloc {
namespace {

struct ReferenceRow {
  long line = 0;
  std::vector<std::string> fields;
};

struct ReferenceText {
  std::vector<std::string> header;
  std::string header_line;
  std::vector<ReferenceRow> rows;
  bool comma_separated = false, had_bom = false, had_crlf = false;
};

std::vector<std::string> ReferenceSplit(const std::string& line, bool comma_separated) {
  std::vector<std::string> fields;
  if (comma_separated) {
    size_t start = 0;
    while (true) {
      const size_t comma = line.find(',', start);
      fields.push_back(
          Trim(line.substr(start, comma == std::string::npos ? std::string::npos : comma - start)));
      if (comma == std::string::npos) break;
      start = comma + 1;
    }
    if (fields.size() > 1 && fields.back().empty()) fields.pop_back();
  } else {
    std::istringstream stream(line);
    std::string field;
    while (stream >> field) fields.push_back(field);
  }
  return fields;
}

// The rules of trajectory_text.h applied line by line with std::getline.
ReferenceText ReferenceRead(const std::string& bytes) {
  ReferenceText text;
  std::istringstream in(bytes);
  std::string line;
  long number = 0;
  bool header_row_checked = false;
  while (std::getline(in, line)) {
    ++number;
    if (number == 1 && line.size() >= 3 && static_cast<unsigned char>(line[0]) == 0xEF &&
        static_cast<unsigned char>(line[1]) == 0xBB &&
        static_cast<unsigned char>(line[2]) == 0xBF) {
      line.erase(0, 3);
      text.had_bom = true;
    }
    if (!line.empty() && line.back() == '\r') {
      line.pop_back();
      text.had_crlf = true;
    }
    const std::string trimmed = Trim(line);
    if (trimmed.empty()) continue;
    if (trimmed.front() == '#') {
      if (text.rows.empty()) {
        text.header_line = Trim(trimmed.substr(1));
        text.header =
            ReferenceSplit(text.header_line, text.header_line.find(',') != std::string::npos);
      }
      continue;
    }
    if (text.rows.empty() && !header_row_checked) {
      header_row_checked = true;
      text.comma_separated = trimmed.find(',') != std::string::npos;
      std::vector<std::string> fields = ReferenceSplit(trimmed, text.comma_separated);
      const NumberTextStatus status = fields.empty()
                                          ? NumberTextStatus::kEmpty
                                          : ParseDoubleText(fields[0], NonFinite::kAllow).status;
      const bool numeric =
          status != NumberTextStatus::kEmpty && status != NumberTextStatus::kNotANumber;
      if (!fields.empty() && !fields[0].empty() && !numeric &&
          (std::isalpha(static_cast<unsigned char>(fields[0][0])) || fields[0][0] == '%')) {
        text.header_line = trimmed;
        text.header = std::move(fields);
        continue;
      }
      text.rows.push_back({number, std::move(fields)});
      continue;
    }
    if (text.rows.empty()) text.comma_separated = trimmed.find(',') != std::string::npos;
    text.rows.push_back({number, ReferenceSplit(trimmed, text.comma_separated)});
  }
  return text;
}

struct TextCase {
  const char* name;
  std::string bytes;
};

std::vector<TextCase> TextCases() {
  const std::string bom = "\xEF\xBB\xBF";
  return {
      {"Plain", "1.0 1 2 3 0 0 0 1\n2.0 4 5 6 0 0 0 1\n"},
      {"NoFinalNewline", "1.0 1 2 3 0 0 0 1\n2.0 4 5 6 0 0 0 1"},
      {"TruncatedLastLine", "1.0 1 2 3 0 0 0 1\n2.0 4 5"},
      {"Crlf", "# timestamp tx ty tz qx qy qz qw\r\n1.0 1 2 3 0 0 0 1\r\n2.0 4 5 6 0 0 0 1\r\n"},
      {"CrlfNoFinalNewline", "1.0 1 2 3 0 0 0 1\r\n2.0 4 5 6 0 0 0 1\r"},
      {"BomAndHeader", bom + "#timestamp,x,y,z,qw,qx,qy,qz\n100,1,2,3,1,0,0,0\n"},
      {"BomOnly", bom},
      {"BlankAndCommentLinesAnywhere",
       "\n\n# first\n  \t \n# timestamp tx ty tz qx qy qz qw\n1.0 1 2 3 0 0 0 1\n\n# later "
       "comment\n"
       "   # indented comment\n2.0 4 5 6 0 0 0 1\n\n\n"},
      {"TabsAndRunsOfBlanks", "  1.0\t1  2\t\t3 0 0 0 1  \n2.0 \t 4 5 6 0 0 0 1\t\n"},
      {"VerticalTabAndFormFeedSeparate", "1.0\v1\f2 3 0 0 0 1\n"},
      {"CarriageReturnInsideARow", "1.0 1\r2 3 0 0 0 1\n"},
      {"CommaRowsWithBlanksAndTrailingComma",
       "100, 1 ,2,\t3,1,0,0,0,\n200,4,5,6,1,0,0,0,\n300,,5,6,1,0,0,0\n"},
      {"CommaHeaderWithoutHash", "timestamp,x,y,z,qw,qx,qy,qz\n100,1,2,3,1,0,0,0\n"},
      {"RostopicHeader", "%time,field.header.stamp,field.pose.position.x\n1,2,3\n"},
      {"NanRowIsData", "nan 1 2 3 0 0 0 1\n"},
      {"FirstRowWhitespaceThenComma", "timestamp x y\n1,2,3\n4,5,6\n"},
      {"HeaderAfterDataIsAComment", "1.0 1 2 3 0 0 0 1\n# timestamp,x\n2.0 4 5 6 0 0 0 1\n"},
      {"OnlyComments", "# nothing\n# here\n"},
      {"Empty", ""},
      {"OnlyNewlines", "\n\n\r\n"},
      {"NulByteInField", std::string("1.0 1 2\0 3 0 0 0 1\n", 20)},
      {"ExponentForms", "1.5e0 1e-3 -2.5E+2 3 0 0 0 1\n"},
  };
}

class TrajectoryTextMatchesLineReader : public ::testing::TestWithParam<TextCase> {};

TEST_P(TrajectoryTextMatchesLineReader, RowsFieldsHeaderFlags) {
  const TextCase& c = GetParam();
  const std::string path = testing::MakeTempDir() + "/t.txt";
  testing::WriteFileBytes(path, c.bytes);
  const ReferenceText expected = ReferenceRead(c.bytes);
  const TrajectoryText text = ReadTrajectoryText(path);
  EXPECT_EQ(text.header, expected.header);
  EXPECT_EQ(text.header_line, expected.header_line);
  EXPECT_EQ(text.comma_separated, expected.comma_separated);
  EXPECT_EQ(text.had_bom, expected.had_bom);
  EXPECT_EQ(text.had_crlf, expected.had_crlf);
  ASSERT_EQ(text.rows.size(), expected.rows.size());
  for (size_t i = 0; i < text.rows.size(); ++i) {
    EXPECT_EQ(text.rows[i].line, expected.rows[i].line) << "row " << i;
    const std::vector<std::string_view> fields = text.Fields(text.rows[i]);
    EXPECT_EQ(std::vector<std::string>(fields.begin(), fields.end()), expected.rows[i].fields)
        << "row " << i;
  }
}

INSTANTIATE_TEST_SUITE_P(Cases, TrajectoryTextMatchesLineReader, ::testing::ValuesIn(TextCases()),
                         [](const auto& test_info) { return std::string(test_info.param.name); });

// Rows longer than a read block and a file of many blocks are split as line by line.
TEST(TrajectoryText, LongRowsAndManyBlocks) {
  std::string bytes = "# timestamp tx ty tz qx qy qz qw\n";
  bytes += "1.0 " + std::string(3 << 20, '7') + " 2 3 0 0 0 1\r\n";
  for (int i = 0; i < 60000; ++i)
    bytes += std::to_string(2 + i) + ".25 1 2 3 0 0 0.6 0.8" + (i % 7 == 0 ? "\r\n" : "\n");
  bytes += "\n# end";
  const std::string path = testing::MakeTempDir() + "/long.txt";
  testing::WriteFileBytes(path, bytes);
  const ReferenceText expected = ReferenceRead(bytes);
  const TrajectoryText text = ReadTrajectoryText(path);
  ASSERT_EQ(text.rows.size(), expected.rows.size());
  EXPECT_EQ(text.had_crlf, expected.had_crlf);
  std::vector<std::string_view> fields;
  for (size_t i = 0; i < text.rows.size(); ++i) {
    text.Fields(text.rows[i], &fields);
    ASSERT_EQ(text.rows[i].line, expected.rows[i].line);
    ASSERT_EQ(std::vector<std::string>(fields.begin(), fields.end()), expected.rows[i].fields);
  }
}

TEST(TrajectoryText, MissingFileAndFolder) {
  const std::string dir = testing::MakeTempDir();
  try {
    ReadTrajectoryText(dir + "/none.txt");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("file does not exist"), std::string::npos) << e.what();
  }
  try {
    ReadTrajectoryText(dir);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("is a folder, not a file"), std::string::npos) << e.what();
  }
}

LoadedTrajectory ReadBytes(const std::string& bytes, TrajectoryReadOptions options = {}) {
  const std::string path = testing::MakeTempDir() + "/t.txt";
  testing::WriteFileBytes(path, bytes);
  return ReadTrajectory(path, options);
}

std::string ReadError(const std::string& bytes) {
  try {
    ReadBytes(bytes);
  } catch (const InputError& e) {
    return e.what();
  }
  return "(accepted)";
}

// The stamps and numbers of TUM rows as the parsers read them: exact decimal seconds, fractions
// past nanoseconds rounded half up, exponents through double, a leading '+'.
TEST(TrajectoryTextThroughReader, StampAndNumberForms) {
  const LoadedTrajectory t = ReadBytes(
      "# timestamp tx ty tz qx qy qz qw\r\n"
      "1403636579.763555584 1.5e0 -2.5E+2 1e-3 0 0 0 1\r\n"
      "\r\n"
      "1403636579.7635555845 +1 2. .5 0 0 0.6 0.8\r\n"
      "1.403636580e9 0 0 0 0 0 0 1");
  ASSERT_EQ(t.poses.size(), 3u);
  EXPECT_EQ(t.poses[0].t_ns, 1403636579763555584);
  EXPECT_EQ(t.poses[1].t_ns, 1403636579763555585);
  EXPECT_EQ(t.poses[2].t_ns, 1403636580000000000);
  EXPECT_EQ(t.poses[0].T_W_B.p, Eigen::Vector3d(1.5, -250.0, 1e-3));
  EXPECT_EQ(t.poses[1].T_W_B.p, Eigen::Vector3d(1.0, 2.0, 0.5));
  EXPECT_NEAR(t.poses[1].T_W_B.q.z(), 0.6, 1e-15);
  EXPECT_TRUE(t.report.had_crlf);
  EXPECT_EQ(t.report.rows, 3u);
}

TEST(TrajectoryTextThroughReader, RowsThatDoNotParseNameFileLineAndField) {
  // A truncated last line (no newline): too few fields on line 3, the first missing one named.
  std::string message = ReadError("1.0 1 2 3 0 0 0 1\n\n2.0 4 5");
  EXPECT_NE(message.find("t.txt:3: field 'tz'"), std::string::npos) << message;
  EXPECT_NE(message.find("expected 8 fields (timestamp tx ty tz qx qy qz qw), found 3"),
            std::string::npos)
      << message;
  // A bad number after CRLF lines and comments keeps its line number.
  message = ReadError("# c\r\n1.0 1 2 3 0 0 0 1\r\n# c\r\n2.0 4 5x 6 0 0 0 1\r\n");
  EXPECT_NE(message.find("t.txt:4: field 'ty'"), std::string::npos) << message;
  EXPECT_NE(message.find("'5x'"), std::string::npos) << message;
  // A NUL byte inside a field.
  message = ReadError(std::string("1.0 1 2\0 3 0 0 0 1\n", 20));
  EXPECT_NE(message.find("t.txt:1: field 'ty'"), std::string::npos) << message;
  EXPECT_NE(message.find("\\x00"), std::string::npos) << message;
  // A stamp in nanoseconds in a TUM file.
  message = ReadError("1403636579763555584 1 2 3 0 0 0 1\n");
  EXPECT_NE(message.find("t.txt:1: field 'timestamp'"), std::string::npos) << message;
  EXPECT_NE(message.find("look like nanoseconds (divide by 1e9)"), std::string::npos) << message;
  // A parse error on a later row wins over rows out of order before it (every row is parsed
  // before the order is checked).
  message = ReadError("2.0 1 2 3 0 0 0 1\n1.0 1 2 3 0 0 0 1\n3.0 1 2 3 0 0 0 2\n");
  EXPECT_NE(message.find("t.txt:3: field 'qw'"), std::string::npos) << message;
  EXPECT_NE(message.find("quaternion is not unit length"), std::string::npos) << message;
  message = ReadError("2.0 1 2 3 0 0 0 1\n1.0 1 2 3 0 0 0 1\n");
  EXPECT_NE(message.find("t.txt:2: field 'timestamp'"), std::string::npos) << message;
  EXPECT_NE(message.find("is earlier than the previous row's"), std::string::npos) << message;
  EXPECT_NE(ReadError("\n# only a comment\n\n").find("file has no data rows"), std::string::npos);
}

// --sort and repeated stamps, in place: stable order, the first of equal stamps kept, the lines
// reported as before.
TEST(TrajectoryTextThroughReader, SortAndRepeatedStamps) {
  TrajectoryReadOptions options;
  options.sort = true;
  const LoadedTrajectory t = ReadBytes(
      "3.0 3 0 0 0 0 0 1\n1.0 1 0 0 0 0 0 1\n2.0 2 0 0 0 0 0 1\n1.0 9 0 0 0 0 0 1\n"
      "3.0 8 0 0 0 0 0 1\n",
      options);
  ASSERT_EQ(t.poses.size(), 3u);
  EXPECT_EQ(t.poses[0].T_W_B.p.x(), 1.0);
  EXPECT_EQ(t.poses[1].T_W_B.p.x(), 2.0);
  EXPECT_EQ(t.poses[2].T_W_B.p.x(), 3.0);
  EXPECT_EQ(t.report.rows_out_of_order, 3u);
  EXPECT_EQ(t.report.first_out_of_order_line, 2);
  EXPECT_EQ(t.report.duplicates_dropped, 2u);
  EXPECT_EQ(t.report.first_duplicate_line, 4);
  const LoadedTrajectory unsorted =
      ReadBytes("1.0 1 0 0 0 0 0 1\n1.0 9 0 0 0 0 0 1\n2.0 2 0 0 0 0 0 1\n");
  ASSERT_EQ(unsorted.poses.size(), 2u);
  EXPECT_EQ(unsorted.poses[0].T_W_B.p.x(), 1.0);
  EXPECT_EQ(unsorted.poses[1].T_W_B.p.x(), 2.0);
  EXPECT_EQ(unsorted.report.first_duplicate_line, 2);
}

// The reader parses rows as the stream hands them out (blocks of 1 MiB): a file of many blocks,
// a row longer than a block, CRLF lines and comments between rows give the poses, lines and
// counts that the whole-file text gives; a bad row deep in the file is named by its line; an
// ASL file's velocities and biases come with their poses.
TEST(TrajectoryTextThroughReader, StreamedRowsAcrossBlocks) {
  std::string bytes = "# timestamp tx ty tz qx qy qz qw\n";
  const int n = 90'000;
  for (int i = 0; i < n; ++i) {
    bytes += std::to_string(i) + ".5 " + std::to_string(i) + " 2 3 0 0 0.6 0.8";
    bytes += i % 5 == 0 ? "\r\n" : "\n";
    if (i % 1000 == 0) bytes += "# comment\n\n";
    if (i == 40'000) bytes += std::to_string(i) + ".5 -1 2 3 0 0 0.6 0.8\n";  // repeated stamp
  }
  const std::string path = testing::MakeTempDir() + "/long.txt";
  testing::WriteFileBytes(path, bytes);
  const LoadedTrajectory t = ReadTrajectory(path);
  const TrajectoryText text = ReadTrajectoryText(path);
  ASSERT_EQ(t.poses.size(), static_cast<size_t>(n));
  EXPECT_EQ(t.report.rows, text.rows.size());
  EXPECT_EQ(t.report.duplicates_dropped, 1u);
  EXPECT_EQ(t.report.first_duplicate_line, text.rows[40'001].line);
  EXPECT_TRUE(t.report.had_crlf);
  EXPECT_TRUE(t.motion.empty());
  for (int i = 0; i < n; i += 997) {
    EXPECT_EQ(t.poses[i].t_ns, i * kNsPerSecond + kNsPerSecond / 2) << i;
    EXPECT_EQ(t.poses[i].T_W_B.p.x(), i) << i;
    EXPECT_NEAR(t.poses[i].T_W_B.q.w(), 0.8, 1e-15) << i;
  }
  std::string bad = bytes;
  bad += "95000.5 1 2 x 0 0 0.6 0.8\n";
  testing::WriteFileBytes(path, bad);
  const size_t lines = static_cast<size_t>(std::count(bad.begin(), bad.end(), '\n'));
  EXPECT_NE(ReadError(bad).find("t.txt:" + std::to_string(lines) + ": field 'tz'"),
            std::string::npos)
      << ReadError(bad);

  const LoadedTrajectory asl = ReadBytes(
      "#timestamp,x,y,z,qw,qx,qy,qz,vx,vy,vz,bwx,bwy,bwz,bax,bay,baz\n"
      "100,1,2,3,1,0,0,0,0.5,0,0,0.01,0,0,0,0.2,0\n200,1,2,3,1,0,0,0,0.7,0,0,0,0,0,0,0,0\n");
  ASSERT_EQ(asl.poses.size(), 2u);
  ASSERT_EQ(asl.motion.size(), 2u);
  EXPECT_EQ(asl.motion[1].v_W.x(), 0.7);
  const std::vector<GroundTruthState> states = asl.States();
  EXPECT_EQ(states[0].b_g.x(), 0.01);
  EXPECT_EQ(states[0].b_a.y(), 0.2);
  EXPECT_EQ(states[1].T_W_B.p.z(), 3.0);
}

}  // namespace
}  // namespace mavloc
