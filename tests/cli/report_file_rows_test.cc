// compare's report files on a long log: truth.tum, the estimates and errors.csv keep at most 50,000
// rows by default (every k-th row of longer ones, said in report.json and report.md), all of them
// with --full-rate-files; the metrics are the same either way.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "evaluation/report_writer.h"
#include "tests/test_support.h"

namespace fs = std::filesystem;

namespace mavloc {
namespace {

using testing::CliPath;
using testing::RunCommand;

size_t Lines(const fs::path& file) {
  std::ifstream in(file);
  size_t lines = 0;
  for (std::string line; std::getline(in, line);) ++lines;
  return lines;
}

nlohmann::json ReadJson(const fs::path& file) {
  std::ifstream in(file);
  return nlohmann::json::parse(in);
}

TEST(RowStride, IsTheSmallestStrideThatFits) {
  EXPECT_EQ(RowStride(10, 0), 1u);
  EXPECT_EQ(RowStride(50'000, 50'000), 1u);
  EXPECT_EQ(RowStride(50'001, 50'000), 2u);
  EXPECT_EQ(RowStride(720'301, 50'000), 15u);
  EXPECT_LE((720'301 + 14) / 15, 50'000);
}

TEST(ReportFileRows, LongLogsAreThinnedUnlessAllRowsAreAskedFor) {
  const fs::path dir = fs::temp_directory_path() / ("mavloc_rows_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string base = CliPath() +
                           " compare --scenario mav-figure-eight --duration 260 --estimators "
                           "imu-dead-reckoning --report ";
  const auto thinned = RunCommand(base + (dir / "thinned").string());
  ASSERT_EQ(thinned.exit_code, 0) << thinned.output;
  const auto full = RunCommand(base + (dir / "full").string() + " --full-rate-files");
  ASSERT_EQ(full.exit_code, 0) << full.output;

  // One header line, then the poses: 52,301 truth rows at 200 Hz, every 2nd kept.
  const size_t truth_rows = Lines(dir / "full" / "truth.tum") - 1;
  EXPECT_GT(truth_rows, 50'000u);
  EXPECT_EQ(Lines(dir / "thinned" / "truth.tum") - 1, (truth_rows + 1) / 2);
  EXPECT_LE(Lines(dir / "thinned" / "errors.csv"), 50'001u);
  EXPECT_GT(Lines(dir / "full" / "errors.csv"), 50'001u);
  const nlohmann::json t = ReadJson(dir / "thinned" / "report.json");
  const nlohmann::json f = ReadJson(dir / "full" / "report.json");
  EXPECT_EQ(t["details"]["report_files"]["every_kth_row"]["truth.tum"], 2);
  EXPECT_FALSE(f["details"].contains("report_files"));
  std::ifstream md(dir / "thinned" / "report.md");
  const std::string markdown((std::istreambuf_iterator<char>(md)), {});
  EXPECT_NE(markdown.find("--full-rate-files"), std::string::npos);
  // The metrics come from every row either way (the runtime is measured, not computed).
  nlohmann::json te = t["estimators"], fe = f["estimators"];
  te[0].erase("runtime_s");
  fe[0].erase("runtime_s");
  EXPECT_EQ(te, fe);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace mavloc
