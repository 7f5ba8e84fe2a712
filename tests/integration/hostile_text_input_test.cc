// Hostile text input through the real CLI, table-driven, on copies of the real EuRoC V1_01 data of
// ../shared/data: NUL bytes, trailing garbage and overflow inside numbers of TUM files and IMU
// CSVs, stamps in the wrong unit, an empty quantity name, image names that leave the dataset. A
// refused case must exit with code 2, print one line on stderr naming the file, line and field,
// and write no output. A second table holds files that must be read correctly (a TUM file with
// commas, with mavloc's own comment line, the CSV `mavloc run` writes): read with the same result
// as the plain TUM file, every pose kept.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "tests/test_support.h"

namespace mavloc {
namespace {

namespace fs = std::filesystem;
using testing::MakeTempDir;
using testing::ReadFileBytes;
using testing::SharedDataDir;
using testing::WriteFileBytes;

// Rows of the copies: 2000 ground-truth poses (10 s at 200 Hz), 1400 IMU samples (7 s, covering the
// 5 s of the ASL ground truth, which starts 1 s after the IMU).
constexpr size_t kTruthRows = 2000;
constexpr size_t kImuRows = 1400;
// mavloc's comment line of the TUM files it writes (datasets/io/tum_io.cc).
constexpr const char* kMavlocTumHeader =
    "# timestamp tx ty tz qx qy qz qw  (mavloc: T_W_B, timestamp in seconds)";

std::vector<std::string> Lines(const std::string& text) {
  std::vector<std::string> lines;
  std::stringstream stream(text);
  std::string line;
  while (std::getline(stream, line)) lines.push_back(line);
  return lines;
}

std::string JoinLines(const std::vector<std::string>& lines) {
  std::string text;
  for (const auto& line : lines) text += line + "\n";
  return text;
}

// Splits at `separator` (every one: empty fields kept).
std::vector<std::string> Split(const std::string& line, char separator) {
  std::vector<std::string> fields;
  size_t start = 0;
  for (size_t at = line.find(separator); at != std::string::npos;
       at = line.find(separator, start)) {
    fields.push_back(line.substr(start, at - start));
    start = at + 1;
  }
  fields.push_back(line.substr(start));
  return fields;
}

std::string Join(const std::vector<std::string>& fields, char separator) {
  std::string line;
  for (size_t i = 0; i < fields.size(); ++i)
    line += (i ? std::string(1, separator) : "") + fields[i];
  return line;
}

// The first `rows` lines (header included) of a shared file, written writable into `to`.
void CopyHead(const fs::path& from, const fs::path& to, size_t rows) {
  fs::create_directories(to.parent_path());
  const std::vector<std::string> lines = Lines(ReadFileBytes(from.string()));
  WriteFileBytes(to.string(),
                 JoinLines({lines.begin(), lines.begin() + std::min(rows, lines.size())}));
}

void CopyFile(const fs::path& from, const fs::path& to) {
  fs::create_directories(to.parent_path());
  WriteFileBytes(to.string(), ReadFileBytes(from.string()));
}

// The estimate: the ground truth's rows with positions moved by a few millimetres (a deterministic
// pattern), so that the APE is not zero; TUM, space-separated, no header.
std::vector<std::string> EstimateRows(const std::vector<std::string>& truth_rows) {
  std::vector<std::string> rows;
  for (size_t i = 0; i < truth_rows.size(); ++i) {
    std::vector<std::string> f = Split(truth_rows[i], ' ');
    const double k = static_cast<double>(i);
    const double offsets[3] = {0.01 * std::sin(k), 0.01 * std::cos(0.7 * k),
                               0.005 * std::sin(2 * k)};
    for (int a = 0; a < 3; ++a) {
      char text[32];
      std::snprintf(text, sizeof(text), "%.6f", std::stod(f[1 + a]) + offsets[a]);
      f[1 + a] = text;
    }
    rows.push_back(Join(f, ' '));
  }
  return rows;
}

std::string WithCommas(const std::vector<std::string>& rows) {
  std::string text;
  for (const auto& row : rows) text += Join(Split(row, ' '), ',') + "\n";
  return text;
}

// `dir`: gt.txt (TUM with its header), est.txt (TUM, no header), est_comma.csv (the same rows with
// commas), est_mavloc.txt / est_mavloc_comma.txt (mavloc's comment line, then the rows with spaces
// / commas), and d/, an ASL dataset: imu0, state_groundtruth_estimate0, cam0 (data.csv and
// sensor.yaml; the images are not copied: a run without camera estimators does not open them).
void MakeInputs(const fs::path& dir) {
  const fs::path euroc = SharedDataDir() + "/euroc_v1_01_easy";
  CopyHead(euroc / "groundtruth_full_tum.txt", dir / "gt.txt", kTruthRows + 1);
  std::vector<std::string> truth_rows = Lines(ReadFileBytes((dir / "gt.txt").string()));
  truth_rows.erase(truth_rows.begin());  // the header
  const std::vector<std::string> rows = EstimateRows(truth_rows);
  WriteFileBytes((dir / "est.txt").string(), JoinLines(rows));
  WriteFileBytes((dir / "est_comma.csv").string(), WithCommas(rows));
  WriteFileBytes((dir / "est_mavloc.txt").string(), kMavlocTumHeader + ("\n" + JoinLines(rows)));
  WriteFileBytes((dir / "est_mavloc_comma.txt").string(),
                 kMavlocTumHeader + ("\n" + WithCommas(rows)));
  const fs::path mav0 = dir / "d/mav0";
  CopyHead(euroc / "mav0/imu0/data.csv", mav0 / "imu0/data.csv", kImuRows + 1);
  for (const char* file : {"imu0/sensor.yaml", "state_groundtruth_estimate0/data.csv",
                           "state_groundtruth_estimate0/sensor.yaml", "cam0/data.csv",
                           "cam0/sensor.yaml", "body.yaml"})
    CopyFile(euroc / "mav0" / file, mav0 / file);
  fs::create_directories(mav0 / "cam0/data");
}

// ---- mutations ----

using Mutation = std::function<void(const fs::path& dir)>;

// Field k of line `line` (1-based, header lines counted) of `file`, split at `separator`.
Mutation SetField(const std::string& file, size_t line, size_t k, const std::string& value,
                  char separator) {
  return [=](const fs::path& dir) {
    std::vector<std::string> lines = Lines(ReadFileBytes((dir / file).string()));
    ASSERT_LE(line, lines.size()) << file;
    std::vector<std::string> fields = Split(lines[line - 1], separator);
    ASSERT_LT(k, fields.size()) << file << ":" << line;
    fields[k] = value;
    lines[line - 1] = Join(fields, separator);
    WriteFileBytes((dir / file).string(), JoinLines(lines));
  };
}

// `file` (created with its folders when absent) holding `text`.
Mutation Whole(const std::string& file, const std::string& text) {
  return [=](const fs::path& dir) {
    fs::create_directories((dir / file).parent_path());
    WriteFileBytes((dir / file).string(), text);
  };
}

// Every stamp of est.txt rewritten by `stamp` (from the seconds text).
Mutation EstimateStamps(const std::function<std::string(const std::string&)>& stamp,
                        char separator) {
  return [=](const fs::path& dir) {
    std::vector<std::string> lines = Lines(ReadFileBytes((dir / "est.txt").string()));
    for (std::string& line : lines) {
      std::vector<std::string> fields = Split(line, ' ');
      fields[0] = stamp(fields[0]);
      line = Join(fields, separator);
    }
    WriteFileBytes((dir / "est.txt").string(), JoinLines(lines));
  };
}

// "1403715274.30214" -> "1403715274302140000" (nanoseconds, as a TUM file must not hold them).
std::string SecondsToNanosecondsText(const std::string& seconds) {
  const auto dot = seconds.find('.');
  std::string fraction = dot == std::string::npos ? "" : seconds.substr(dot + 1);
  fraction.resize(9, '0');
  return seconds.substr(0, dot) + fraction;
}

std::string WholeSeconds(const std::string& seconds) {
  return seconds.substr(0, seconds.find('.'));
}

// A number with a NUL byte inside: C-string parsing reads only the text before it.
std::string NulInside(const std::string& before, const std::string& after) {
  return before + std::string(1, '\0') + after;
}

// ---- refused cases ----

struct Refused {
  std::string name;
  Mutation mutate;
  std::string command;  // run in the case folder, mavloc prepended
  int exit_code = 2;
  std::vector<std::string> expected;  // substrings of the one stderr line
  std::vector<std::string> outputs;   // must not exist afterwards
};

const std::string kEval = "eval --gt gt.txt --est est.txt --out report --json eval.json";
const std::vector<std::string> kEvalOutputs = {"report", "eval.json"};
const std::string kRun = "run --dataset d --estimator imu-dead-reckoning --out o.txt";
const std::vector<std::string> kRunOutputs = {"o.txt"};
const std::string kImu = "d/mav0/imu0/data.csv";
const std::string kCam = "d/mav0/cam0/data.csv";
const std::string kTruthQuantities = "d/mav0/truth_quantities0/data.csv";

// A truth_quantities0 stream whose header is `header` (rows at the IMU's first stamps).
Mutation TruthQuantities(const std::string& header) {
  return Whole(kTruthQuantities, header +
                                     "\n1403715274302142976,1.5,2.5\n"
                                     "1403715274307142912,1.5,2.5\n");
}

std::vector<Refused> RefusedCases() {
  return {
      // A NUL byte inside a number: refused, never read as the number before it.
      {"tum_nul_in_number",
       SetField("est.txt", 3, 1, NulInside("0.87", "8612"), ' '),
       kEval,
       2,
       {"est.txt:3: field 'tx'", "NUL byte at character 5"},
       kEvalOutputs},
      {"tum_nul_in_stamp",
       SetField("est.txt", 2, 0, NulInside("1403715274.30", "714"), ' '),
       kEval,
       2,
       {"est.txt:2: field 'timestamp'", "NUL byte at character 14"},
       kEvalOutputs},
      {"imu_nul_in_number",
       SetField(kImu, 5, 1, NulInside("-0.00", "20943951023931952"), ','),
       kRun,
       2,
       {"imu0/data.csv:5: field 'w_RS_S_x [rad s^-1]'", "NUL byte"},
       kRunOutputs},
      {"imu_nul_in_stamp",
       SetField(kImu, 6, 0, NulInside("140371527328", "2142976"), ','),
       kRun,
       2,
       {"imu0/data.csv:6: field 'timestamp [ns]'", "NUL byte"},
       kRunOutputs},
      // Text after the number.
      {"tum_trailing_garbage",
       SetField("est.txt", 4, 2, "2.142470abc", ' '),
       kEval,
       2,
       {"est.txt:4: field 'ty'", "'abc' after '2.142470'"},
       kEvalOutputs},
      {"imu_trailing_garbage",
       SetField(kImu, 7, 4, "9.08 m/s^2", ','),
       kRun,
       2,
       {"imu0/data.csv:7: field 'a_RS_S_x [m s^-2]'", "' m/s^2' after '9.08'"},
       kRunOutputs},
      // Beyond the range of a double.
      {"tum_overflow",
       SetField("est.txt", 5, 3, "1e999", ' '),
       kEval,
       2,
       {"est.txt:5: field 'tz'", "'1e999' is not finite (beyond the largest double"},
       kEvalOutputs},
      {"imu_overflow",
       SetField(kImu, 8, 6, "-1e999", ','),
       kRun,
       2,
       {"imu0/data.csv:8: field 'a_RS_S_z [m s^-2]'", "is not finite (beyond the largest double"},
       kRunOutputs},
      // Stamps in the wrong unit.
      {"tum_stamps_in_nanoseconds",
       EstimateStamps(SecondsToNanosecondsText, ' '),
       kEval,
       2,
       {"est.txt:1: field 'timestamp'",
        "TUM stamps are seconds; these look like nanoseconds (divide by 1e9)"},
       kEvalOutputs},
      {"comma_rows_with_whole_seconds",
       EstimateStamps(WholeSeconds, ','),
       kEval,
       2,
       {"est.txt:1: field 'timestamp [ns]'", "they look like seconds"},
       kEvalOutputs},
      {"convert_comma_rows_with_whole_seconds",
       EstimateStamps(WholeSeconds, ','),
       "convert --in est.txt --out back.tum --format tum",
       2,
       {"est.txt:1: field 'timestamp [ns]'", "they look like seconds"},
       {"back.tum"}},
      // truth_quantities0: every column after the timestamp names a quantity.
      {"truth_quantities_empty_name",
       TruthQuantities("#timestamp [ns],,d [m]"),
       kRun,
       2,
       {"truth_quantities0/data.csv:1: field 'column 2'", "no quantity name"},
       kRunOutputs},
      {"truth_quantities_empty_last_name",
       TruthQuantities("#timestamp [ns],d [m], [m]"),
       kRun,
       2,
       {"truth_quantities0/data.csv:1: field 'column 3'", "no quantity name"},
       kRunOutputs},
      // Image names are plain file names of cam0/data/.
      {"image_name_leaves_dataset",
       SetField(kCam, 2, 1, "../../../../etc/passwd", ','),
       kRun,
       2,
       {"cam0/data.csv:2: field 'filename'", "'../../../../etc/passwd' is not a plain file name"},
       kRunOutputs},
      {"image_name_empty",
       SetField(kCam, 3, 1, "", ','),
       kRun,
       2,
       {"cam0/data.csv:3: field 'filename'", "empty image file name"},
       kRunOutputs},
      {"image_name_parent_folder",
       SetField(kCam, 4, 1, "..", ','),
       kRun,
       2,
       {"cam0/data.csv:4: field 'filename'", "'..' is a folder"},
       kRunOutputs},
  };
}

bool HasControlBytes(const std::string& text) {
  return std::any_of(text.begin(), text.end(), [](char c) {
    const auto u = static_cast<unsigned char>(c);
    return (u < 0x20 && c != '\n') || u == 0x7f;
  });
}

// "ATE translation rmse 0.012345" -> "0.012345" (first run line of `mavloc eval`).
std::string AteRmse(const std::string& out) {
  std::smatch match;
  if (!std::regex_search(out, match, std::regex("ATE translation rmse ([0-9.]+)"))) return "";
  return match[1].str();
}

size_t DataLines(const std::string& text) {
  size_t n = 0;
  for (const auto& line : Lines(text))
    if (!line.empty() && line[0] != '#') ++n;
  return n;
}

class HostileTextInput : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!testing::HasSharedData()) GTEST_SKIP() << "../shared/data is absent";
  }

  static fs::path CaseDir(const std::string& name) {
    const fs::path dir = fs::path(MakeTempDir()) / name;
    fs::create_directories(dir);
    MakeInputs(dir);
    return dir;
  }
};

TEST_F(HostileTextInput, UnmutatedCopiesLoad) {
  const fs::path dir = CaseDir("baseline");
  for (const std::string& command : {kEval, kRun}) {
    const testing::CliRun r = testing::RunCliIn(dir.string(), command);
    EXPECT_EQ(r.exit_code, 0) << command << "\n" << r.out << r.err;
  }
}

TEST_F(HostileTextInput, RefusedWithFileLineAndFieldAndNoOutput) {
  for (const Refused& c : RefusedCases()) {
    SCOPED_TRACE(c.name);
    const fs::path dir = CaseDir(c.name);
    c.mutate(dir);
    if (::testing::Test::HasFatalFailure()) return;
    const testing::CliRun r = testing::RunCliIn(dir.string(), c.command);
    EXPECT_EQ(r.exit_code, c.exit_code) << r.out << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_FALSE(HasControlBytes(r.err)) << r.err;
    EXPECT_EQ(r.err.find("internal"), std::string::npos) << r.err;
    for (const std::string& expected : c.expected)
      EXPECT_NE(r.err.find(expected), std::string::npos) << "expected '" << expected << "' in\n"
                                                         << r.err;
    for (const std::string& output : c.outputs)
      EXPECT_FALSE(fs::exists(dir / output)) << output << " written";
  }
}

// ---- files that must be read correctly ----

struct Accepted {
  std::string name;
  std::string estimate;  // evaluated against gt.txt: the same APE as est.txt
};

std::vector<Accepted> AcceptedCases() {
  return {
      {"comma_tum_without_header", "est_comma.csv"},
      {"tum_with_mavloc_comment_line", "est_mavloc.txt"},
      {"comma_tum_with_mavloc_comment_line", "est_mavloc_comma.txt"},
  };
}

TEST_F(HostileTextInput, TumVariantsEvaluateLikeThePlainFile) {
  const fs::path dir = CaseDir("tum_variants");
  const testing::CliRun plain = testing::RunCliIn(dir.string(), "eval --gt gt.txt --est est.txt");
  ASSERT_EQ(plain.exit_code, 0) << plain.out << plain.err;
  const std::string rmse = AteRmse(plain.out);
  ASSERT_FALSE(rmse.empty()) << plain.out;
  ASSERT_NE(rmse, "0.000000") << "the estimate must differ from the ground truth";
  EXPECT_NE(plain.out.find("2000 of 2000 poses associated"), std::string::npos) << plain.out;
  for (const Accepted& c : AcceptedCases()) {
    SCOPED_TRACE(c.name);
    const testing::CliRun r =
        testing::RunCliIn(dir.string(), "eval --gt gt.txt --est " + c.estimate);
    EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
    EXPECT_EQ(AteRmse(r.out), rmse) << r.out;
    EXPECT_NE(r.out.find("2000 of 2000 poses associated"), std::string::npos) << r.out;
  }
}

TEST_F(HostileTextInput, ConvertWritesEveryPose) {
  const fs::path dir = CaseDir("convert");
  for (const Accepted& c : AcceptedCases()) {
    SCOPED_TRACE(c.name);
    const std::string out = c.name + ".tum";
    const testing::CliRun r = testing::RunCliIn(
        dir.string(), "convert --in " + c.estimate + " --out " + out + " --format tum");
    EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
    EXPECT_NE(r.out.find("2000 poses"), std::string::npos) << r.out;
    EXPECT_EQ(DataLines(ReadFileBytes((dir / out).string())), kTruthRows);
    // The converted file is the estimate: the same APE.
    const testing::CliRun back = testing::RunCliIn(dir.string(), "eval --gt gt.txt --est " + out);
    const testing::CliRun plain = testing::RunCliIn(dir.string(), "eval --gt gt.txt --est est.txt");
    EXPECT_EQ(AteRmse(back.out), AteRmse(plain.out)) << back.out << back.err;
  }
}

// A file with repeated stamps: convert says how many rows it dropped and why.
TEST_F(HostileTextInput, ConvertSaysHowManyRowsItDropped) {
  const fs::path dir = CaseDir("convert_duplicates");
  std::vector<std::string> lines = Lines(ReadFileBytes((dir / "est.txt").string()));
  lines.insert(lines.begin() + 10, lines[9]);
  lines.insert(lines.begin() + 20, lines[19]);
  WriteFileBytes((dir / "est.txt").string(), JoinLines(lines));
  const testing::CliRun r =
      testing::RunCliIn(dir.string(), "convert --in est.txt --out back.tum --format tum");
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.err.find("wrote 2000 of 2002 rows (2 with a repeated timestamp dropped"),
            std::string::npos)
      << r.err;
  EXPECT_EQ(DataLines(ReadFileBytes((dir / "back.tum").string())), kTruthRows);
}

// Every file `mavloc run --out FILE` writes is read by `mavloc eval`: the TUM trajectory and the
// quantity CSV (x, y, z, roll, pitch, yaw, ...) give the same APE.
TEST_F(HostileTextInput, EvalReadsWhatRunWrites) {
  const fs::path dir = CaseDir("run_outputs");
  const std::string truth = "d/mav0/state_groundtruth_estimate0/data.csv";
  std::string rmse;
  for (const std::string out : {"run.txt", "run.csv"}) {
    SCOPED_TRACE(out);
    const testing::CliRun run = testing::RunCliIn(
        dir.string(), "run --dataset d --estimator imu-dead-reckoning --out " + out);
    ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
    const testing::CliRun eval =
        testing::RunCliIn(dir.string(), "eval --gt " + truth + " --est " + out);
    EXPECT_EQ(eval.exit_code, 0) << eval.out << eval.err;
    if (rmse.empty())
      rmse = AteRmse(eval.out);
    else
      EXPECT_EQ(AteRmse(eval.out), rmse) << eval.out;
  }
  EXPECT_FALSE(rmse.empty());
}

}  // namespace
}  // namespace mavloc
