// detect-tags --family aprilgrid --target FILE: with the board known, the tags the detector missed
// on the real hand-held D435i frames are predicted from the grid (frontends/apriltag/
// aprilgrid_detector.h), so the CLI finds more of them; a board for another family, or a file
// without a board, is a clear error with nothing written.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "tests/test_support.h"

namespace mavloc {
namespace {

namespace fs = std::filesystem;
using testing::CliRun;
using testing::RunCliIn;

// Detections in the photo CSV written by `detect-tags --images` (one row each, after the header).
int DetectionRows(const std::string& csv) {
  int rows = -1;  // the header
  for (const char c : testing::ReadFileBytes(csv)) rows += c == '\n' ? 1 : 0;
  return rows;
}

TEST(DetectTagsTarget, TheBoardFindsMoreTagsOnHandHeldFrames) {
  REQUIRE_SHARED_DATA();
  const std::string dir = testing::MakeTempDir();
  const std::string data = testing::SharedDataDir() + "/d435i_aprilgrid";
  const std::string images = "detect-tags --family aprilgrid --images " + data + "/cam0/data";
  const CliRun plain = RunCliIn(dir, images + " --out plain.csv");
  ASSERT_EQ(plain.exit_code, 0) << plain.err;
  const CliRun board =
      RunCliIn(dir, images + " --target " + data + "/calib_mocap-intel_d435i.yaml --out board.csv");
  ASSERT_EQ(board.exit_code, 0) << board.err;
  const int without = DetectionRows(dir + "/plain.csv"), with = DetectionRows(dir + "/board.csv");
  // yac finds 339 tags on the grid in these 10 frames (frontends_aprilgrid_handheld_test checks
  // the matches, corners and ids): at least 95 % of them with the board.
  EXPECT_GE(with, 322) << "with the board";
  EXPECT_GT(with, without);
}

TEST(DetectTagsTarget, ABoardForAnotherFamilyOrAFileWithoutABoardIsAnError) {
  REQUIRE_SHARED_DATA();
  const std::string dir = testing::MakeTempDir();
  const std::string data = testing::SharedDataDir() + "/d435i_aprilgrid";
  const CliRun family =
      RunCliIn(dir, "detect-tags --images " + data + "/cam0/data --out o.csv --target " + data +
                        "/calib_mocap-intel_d435i.yaml");
  EXPECT_EQ(family.exit_code, 2);
  EXPECT_NE(family.err.find("--family aprilgrid"), std::string::npos) << family.err;
  testing::WriteFileBytes(dir + "/empty.yaml", "camera: 1\n");
  const CliRun empty = RunCliIn(dir, "detect-tags --family aprilgrid --images " + data +
                                         "/cam0/data --out o.csv --target " + dir + "/empty.yaml");
  EXPECT_EQ(empty.exit_code, 2);
  EXPECT_NE(empty.err.find("empty.yaml"), std::string::npos) << empty.err;
  EXPECT_FALSE(fs::exists(dir + "/o.csv"));
}

}  // namespace
}  // namespace mavloc
