// The bad-input catalogue, table-driven: mutated copies of simulated datasets through
// the real CLI. Every refused case must exit with code 2, print one line naming the file, the line
// and the field, and leave no report folder behind. A second table holds inputs that must keep
// loading (a BOM, CRLF, quaternions printed with few decimals): too strict is a bug as well.
//
// Cases come from two sources: hand-written ones per class of bad input (YAML types, absurd
// values, ids, silent degradation, messages), and generated ones: every data column of every CSV
// stream with 1e308, nan, text and an empty value.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "tests/test_support.h"

namespace mavloc {
namespace {

namespace fs = std::filesystem;
using testing::CliPath;
using testing::MakeTempDir;
using testing::RunCommand;

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

std::vector<std::string> SplitCommas(const std::string& line) {
  std::vector<std::string> fields;
  std::stringstream stream(line);
  std::string field;
  while (std::getline(stream, field, ',')) fields.push_back(field);
  return fields;
}

std::string JoinCommas(const std::vector<std::string>& fields) {
  std::string line;
  for (size_t i = 0; i < fields.size(); ++i) line += (i ? "," : "") + fields[i];
  return line;
}

std::string Trim(const std::string& text) {
  const auto begin = text.find_first_not_of(" \t#");
  const auto end = text.find_last_not_of(" \t\r");
  return begin == std::string::npos ? "" : text.substr(begin, end - begin + 1);
}

// A mutation of one file of a dataset: the edited text, or (folder = true) the file replaced by a
// folder of the same name.
struct Mutation {
  std::string file;  // relative to the dataset root
  std::function<std::string(const std::string&)> edit;
  bool folder = false;
};

Mutation ReplaceLine(const std::string& file, int line, const std::string& text) {
  return {file, [line, text](const std::string& before) {
            auto lines = Lines(before);
            EXPECT_LE(line, static_cast<int>(lines.size())) << "case edits a missing line";
            if (line <= static_cast<int>(lines.size())) lines[line - 1] = text;
            return JoinLines(lines);
          }};
}

Mutation Substitute(const std::string& file, const std::string& from, const std::string& to) {
  return {file, [from, to](const std::string& before) {
            std::string after = before;
            const auto at = after.find(from);
            EXPECT_NE(at, std::string::npos) << "case substitutes missing text '" << from << "'";
            if (at != std::string::npos) after.replace(at, from.size(), to);
            return after;
          }};
}

Mutation Whole(const std::string& file, const std::string& text) {
  return {file, [text](const std::string&) { return text; }};
}

Mutation Append(const std::string& file, const std::string& text) {
  return {file, [text](const std::string& before) { return before + text; }};
}

Mutation MakeFolder(const std::string& file) { return {file, nullptr, true}; }

// Field k of data row `row` (1-based line of the file) set to `value`.
Mutation SetField(const std::string& file, int line, size_t k, const std::string& value) {
  return {file, [line, k, value](const std::string& before) {
            auto lines = Lines(before);
            auto fields = SplitCommas(lines.at(line - 1));
            EXPECT_LT(k, fields.size());
            if (k < fields.size()) fields[k] = value;
            lines[line - 1] = JoinCommas(fields);
            return JoinLines(lines);
          }};
}

struct Case {
  Case(std::string name_, Mutation mutation_, std::vector<std::string> expected_,
       std::string estimators_ = "")
      : name(std::move(name_)),
        mutation(std::move(mutation_)),
        expected(std::move(expected_)),
        estimators(std::move(estimators_)) {}
  std::string name;
  Mutation mutation;
  std::vector<std::string> expected;  // substrings of the error line
  std::string estimators;             // compare --estimators (default: the base's)
};

// The simulated datasets the cases mutate: one per stream family, 2 s each, made once per test
// process.
struct Base {
  const char* scenario;
  const char* estimators;  // applicable, so that loading is what is tested
};
const std::map<std::string, Base>& Bases() {
  static const std::map<std::string, Base> bases = {
      {"features", {"mav-figure-eight", "imu-dead-reckoning"}},
      {"tags", {"tag-arena-hover", "tag-pnp"}},
      {"laser", {"laser-plane", "laser-ekf"}},
  };
  return bases;
}

// One scratch folder per test process (MakeTempDir empties its folder at every call).
const fs::path& Scratch() {
  static const fs::path root = MakeTempDir();
  return root;
}

class BadInputCatalogue : public ::testing::Test {
 protected:
  static fs::path BaseDataset(const std::string& base) {
    static std::map<std::string, fs::path> made;
    if (made.count(base)) return made[base];
    const fs::path dir = Scratch() / ("base-" + base);
    const auto result = RunCommand(CliPath() + " simulate --scenario " + Bases().at(base).scenario +
                                   " --duration 2 --seed 3 --out " + dir.string());
    EXPECT_EQ(result.exit_code, 0) << result.output;
    made[base] = dir;
    return dir;
  }

  // Copies the base, applies the mutation, runs compare, returns {exit code, output} and whether
  // the report folder exists afterwards.
  struct Outcome {
    int exit_code = -1;
    std::string output;
    bool report_left = false;
  };
  static Outcome Run(const std::string& base, const Case& c) {
    const fs::path work = Scratch() / "case";
    fs::remove_all(work);
    fs::copy(BaseDataset(base), work, fs::copy_options::recursive);
    const fs::path target = work / c.mutation.file;
    if (c.mutation.folder) {
      fs::remove_all(target);
      fs::create_directories(target);
    } else {
      testing::WriteFileBytes(
          target, c.mutation.edit(fs::exists(target) ? testing::ReadFileBytes(target) : ""));
    }
    const fs::path report = work.parent_path() / "report";
    fs::remove_all(report);
    // "default": compare's own choice (every estimator that applies).
    const std::string estimators =
        c.estimators == "default"
            ? ""
            : " --estimators " +
                  (c.estimators.empty() ? Bases().at(base).estimators : c.estimators);
    const auto result = RunCommand("MAVLOC_FIGURES=0 " + CliPath() + " compare --dataset " +
                                   work.string() + estimators + " --report " + report.string());
    return {result.exit_code, result.output, fs::exists(report)};
  }

  static void ExpectRefused(const std::string& base, const std::vector<Case>& cases) {
    for (const auto& c : cases) {
      SCOPED_TRACE(base + ": " + c.name);
      const Outcome outcome = Run(base, c);
      EXPECT_EQ(outcome.exit_code, 2) << outcome.output;
      EXPECT_FALSE(outcome.report_left) << "a report folder was left behind";
      for (const auto& expected : c.expected)
        EXPECT_NE(outcome.output.find(expected), std::string::npos)
            << "expected '" << expected << "' in: " << outcome.output;
      // One line of reasonable length, no raw control bytes.
      EXPECT_LT(outcome.output.size(), 1500u) << outcome.output.substr(0, 300);
      for (char ch : outcome.output) {
        const auto byte = static_cast<unsigned char>(ch);
        EXPECT_TRUE(byte >= 0x20 || ch == '\n') << "raw control byte " << int(byte);
        if (!(byte >= 0x20 || ch == '\n')) break;
      }
    }
  }

  static void ExpectAccepted(const std::string& base, const std::vector<Case>& cases) {
    for (const auto& c : cases) {
      SCOPED_TRACE(base + ": " + c.name);
      const Outcome outcome = Run(base, c);
      EXPECT_EQ(outcome.exit_code, 0) << outcome.output;
      for (const auto& expected : c.expected)
        EXPECT_NE(outcome.output.find(expected), std::string::npos)
            << "expected '" << expected << "' in: " << outcome.output;
    }
  }

  // Every data column k >= 1 of the first data row of a CSV stream, set to values that are not
  // measurements. The message names file:line and the column (quaternion columns: the quaternion).
  static std::vector<Case> ColumnCases(const std::string& base, const std::string& file,
                                       size_t first_column = 1) {
    const auto lines = Lines(testing::ReadFileBytes(BaseDataset(base) / file));
    const auto header = SplitCommas(lines.at(0));
    const auto fields = SplitCommas(lines.at(1));
    std::vector<Case> cases;
    for (size_t k = first_column; k < fields.size(); ++k) {
      const std::string name = Trim(header.at(k));
      const bool quaternion = name.rfind("q_RS_", 0) == 0;
      // Every column: an absurd number and text; the first column also nan, empty and -inf
      // (the same parser for every column).
      std::vector<std::string> values = {"1e308", "x1"};
      if (k == first_column) values.insert(values.end(), {"nan", "", "-inf"});
      for (const std::string& value : values) {
        // The quaternion is judged as a whole once all four are numbers.
        const bool numeric = value == "1e308";
        const std::string field = quaternion && numeric ? "q_RS_w" : name;
        std::vector<std::string> expected = {file + ":2: field '" + field};
        cases.push_back({file + " column " + name + " = '" + value + "'",
                         SetField(file, 2, k, value), expected});
      }
    }
    return cases;
  }
};

// ---- Class 1: YAML type errors, with file and line ----

TEST_F(BadInputCatalogue, ImuSensorYaml) {
  const std::string f = "mav0/imu0/sensor.yaml";
  ExpectRefused(
      "features",
      {
          {"top-level scalar", Whole(f, "42\n"), {f + ":1", "expected a map of keys at the top"}},
          {"top-level list", Whole(f, "- a\n- b\n"), {f + ":1", "found a list"}},
          {"rate as list", ReplaceLine(f, 7, "rate_hz: [200]"), {f + ":7: field 'rate_hz'"}},
          {"rate negative", ReplaceLine(f, 7, "rate_hz: -5"), {f + ":7: field 'rate_hz'"}},
          {"rate absurd", ReplaceLine(f, 7, "rate_hz: 1e308"), {f + ":7: field 'rate_hz'"}},
          {"rate text", ReplaceLine(f, 7, "rate_hz: fast"), {f + ":7: field 'rate_hz'"}},
          {"rate nan", ReplaceLine(f, 7, "rate_hz: .nan"), {f + ":7: field 'rate_hz'"}},
          {"gyro noise negative",
           ReplaceLine(f, 8, "gyroscope_noise_density: -1"),
           {f + ":8: field 'gyroscope_noise_density'"}},
          {"gyro walk absurd",
           ReplaceLine(f, 9, "gyroscope_random_walk: 1e308"),
           {f + ":9: field 'gyroscope_random_walk'"}},
          {"accel noise absurd",
           ReplaceLine(f, 10, "accelerometer_noise_density: 1e308"),
           {f + ":10: field 'accelerometer_noise_density'"}},
          {"accel walk map",
           ReplaceLine(f, 11, "accelerometer_random_walk: {a: 1}"),
           {f + ":11: field 'accelerometer_random_walk'"}},
          {"bias sigma negative",
           ReplaceLine(f, 12, "gyroscope_bias_sigma: -0.1"),
           {f + ":12: field 'gyroscope_bias_sigma'"}},
          {"accel bias sigma absurd",
           ReplaceLine(f, 13, "accelerometer_bias_sigma: 1e9"),
           {f + ":13: field 'accelerometer_bias_sigma'"}},
          {"T_BS all zero",
           ReplaceLine(f, 6, "  data: [0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0]"),
           {f + ":4: field 'T_BS'", "not a rigid transform"}},
          {"T_BS all two",
           ReplaceLine(f, 6, "  data: [2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2]"),
           {f + ":4: field 'T_BS'", "not a rigid transform"}},
          {"T_BS scaled rotation",
           ReplaceLine(f, 6, "  data: [2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 1]"),
           {f + ":4: field 'T_BS'", "rotation part"}},
          {"T_BS reflection",
           ReplaceLine(f, 6, "  data: [-1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]"),
           {f + ":4: field 'T_BS'", "det"}},
          {"T_BS absurd translation",
           ReplaceLine(f, 6, "  data: [1, 0, 0, 1e308, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]"),
           {f + ":4: field 'T_BS'", "translation"}},
          {"T_BS short", ReplaceLine(f, 6, "  data: [1, 0]"), {f + ":6: field 'data'", "16"}},
          {"T_BS data text",
           ReplaceLine(f, 6, "  data: [a, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]"),
           {f + ":6: field 'data'", "not a number"}},
          {"T_BS data nested",
           ReplaceLine(f, 6, "  data: [[1], 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]"),
           {f + ":6: field 'data'"}},
          {"T_BS scalar",
           Substitute(f, "T_BS:\n  cols: 4\n  rows: 4\n", "T_BS: 5\nx:\n  a: 4\n"),
           {f + ":3: field 'T_BS'"}},
          {"invalid YAML", ReplaceLine(f, 7, "rate_hz: [200"), {f, "invalid YAML"}},
          {"non-scalar key", Append(f, "? [a, b]\n: 1\n"), {f + ":14", "key"}},
      });
}

TEST_F(BadInputCatalogue, CameraSensorYaml) {
  const std::string f = "mav0/cam0/sensor.yaml";
  ExpectRefused(
      "features",
      {
          {"top-level scalar", Whole(f, "camera\n"), {f + ":1", "expected a map"}},
          {"camera_model list",
           ReplaceLine(f, 9, "camera_model: [pinhole]"),
           {f + ":9: field 'camera_model'", "single value"}},
          {"camera_model other", ReplaceLine(f, 9, "camera_model: omni"), {f + ":9"}},
          {"resolution absurd",
           ReplaceLine(f, 8, "resolution: [1e308, 480]"),
           {f + ":8: field 'resolution'"}},
          {"resolution negative",
           ReplaceLine(f, 8, "resolution: [-752, 480]"),
           {f + ":8: field 'resolution'"}},
          {"resolution fraction",
           ReplaceLine(f, 8, "resolution: [752.5, 480]"),
           {f + ":8: field 'resolution'"}},
          {"resolution zero", ReplaceLine(f, 8, "resolution: [752, 0]"), {f + ":8"}},
          {"resolution map", ReplaceLine(f, 8, "resolution: {w: 752}"), {f + ":8", "a map"}},
          {"resolution one value", ReplaceLine(f, 8, "resolution: [752]"), {f + ":8"}},
          {"intrinsics zero",
           ReplaceLine(f, 10, "intrinsics: [0, 0, 0, 0]"),
           {f + ":10: field 'intrinsics'", "fu"}},
          {"intrinsics negative focal",
           ReplaceLine(f, 10, "intrinsics: [458, -457, 367, 248]"),
           {f + ":10: field 'intrinsics'", "fv"}},
          {"intrinsics absurd centre",
           ReplaceLine(f, 10, "intrinsics: [458, 457, 1e308, 248]"),
           {f + ":10: field 'intrinsics'", "cu"}},
          {"intrinsics three",
           ReplaceLine(f, 10, "intrinsics: [458, 457, 367]"),
           {f + ":10: field 'intrinsics'"}},
          {"intrinsics missing", ReplaceLine(f, 10, "# no intrinsics"), {f, "'intrinsics'"}},
          {"distortion unknown",
           ReplaceLine(f, 11, "distortion_model: fisheye2"),
           {f + ":11: field 'distortion_model'"}},
          {"distortion model list",
           ReplaceLine(f, 11, "distortion_model: [a]"),
           {f + ":11: field 'distortion_model'"}},
          {"distortion absurd",
           ReplaceLine(f, 12, "distortion_coefficients: [1e308, 0, 0, 0]"),
           {f + ":12: field 'distortion_coefficients'"}},
          {"distortion two",
           ReplaceLine(f, 12, "distortion_coefficients: [0.1, 0.2]"),
           {f + ":12: field 'distortion_coefficients'"}},
          {"T_BS non-rigid",
           ReplaceLine(f, 6, "  data: [2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2]"),
           {f + ":4: field 'T_BS'"}},
          {"rate text", ReplaceLine(f, 7, "rate_hz: twenty"), {f + ":7: field 'rate_hz'"}},
          {"sensor.yaml a folder", MakeFolder(f), {f, "folder"}},
      });
}

TEST_F(BadInputCatalogue, MapYamlLandmarks) {
  const std::string f = "map.yaml";
  ExpectRefused(
      "features",
      {
          {"scalar", Whole(f, "hello\n"), {f + ":1", "expected a map"}},
          {"list", Whole(f, "- 1\n"), {f + ":1", "expected a map"}},
          {"landmarks as map",
           Whole(f, "landmarks: {a: 1}\n"),
           {f + ":1: field 'landmarks'", "expected a list"}},
          {"landmarks as scalar", Whole(f, "landmarks: 5\n"), {f + ":1: field 'landmarks'"}},
          {"landmark entry scalar", ReplaceLine(f, 3, "  - 5"), {f + ":3", "each entry"}},
          {"landmark id repeated",
           Substitute(f, "{id: 1,", "{id: 0,"),
           {f + ":4: field 'id'", "repeated (first on line 3)"}},
          {"landmark id fraction",
           Substitute(f, "{id: 1,", "{id: 1.5,"),
           {f + ":4: field 'id'", "not an integer"}},
          {"landmark id absurd",
           Substitute(f, "{id: 1,", "{id: 1e308,"),
           {f + ":4: field 'id'", "not an integer"}},
          {"landmark id too large",
           Substitute(f, "{id: 1,", "{id: 3000000000,"),
           {f + ":4: field 'id'", "outside"}},
          {"landmark id negative", Substitute(f, "{id: 1,", "{id: -1,"), {f + ":4: field 'id'"}},
          {"landmark id list", Substitute(f, "{id: 1,", "{id: [1],"), {f + ":4: field 'id'"}},
          {"landmark id missing",
           ReplaceLine(f, 3, "  - {p_W: [1, 2, 3]}"),
           {f + ":3: field 'id'", "missing"}},
          {"landmark position absurd",
           ReplaceLine(f, 3, "  - {id: 0, p_W: [1e308, 0, 0]}"),
           {f + ":3: field 'p_W'"}},
          {"landmark position two values",
           ReplaceLine(f, 3, "  - {id: 0, p_W: [1, 2]}"),
           {f + ":3: field 'p_W'", "3 values"}},
          {"landmark position text",
           ReplaceLine(f, 3, "  - {id: 0, p_W: [a, 2, 3]}"),
           {f + ":3: field 'p_W'"}},
          {"frame list", Append(f, "frame: [world]\n"), {f, "field 'frame'"}},
          {"frame unknown", Append(f, "frame: moon\n"), {f, "field 'frame'", "moon"}},
          {"parameters list", Append(f, "parameters: [1, 2]\n"), {f, "field 'parameters'"}},
          {"parameters text", Append(f, "parameters:\n  D: tall\n"), {f, "field 'D'"}},
          {"plane scalar", Append(f, "plane: 3\n"), {f, "field 'plane'"}},
          {"map.yaml a folder", MakeFolder(f), {f, "folder"}},
          {"invalid YAML", Append(f, "landmarks: [\n"), {f, "YAML"}},
      });
}

TEST_F(BadInputCatalogue, MapYamlTags) {
  const std::string f = "map.yaml";
  ExpectRefused(
      "tags",
      {
          {"tags scalar", Whole(f, "tags: 5\n"), {f + ":1: field 'tags'"}},
          {"tag quaternion zero",
           ReplaceLine(f, 3, "  - {id: 0, size_m: 0.2, p_W: [0, 0, 0], q_W_T: [0, 0, 0, 0]}"),
           {f + ":3: field 'q_W_T'", "not unit length"}},
          {"tag quaternion half",
           ReplaceLine(f, 3, "  - {id: 0, size_m: 0.2, p_W: [0, 0, 0], q_W_T: [0.5, 0, 0, 0]}"),
           {f + ":3: field 'q_W_T'"}},
          {"tag quaternion three",
           ReplaceLine(f, 3, "  - {id: 0, size_m: 0.2, p_W: [0, 0, 0], q_W_T: [1, 0, 0]}"),
           {f + ":3: field 'q_W_T'"}},
          {"tag size negative",
           ReplaceLine(f, 3, "  - {id: 0, size_m: -0.2, p_W: [0, 0, 0], q_W_T: [1, 0, 0, 0]}"),
           {f + ":3: field 'size_m'"}},
          {"tag size zero",
           ReplaceLine(f, 3, "  - {id: 0, size_m: 0, p_W: [0, 0, 0], q_W_T: [1, 0, 0, 0]}"),
           {f + ":3: field 'size_m'"}},
          {"tag size absurd",
           ReplaceLine(f, 3, "  - {id: 0, size_m: 1e308, p_W: [0, 0, 0], q_W_T: [1, 0, 0, 0]}"),
           {f + ":3: field 'size_m'"}},
          {"tag position absurd",
           ReplaceLine(f, 3, "  - {id: 0, size_m: 0.2, p_W: [0, 1e308, 0], q_W_T: [1, 0, 0, 0]}"),
           {f + ":3: field 'p_W'"}},
          {"tag id absurd",
           ReplaceLine(f, 3, "  - {id: 1e308, size_m: 0.2, p_W: [0, 0, 0], q_W_T: [1, 0, 0, 0]}"),
           {f + ":3: field 'id'"}},
          {"tag id 3e9",
           ReplaceLine(f, 3, "  - {id: 3e9, size_m: 0.2, p_W: [0, 0, 0], q_W_T: [1, 0, 0, 0]}"),
           {f + ":3: field 'id'"}},
          {"tag id repeated",
           ReplaceLine(f, 4, "  - {id: 0, size_m: 0.2, p_W: [0, 0, 0], q_W_T: [1, 0, 0, 0]}"),
           {f + ":4: field 'id'", "repeated"}},
          {"tag entry list", ReplaceLine(f, 3, "  - [0, 0.2]"), {f + ":3", "each entry"}},
      });
}

TEST_F(BadInputCatalogue, MapYamlPlaneAndParameters) {
  const std::string f = "map.yaml";
  ExpectRefused(
      "laser",
      {
          {"plane normal zero",
           ReplaceLine(f, 2, "plane: {n_W: [0, 0, 0], d_m: 0}"),
           {f + ":2: field 'n_W'", "not unit length"}},
          {"plane normal long",
           ReplaceLine(f, 2, "plane: {n_W: [0, 0, 1e308], d_m: 0}"),
           {f + ":2: field 'n_W'"}},
          {"plane distance absurd",
           ReplaceLine(f, 2, "plane: {n_W: [0, 0, 1], d_m: 1e308}"),
           {f + ":2: field 'd_m'"}},
          {"plane list", ReplaceLine(f, 2, "plane: [0, 0, 1]"), {f + ":2: field 'plane'"}},
          {"plane missing normal",
           ReplaceLine(f, 2, "plane: {d_m: 0}"),
           {f + ":2: field 'n_W'", "missing"}},
          {"parameter text", ReplaceLine(f, 4, "  laser_Lx: far"), {f + ":4: field 'laser_Lx'"}},
          {"parameter list", ReplaceLine(f, 4, "  laser_Lx: [1]"), {f + ":4: field 'laser_Lx'"}},
          {"parameters scalar",
           Substitute(f, "parameters:\n  laser_Lx: 0.3\n", "parameters: 3\nx:\n  laser_Lx: 0.3\n"),
           {f + ":3: field 'parameters'"}},
      });
}

TEST_F(BadInputCatalogue, ScenarioYaml) {
  const std::string f = "scenario.yaml";
  ExpectRefused("features",
                {
                    {"scalar", Whole(f, "figure-eight\n"), {f + ":1", "expected a map"}},
                    {"non-scalar key", Append(f, "? [a, b]\n: 1\n"), {f, "key"}},
                    {"list value", Append(f, "extra: [1, 2]\n"), {f, "field 'extra'"}},
                    {"map value", Append(f, "extra: {a: 1}\n"), {f, "field 'extra'"}},
                    {"invalid YAML", Append(f, "extra: [1, 2\n"), {f, "YAML"}},
                });
}

// ---- Classes 2 and 3: absurd values and ids, in every column of every stream ----

TEST_F(BadInputCatalogue, ImuCsvColumns) {
  ExpectRefused("features", ColumnCases("features", "mav0/imu0/data.csv"));
}

TEST_F(BadInputCatalogue, GroundTruthCsvColumns) {
  ExpectRefused("features", ColumnCases("features", "mav0/state_groundtruth_estimate0/data.csv"));
}

TEST_F(BadInputCatalogue, FeatureAndTagCsvColumns) {
  ExpectRefused("features", ColumnCases("features", "mav0/features0/data.csv"));
  ExpectRefused("tags", ColumnCases("tags", "mav0/tags0/data.csv"));
}

TEST_F(BadInputCatalogue, LaserAndQuantityCsvColumns) {
  ExpectRefused("laser", ColumnCases("laser", "mav0/laser0/data.csv"));
  ExpectRefused("laser", ColumnCases("laser", "mav0/truth_quantities0/data.csv"));
}

TEST_F(BadInputCatalogue, StreamRows) {
  const std::string imu = "mav0/imu0/data.csv";
  const std::string gt = "mav0/state_groundtruth_estimate0/data.csv";
  const std::string features = "mav0/features0/data.csv";
  ExpectRefused(
      "features",
      {
          {"imu accel absurd", SetField(imu, 2, 4, "1e308"), {imu + ":2: field 'a_RS_S_x"}},
          {"imu gyro beyond range", SetField(imu, 2, 1, "1000"), {imu + ":2: field 'w_RS_S_x"}},
          {"imu stamp scientific", SetField(imu, 2, 0, "1e30"), {imu + ":2: field 'timestamp"}},
          {"imu stamp overflow",
           SetField(imu, 2, 0, "99999999999999999999"),
           {imu + ":2: field 'timestamp"}},
          {"imu stamp beyond 2116",
           SetField(imu, 2, 0, "9000000000000000000"),
           {imu + ":2: field 'timestamp", "2116"}},
          {"imu stamp negative", SetField(imu, 2, 0, "-5"), {imu + ":2: field 'timestamp"}},
          {"imu stamp repeated", SetField(imu, 3, 0, "1000000000000"), {imu + ":3", "duplicate"}},
          {"imu stamp backwards", SetField(imu, 3, 0, "999000000000"), {imu + ":3", "earlier"}},
          {"imu short row", ReplaceLine(imu, 2, "1000000000000,0,0"), {imu + ":2", "7 fields"}},
          {"imu empty file", Whole(imu, ""), {imu, "no data rows"}},
          {"imu header only", Whole(imu, "#timestamp [ns],w\n"), {imu, "no data rows"}},
          {"imu data a folder", MakeFolder(imu), {imu, "folder"}},
          {"gt quaternion zero",
           {gt,
            [gt](const std::string& text) {
              std::string out = text;
              for (size_t k = 4; k < 8; ++k) out = SetField(gt, 2, k, "0").edit(out);
              return out;
            }},
           {gt + ":2: field 'q_RS_w", "not unit length"}},
          {"gt twelve fields",
           ReplaceLine(gt, 2, "1000000000000,0,0,1.6,1,0,0,0,0,0,0,0"),
           {gt + ":2", "17 fields"}},
          {"gt stamp backwards", SetField(gt, 3, 0, "1"), {gt + ":3", "earlier"}},
          {"feature id fraction",
           SetField(features, 2, 1, "1.5"),
           {features + ":2: field 'landmark_id'"}},
          {"feature id 2.7",
           SetField(features, 3, 1, "2.7"),
           {features + ":3: field 'landmark_id'"}},
          {"feature id absurd",
           SetField(features, 2, 1, "1e308"),
           {features + ":2: field 'landmark_id'", "not an integer id"}},
          {"feature id 3e9",
           SetField(features, 2, 1, "3000000000"),
           {features + ":2: field 'landmark_id'", "outside"}},
          {"feature id negative",
           SetField(features, 2, 1, "-1"),
           {features + ":2: field 'landmark_id'"}},
          {"feature landmark not in map",
           SetField(features, 3, 1, "99999"),
           {features + ":3: field 'landmark_id'", "landmark 99999 is not in map.yaml"}},
          {"feature stamp backwards", SetField(features, 3, 0, "5"), {features + ":3", "earlier"}},
      });
  const std::string tags = "mav0/tags0/data.csv";
  ExpectRefused("tags",
                {
                    {"tag id 2.7", SetField(tags, 2, 1, "2.7"), {tags + ":2: field 'tag_id'"}},
                    {"tag id 3e9", SetField(tags, 2, 1, "3e9"), {tags + ":2: field 'tag_id'"}},
                    {"tag short row",
                     ReplaceLine(tags, 2, "1000000000000,1,2,3"),
                     {tags + ":2", "10 fields"}},
                });
  const std::string quantities = "mav0/truth_quantities0/data.csv";
  ExpectRefused(
      "laser",
      {
          {"quantities without header",
           Substitute(quantities,
                      "#timestamp [ns],d [m],v_o [m/s],roll [rad],pitch [rad],alpha [rad]\n", ""),
           {quantities + ":1: field 'header'", "missing"}},
          {"quantities short header",
           Substitute(quantities, ",pitch [rad],alpha [rad]", ""),
           {quantities + ":2", "header names 4"}},
      });
}

// ---- Class 4: silent degradation ----

TEST_F(BadInputCatalogue, GroundTruthThatCannotJudge) {
  const std::string gt = "mav0/state_groundtruth_estimate0/data.csv";
  const auto keep_rows = [](size_t n) {
    return [n](const std::string& before) {
      auto lines = Lines(before);
      lines.resize(std::min(lines.size(), n + 1));
      return JoinLines(lines);
    };
  };
  const auto shift_stamps = [](const std::string& before) {
    auto lines = Lines(before);
    for (size_t i = 1; i < lines.size(); ++i) {
      auto fields = SplitCommas(lines[i]);
      fields[0] = std::to_string(std::stoll(fields[0]) + 3600000000000LL);  // one hour later
      lines[i] = JoinCommas(fields);
    }
    return JoinLines(lines);
  };
  ExpectRefused("features", {
                                {"one-row truth", {gt, keep_rows(1)}, {gt, "1 row"}},
                                {"truth after the data", {gt, shift_stamps}, {gt, "no overlap"}},
                            });
}

TEST_F(BadInputCatalogue, NotApplicableEstimatorsAreNamed) {
  // Pose-only ground truth: dead reckoning would start from zero velocity; it says why it does
  // not run instead, and the default comparison names every estimator it leaves out.
  const std::string gt = "mav0/state_groundtruth_estimate0/data.csv";
  const auto pose_only = [](const std::string& before) {
    auto lines = Lines(before);
    for (auto& line : lines) {
      auto fields = SplitCommas(line);
      fields.resize(8);
      line = JoinCommas(fields);
    }
    return JoinLines(lines);
  };
  ExpectAccepted("features",
                 {{"pose-only truth",
                   {gt, pose_only},
                   {"Not applicable to this dataset:",
                    "imu-dead-reckoning (the ground truth has no velocity", "tag-pnp ("},
                   "default"}});
}

// ---- Class 8: real files that must keep loading ----

TEST_F(BadInputCatalogue, AcceptedRealWorldVariants) {
  const std::string imu = "mav0/imu0/data.csv";
  const std::string gt = "mav0/state_groundtruth_estimate0/data.csv";
  ExpectAccepted(
      "features",
      {
          {"BOM before the IMU header",
           {imu, [](const std::string& s) { return "\xEF\xBB\xBF" + s; }},
           {}},
          {"BOM before sensor.yaml",
           {"mav0/imu0/sensor.yaml", [](const std::string& s) { return "\xEF\xBB\xBF" + s; }},
           {}},
          {"CRLF line ends",
           {imu,
            [](const std::string& s) {
              std::string out;
              for (char c : s) out += c == '\n' ? std::string("\r\n") : std::string(1, c);
              return out;
            }},
           {}},
          {"truth quaternion with 3 decimals",
           {gt,
            [gt](const std::string& text) {
              auto lines = Lines(text);
              auto fields = SplitCommas(lines.at(1));
              for (size_t k = 4; k < 8; ++k) {
                char rounded[32];
                std::snprintf(rounded, sizeof rounded, "%.3f", std::stod(fields[k]));
                fields[k] = rounded;
              }
              lines[1] = JoinCommas(fields);
              return JoinLines(lines);
            }},
           {}},
          {"T_BS with 4 decimals",
           Substitute("mav0/cam0/sensor.yaml", "0.939692620785908", "0.9397"),
           {}},
      });
}

// ---- Trajectory files (eval): TUM, EuRoC CSV, KITTI; messages ----

struct FileCase {
  std::string name;
  std::string estimate;  // contents of est.txt (the ground truth is a valid TUM file)
  std::vector<std::string> expected;
};

// A curved path (a straight one cannot be aligned), one pose per second.
std::string TumRow(int i) {
  return std::to_string(100 + i) + ".0 " + std::to_string(0.1 * i) + " " +
         std::to_string(0.5 * std::sin(0.2 * i)) + " 1 0 0 0 1\n";
}

std::string TumTruth() {
  std::string text = "# timestamp tx ty tz qx qy qz qw\n";
  for (int i = 0; i < 50; ++i) text += TumRow(i);
  return text;
}

void ExpectEvalRefuses(const std::vector<FileCase>& cases, int expected_exit = 2) {
  for (const auto& c : cases) {
    SCOPED_TRACE(c.name);
    const fs::path dir = Scratch() / "eval";
    fs::remove_all(dir);
    fs::create_directories(dir);
    testing::WriteFileBytes(dir / "gt.tum", TumTruth());
    testing::WriteFileBytes(dir / "est.txt", c.estimate);
    const auto result =
        RunCommand(CliPath() + " eval --gt " + (dir / "gt.tum").string() + " --est " +
                   (dir / "est.txt").string() + " --out " + (dir / "report").string());
    EXPECT_EQ(result.exit_code, expected_exit) << result.output.substr(0, 2000);
    for (const auto& expected : c.expected)
      EXPECT_NE(result.output.find(expected), std::string::npos)
          << "expected '" << expected << "' in: " << result.output.substr(0, 2000);
    if (expected_exit != 0) {
      EXPECT_FALSE(fs::exists(dir / "report")) << "a report folder was left behind";
      EXPECT_LT(result.output.size(), 1500u);
      for (char ch : result.output) {
        const auto byte = static_cast<unsigned char>(ch);
        EXPECT_TRUE(byte >= 0x20 || ch == '\n') << "raw control byte " << int(byte);
        if (!(byte >= 0x20 || ch == '\n')) break;
      }
    }
  }
}

std::string TumRows(const std::string& row2) {
  std::string text = "# timestamp tx ty tz qx qy qz qw\n" + TumRow(0) + row2 + "\n";
  for (int i = 2; i < 50; ++i) text += TumRow(i);
  return text;
}

TEST(BadInputCatalogueFiles, TrajectoryFilesRefused) {
  const std::string huge(10 * 1024 * 1024, 'x');
  ExpectEvalRefuses({
      {"position absurd", TumRows("101.0 1e308 0 1 0 0 0 1"), {"est.txt:3", "outside"}},
      {"position nan", TumRows("101.0 nan 0 1 0 0 0 1"), {"est.txt:3", "not finite"}},
      {"stamp absurd", TumRows("1e300 0 0 1 0 0 0 1"), {"est.txt:3", "time"}},
      {"stamp negative", TumRows("-101.0 0 0 1 0 0 0 1"), {"est.txt:3"}},
      {"quaternion zero", TumRows("101.0 0 0 1 0 0 0 0"), {"est.txt:3", "not unit length"}},
      {"quaternion half", TumRows("101.0 0 0 1 0 0 0 0.5"), {"est.txt:3", "not unit length"}},
      {"stamp backwards", TumRows("99.0 0 0 1 0 0 0 1"), {"est.txt:3", "earlier"}},
      {"too few fields", TumRows("101.0 0 0 1"), {"est.txt:3"}},
      {"10 MB field", TumRows("101.0 " + huge + " 0 1 0 0 0 1"), {"est.txt:3", "bytes cut"}},
      {"binary garbage",
       TumRows(std::string("101.0 \x01\x02\x1b[31m\xff 0 1 0 0 0 1")),
       {"est.txt:3", "\\x1B[31m"}},
      {"empty file", "", {"est.txt"}},
      {"one row", "100.0 0 0 1 0 0 0 1\n", {"est.txt", "only 1 pose pair"}},
  });
}

TEST(BadInputCatalogueFiles, TrajectoryFilesAccepted) {
  std::string commas = TumTruth();
  for (auto& ch : commas)
    if (ch == ' ') ch = ',';
  commas = "# timestamp,tx,ty,tz,qx,qy,qz,qw" + commas.substr(commas.find('\n'));
  std::string three_decimals = TumRows("101.0 0.1 0.099 1 0 0 0.001 0.999");
  ExpectEvalRefuses({{"UTF-8 BOM", "\xEF\xBB\xBF" + TumTruth(), {}},
                     {"quaternion with 3 decimals", three_decimals, {}},
                     {"comma-separated TUM", commas, {}}},
                    0);
}

}  // namespace
}  // namespace mavloc
