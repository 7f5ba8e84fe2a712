// Per-image aprilgrid corner files (yac/Kalibr layout): the real EuRoC imu_april and cam_april
// folders (frames, empty frames, tags, corners) and every bad case with its file, line and field.
#include "datasets/io/aprilgrid_corners_io.h"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "core/errors.h"
#include "tests/test_support.h"

namespace fs = std::filesystem;

namespace mavloc {
namespace {

constexpr const char* kHeader =
    "#ts,tag_rows,tag_cols,tag_size,tag_spacing,kp_x,kp_y,p_x,p_y,p_z,tag_id,corner_idx\n";

AprilgridTarget Euroc6x6() { return {6, 6, 0.088, 0.3}; }

// One row of tag `id`, corner k, at pixel (u, v), with the true grid point.
std::string Row(long long ts, int id, int k, double u = 100, double v = 200) {
  const Eigen::Vector3d p = AprilgridCorner(Euroc6x6(), id, k);
  return fmt::format("{},6,6,0.088000,0.300000,{:.4f},{:.4f},{:.6f},{:.6f},{:.6f},{},{}\n", ts, u,
                     v, p.x(), p.y(), p.z(), id, k);
}

std::string Tag(long long ts, int id) {
  std::string rows;
  for (int k = 0; k < 4; ++k) rows += Row(ts, id, k, 100 + k, 200 + 2 * k);
  return rows;
}

std::string WriteFile(const std::string& dir, const std::string& name, const std::string& text) {
  const std::string path = dir + "/" + name;
  std::ofstream(path) << text;
  return path;
}

std::string ErrorOfFile(const std::string& path, const AprilgridCornerFileOptions& options = {}) {
  try {
    ReadAprilgridCornerFile(path, Euroc6x6(), options);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(AprilgridCornersIo, RealImuAprilLogBothCameras) {
  REQUIRE_SHARED_DATA();
  for (int camera : {0, 1}) {
    AprilgridCornerFileOptions options;
    options.camera = camera;
    options.image_size = Eigen::Vector2i(752, 480);
    const AprilgridCornerLog log = ReadAprilgridCornerFolder(
        testing::SharedDataDir() + "/euroc_imu_april/cam" + std::to_string(camera), Euroc6x6(),
        options);
    // ../shared/data/SOURCES.md: 1,439 files per camera, 23 header-only, about 125 corners per
    // frame.
    EXPECT_EQ(log.stats.frames, 1439);
    EXPECT_EQ(log.frames_ns.size(), 1439u);
    EXPECT_EQ(log.stats.empty_frames, 23);
    EXPECT_EQ(log.frames_ns.front(), 1404733405732800000);
    EXPECT_GT(log.stats.corners, 100L * 1416);
    EXPECT_LT(log.stats.corners, 144L * 1416);
    // Every corner is either in a complete tag or counted as skipped.
    EXPECT_EQ(log.stats.corners, 4 * log.stats.tags + log.stats.incomplete_corners);
    EXPECT_EQ(static_cast<long>(log.tags.size()), log.stats.tags);
    for (size_t i = 1; i < log.frames_ns.size(); ++i)
      ASSERT_LT(log.frames_ns[i - 1], log.frames_ns[i]);
    for (size_t i = 1; i < log.tags.size(); ++i) {
      const auto& a = log.tags[i - 1];
      const auto& b = log.tags[i];
      ASSERT_TRUE(a.t_ns < b.t_ns || (a.t_ns == b.t_ns && a.tag_id < b.tag_id)) << i;
    }
    for (const auto& tag : log.tags) ASSERT_EQ(tag.camera, camera);
  }
}

TEST(AprilgridCornersIo, FirstTagOfTheFirstFrameInCornerIdxOrder) {
  REQUIRE_SHARED_DATA();
  const AprilgridCornerFrame frame = ReadAprilgridCornerFile(
      testing::SharedDataDir() + "/euroc_imu_april/cam0/1404733405732800000.csv", Euroc6x6());
  ASSERT_FALSE(frame.tags.empty());
  const TagObservation& tag0 = frame.tags.front();
  EXPECT_EQ(tag0.tag_id, 0);
  EXPECT_EQ(tag0.t_ns, 1404733405732800000);
  // The file's first four rows (tag 0, corner_idx 0..3).
  EXPECT_NEAR(tag0.corners_px[0].x(), 175.9866943359, 1e-9);
  EXPECT_NEAR(tag0.corners_px[0].y(), 336.8252258301, 1e-9);
  EXPECT_NEAR(tag0.corners_px[1].x(), 213.3338928223, 1e-9);
  EXPECT_NEAR(tag0.corners_px[2].y(), 296.1163635254, 1e-9);
  EXPECT_NEAR(tag0.corners_px[3].x(), 170.5467529297, 1e-9);
}

TEST(AprilgridCornersIo, RealCamAprilFolder) {
  REQUIRE_SHARED_DATA();
  const AprilgridCornerLog log =
      ReadAprilgridCornerFolder(testing::SharedDataDir() + "/euroc_cam_april/cam1", Euroc6x6());
  EXPECT_EQ(log.stats.frames, 30);
  EXPECT_GT(log.stats.tags, 0);
}

TEST(AprilgridCornersIo, GroupsRowsByTagAndSkipsIncompleteTags) {
  const std::string dir = testing::MakeTempDir();
  // Tag 7 complete but listed out of order and interleaved with tag 3 (3 corners only).
  const long long ts = 1000;
  const std::string text = std::string(kHeader) + Row(ts, 7, 2, 12, 22) + Row(ts, 3, 0) +
                           Row(ts, 7, 0, 10, 20) + Row(ts, 3, 1) + Row(ts, 7, 3, 13, 23) +
                           Row(ts, 3, 3) + Row(ts, 7, 1, 11, 21) + Tag(ts, 35);
  const AprilgridCornerFrame frame =
      ReadAprilgridCornerFile(WriteFile(dir, "1000.csv", text), Euroc6x6(), {1, {}, 1e-6});
  EXPECT_EQ(frame.t_ns, 1000);
  EXPECT_EQ(frame.corners, 11);
  EXPECT_EQ(frame.incomplete_tags, 1);
  EXPECT_EQ(frame.incomplete_corners, 3);
  ASSERT_EQ(frame.tags.size(), 2u);
  EXPECT_EQ(frame.tags[0].tag_id, 7);
  EXPECT_EQ(frame.tags[0].camera, 1);
  for (int k = 0; k < 4; ++k) {
    EXPECT_DOUBLE_EQ(frame.tags[0].corners_px[k].x(), 10 + k);
    EXPECT_DOUBLE_EQ(frame.tags[0].corners_px[k].y(), 20 + k);
  }
  EXPECT_EQ(frame.tags[1].tag_id, 35);
}

TEST(AprilgridCornersIo, HeaderOnlyFilesAreEmptyFrames) {
  const std::string dir = testing::MakeTempDir();
  WriteFile(dir, "2000.csv", kHeader);
  WriteFile(dir, "1000.csv", std::string(kHeader) + Tag(1000, 0));
  WriteFile(dir, "3000.csv", "");
  WriteFile(dir, "notes.txt", "not a corner file");
  const AprilgridCornerLog log = ReadAprilgridCornerFolder(dir, Euroc6x6());
  EXPECT_EQ(log.frames_ns, (std::vector<TimeNs>{1000, 2000, 3000}));
  EXPECT_EQ(log.stats.frames, 3);
  EXPECT_EQ(log.stats.empty_frames, 2);
  EXPECT_EQ(log.stats.tags, 1);
  EXPECT_EQ(log.stats.corners, 4);
}

TEST(AprilgridCornersIo, BadRowsNameFileLineAndField) {
  const std::string dir = testing::MakeTempDir();
  auto error_with_row = [&](const std::string& row) {
    return ErrorOfFile(WriteFile(dir, "1000.csv", std::string(kHeader) + Tag(1000, 0) + row));
  };
  const std::string file = dir + "/1000.csv:6: field ";
  // A grid point that is not the target's.
  {
    std::string row = Row(1000, 8, 2);
    row.replace(row.find("0.316800"), 8, "0.316802");  // p_x of tag 8 corner 2 is 0.3168
    const std::string e = error_with_row(row);
    EXPECT_NE(e.find(file + "'p_x'"), std::string::npos) << e;
    EXPECT_NE(e.find("not tag 8 corner 2"), std::string::npos) << e;
  }
  // Within the 1e-6 m tolerance (the files print p with 6 decimals) a point is accepted.
  {
    std::string row = Row(1000, 8, 2);
    row.replace(row.find("0.316800"), 8, "0.3168005");
    EXPECT_EQ(error_with_row(row), "");
  }
  // The same row with the wrong corner index is caught through p too.
  {
    std::string row = Row(1000, 8, 2);
    row.back() = '\n';
    row[row.size() - 2] = '1';
    EXPECT_NE(error_with_row(row).find(file + "'p_y'"), std::string::npos);
  }
  EXPECT_NE(error_with_row("1000,6,6,0.088,0.3,1,2,0,0,0,36,0\n").find(file + "'tag_id'"),
            std::string::npos);
  EXPECT_NE(error_with_row("1000,6,6,0.088,0.3,1,2,0,0,0,0,4\n").find(file + "'corner_idx'"),
            std::string::npos);
  EXPECT_NE(error_with_row("1000,6,7,0.088,0.3,1,2,0,0,0,0,0\n").find(file + "'tag_cols'"),
            std::string::npos);
  EXPECT_NE(error_with_row("1000,6,6,0.09,0.3,1,2,0,0,0,0,0\n").find(file + "'tag_size'"),
            std::string::npos);
  EXPECT_NE(error_with_row("1000,6,6,0.088,0.25,1,2,0,0,0,0,0\n").find(file + "'tag_spacing'"),
            std::string::npos);
  EXPECT_NE(error_with_row("1000,6,6,0.088,0.3,nan,2,0,0,0,0,0\n").find(file + "'kp_x'"),
            std::string::npos);
  EXPECT_NE(error_with_row("1000,6,6,0.088,0.3,1,inf,0,0,0,0,0\n").find(file + "'kp_y'"),
            std::string::npos);
  EXPECT_NE(
      error_with_row("1000,6,6,0.088,0.3,1,2,0,0,0,0\n").find("expected 12 columns, found 11"),
      std::string::npos);
  EXPECT_NE(error_with_row("1000,6,6,0.088,0.3,1,2,0,0,0,0,0,9\n").find("found 13"),
            std::string::npos);
  EXPECT_NE(error_with_row("1001,6,6,0.088,0.3,1,2,0,0,0,0,0\n").find(file + "'ts'"),
            std::string::npos);
  EXPECT_NE(error_with_row("1000,6,6,0.088,0.3,1x,2,0,0,0,0,0\n").find("'1x' is not a number"),
            std::string::npos);
  // A corner listed twice.
  {
    const std::string e = error_with_row(Row(1000, 0, 3));
    EXPECT_NE(e.find(file + "'corner_idx'"), std::string::npos) << e;
    EXPECT_NE(e.find("tag 0 corner 3 listed twice (first on line 5)"), std::string::npos) << e;
  }
  // A pixel outside the image, when its size is known.
  {
    const std::string path =
        WriteFile(dir, "1000.csv", std::string(kHeader) + Row(1000, 0, 0, 752.2, 10));
    EXPECT_EQ(ErrorOfFile(path), "");
    const std::string e = ErrorOfFile(path, {0, Eigen::Vector2i(752, 480), 1e-6});
    EXPECT_NE(e.find("1000.csv:2: field 'kp_x'"), std::string::npos) << e;
    EXPECT_NE(e.find("outside the 752x480 image"), std::string::npos) << e;
  }
  // A header with other columns.
  {
    const std::string e =
        ErrorOfFile(WriteFile(dir, "1000.csv",
                              "#ts,tag_rows,tag_cols,tag_size,tag_spacing,kp_y,kp_x,p_x,p_y,p_z,"
                              "tag_id,corner_idx\n"));
    EXPECT_NE(e.find("1000.csv:1: field 'kp_x'"), std::string::npos) << e;
  }
}

TEST(AprilgridCornersIo, BadFileNamesAndFramesListedTwice) {
  const std::string dir = testing::MakeTempDir();
  WriteFile(dir, "1000.csv", std::string(kHeader) + Tag(1000, 0));
  WriteFile(dir, "0001000.csv", kHeader);
  try {
    ReadAprilgridCornerFolder(dir, Euroc6x6());
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("frame 1000 listed twice"), std::string::npos) << e.what();
  }
  fs::remove(dir + "/0001000.csv");
  WriteFile(dir, "frame_12.csv", kHeader);
  try {
    ReadAprilgridCornerFolder(dir, Euroc6x6());
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("frame_12.csv: file name 'frame_12' is not a timestamp"),
              std::string::npos)
        << e.what();
  }
  EXPECT_THROW(ReadAprilgridCornerFolder(dir + "/absent", Euroc6x6()), InputError);
  const std::string empty = dir + "/empty";
  fs::create_directories(empty);
  EXPECT_THROW(ReadAprilgridCornerFolder(empty, Euroc6x6()), InputError);
}

}  // namespace
}  // namespace mavloc
