// Error lines stay readable whatever the input holds: a trajectory file
// with a 2 MB field or with binary garbage gives exit code 2 and one short line on stderr naming
// the file, with control bytes escaped, never echoed raw.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "tests/test_support.h"

namespace mavloc {
namespace {

using testing::CliPath;
using testing::MakeTempDir;
using testing::RunCommand;

// Runs `arguments` with stderr captured alone (stdout discarded).
testing::CommandResult RunForStderr(const std::string& arguments, const std::string& dir) {
  // An inner shell keeps RunCommand's trailing "2>&1" off mavloc's own redirections.
  testing::CommandResult r =
      RunCommand("sh -c '" + CliPath() + " " + arguments + " >/dev/null 2>" + dir + "/stderr.txt'");
  std::ifstream in(dir + "/stderr.txt", std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  r.output = text.str();
  return r;
}

void ExpectOneReadableLine(const std::string& output) {
  ASSERT_FALSE(output.empty());
  EXPECT_LE(output.size(), 1200u) << output.substr(0, 300);
  EXPECT_EQ(output.find('\n'), output.size() - 1) << "more than one line";
  for (const char c : output.substr(0, output.size() - 1))
    EXPECT_FALSE(static_cast<unsigned char>(c) < 0x20 || c == 0x7f) << "raw control byte";
}

TEST(CliErrorMessage, HugeFieldIsCut) {
  const std::string dir = MakeTempDir();
  {
    std::ofstream gt(dir + "/gt.txt");
    gt << "0 0 0 0 0 0 0 1\n1 " << std::string(2'000'000, '9') << "x 0 0 0 0 0 1\n";
    std::ofstream est(dir + "/est.txt");
    est << "0 0 0 0 0 0 0 1\n1 0 0 0 0 0 0 1\n";
  }
  const auto r = RunForStderr("eval --gt " + dir + "/gt.txt --est " + dir + "/est.txt", dir);
  EXPECT_EQ(r.exit_code, 2) << r.output.substr(0, 300);
  EXPECT_NE(r.output.find("gt.txt:2"), std::string::npos) << r.output.substr(0, 300);
  EXPECT_NE(r.output.find("bytes cut"), std::string::npos) << r.output.substr(0, 300);
  ExpectOneReadableLine(r.output);
}

TEST(CliErrorMessage, BinaryGarbageIsEscaped) {
  const std::string dir = MakeTempDir();
  {
    std::ofstream gt(dir + "/gt.txt", std::ios::binary);
    gt << "0 0 0 0 0 0 0 1\n1 \x01\x02\x1b[31mred\x7f\xff\xfe 0 0 0 0 0 1\n";
    std::ofstream est(dir + "/est.txt");
    est << "0 0 0 0 0 0 0 1\n1 0 0 0 0 0 0 1\n";
  }
  const auto r = RunForStderr("eval --gt " + dir + "/gt.txt --est " + dir + "/est.txt", dir);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("gt.txt:2"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("\\x1B"), std::string::npos) << r.output;
  ExpectOneReadableLine(r.output);
}

}  // namespace
}  // namespace mavloc
