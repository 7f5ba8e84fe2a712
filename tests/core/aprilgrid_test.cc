// Kalibr's aprilgrid numbering (core/aprilgrid.h): the corner positions and grid point indices of
// the header's diagram, the map tags' corner order, and the convention checked against every
// corner row of the real EuRoC corner files (euroc_imu_april, euroc_cam_april, both cameras),
// which carry each corner's grid point p beside its tag_id and corner_idx. The files are parsed
// here with a few lines of their own, independently of datasets/io's reader.
#include "core/aprilgrid.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>

#include "core/tag_geometry.h"
#include "tests/test_support.h"

namespace fs = std::filesystem;

namespace mavloc {
namespace {

AprilgridTarget Euroc6x6() { return {6, 6, 0.088, 0.3}; }

TEST(Aprilgrid, ValidateNamesWhatIsWrong) {
  EXPECT_EQ(Euroc6x6().Validate(), "");
  EXPECT_NE(AprilgridTarget({0, 6, 0.088, 0.3}).Validate().find("tag_rows"), std::string::npos);
  EXPECT_NE(AprilgridTarget({6, -1, 0.088, 0.3}).Validate().find("tag_cols"), std::string::npos);
  EXPECT_NE(AprilgridTarget({6, 6, 0.0, 0.3}).Validate().find("tag_size"), std::string::npos);
  EXPECT_NE(AprilgridTarget({6, 6, 0.088, -0.1}).Validate().find("tag_spacing"), std::string::npos);
  EXPECT_NE(AprilgridTarget({6, 6, std::nan(""), 0.3}).Validate(), "");
  EXPECT_EQ(AprilgridTarget({6, 6, 0.088, 0.0}).Validate(), "");  // touching tags are allowed
}

TEST(Aprilgrid, CornersOfTheFirstTagsAndPitch) {
  const AprilgridTarget t = Euroc6x6();
  EXPECT_EQ(t.NumTags(), 36);
  EXPECT_NEAR(t.PitchM(), 0.1144, 1e-15);
  const double s = 0.088, pitch = 0.1144;
  const Eigen::Vector3d tag0[4] = {{0, 0, 0}, {s, 0, 0}, {s, s, 0}, {0, s, 0}};
  for (int k = 0; k < 4; ++k) {
    EXPECT_NEAR((AprilgridCorner(t, 0, k) - tag0[k]).norm(), 0, 1e-15) << k;
    EXPECT_NEAR((AprilgridCorner(t, 1, k) - tag0[k] - Eigen::Vector3d(pitch, 0, 0)).norm(), 0,
                1e-15);  // tag 1: next column, along x
    EXPECT_NEAR((AprilgridCorner(t, 6, k) - tag0[k] - Eigen::Vector3d(0, pitch, 0)).norm(), 0,
                1e-15);  // tag 6: next row, along y
    EXPECT_NEAR(
        (AprilgridCorner(t, 35, k) - tag0[k] - Eigen::Vector3d(5 * pitch, 5 * pitch, 0)).norm(), 0,
        1e-15);
  }
  // A non-square grid: ids run along a row (x) first.
  const AprilgridTarget wide{2, 3, 0.1, 0.5};
  EXPECT_TRUE(AprilgridCorner(wide, 2, 0).isApprox(Eigen::Vector3d(0.3, 0, 0)));
  EXPECT_TRUE(AprilgridCorner(wide, 3, 0).isApprox(Eigen::Vector3d(0, 0.15, 0)));
}

TEST(Aprilgrid, KalibrPointIndexMatchesTheDiagram) {
  // core/aprilgrid.h's 2x2 diagram: tag t, corners 0..3 -> grid points.
  const AprilgridTarget t{2, 2, 0.1, 0.2};
  const int expected[4][4] = {{0, 1, 5, 4}, {2, 3, 7, 6}, {8, 9, 13, 12}, {10, 11, 15, 14}};
  for (int tag = 0; tag < 4; ++tag)
    for (int k = 0; k < 4; ++k) EXPECT_EQ(KalibrPointIndex(t, tag, k), expected[tag][k]);
  // On any grid the index is a bijection onto 0 .. 4 N - 1, row-major in (y, x): point
  // (r, c) of the 2 rows x 2 cols point lattice sits at x = c/2 pitch + (c%2) s, y likewise.
  const AprilgridTarget g{4, 5, 0.05, 0.25};
  std::set<int> seen;
  for (int tag = 0; tag < g.NumTags(); ++tag) {
    for (int k = 0; k < 4; ++k) {
      const int point = KalibrPointIndex(g, tag, k);
      EXPECT_TRUE(seen.insert(point).second) << point;
      const int r = point / (2 * g.tag_cols), c = point % (2 * g.tag_cols);
      const Eigen::Vector3d p((c / 2) * g.PitchM() + (c % 2) * g.tag_size_m,
                              (r / 2) * g.PitchM() + (r % 2) * g.tag_size_m, 0.0);
      EXPECT_NEAR((AprilgridCorner(g, tag, k) - p).norm(), 0.0, 1e-15) << tag << " " << k;
    }
  }
  EXPECT_EQ(seen.size(), 4u * g.NumTags());
  EXPECT_EQ(*seen.begin(), 0);
  EXPECT_EQ(*seen.rbegin(), 4 * g.NumTags() - 1);
}

TEST(Aprilgrid, MapTagsHaveTheGridCornersInMavlocOrder) {
  const AprilgridTarget t{3, 4, 0.06, 0.3};
  const auto tags = AprilgridTags(t);
  ASSERT_EQ(tags.size(), 12u);
  for (const auto& [id, tag] : tags) {
    EXPECT_EQ(tag.id, id);
    EXPECT_DOUBLE_EQ(tag.size_m, 0.06);
    EXPECT_TRUE(tag.T_W_T.q.isApprox(Eigen::Quaterniond::Identity()));
    const auto corners = TagCornersInWorld(tag);
    for (int k = 0; k < 4; ++k)
      EXPECT_NEAR((corners[k] - AprilgridCorner(t, id, k)).norm(), 0.0, 1e-15) << id << " " << k;
    // Counter-clockwise seen from +z (towards the camera).
    EXPECT_GT((corners[1] - corners[0]).cross(corners[2] - corners[1]).z(), 0.0);
  }
  EXPECT_EQ(tags.begin()->first, 0);
  EXPECT_EQ(tags.rbegin()->first, 11);
}

// Every row "ts,tag_rows,tag_cols,tag_size,tag_spacing,kp_x,kp_y,p_x,p_y,p_z,tag_id,corner_idx"
// of every corner file in `folder`: p must be AprilgridCorner(tag_id, corner_idx) within 1e-6.
struct FolderCheck {
  long files = 0, rows = 0, mismatches = 0;
  std::set<int> tag_ids;
  std::string first_mismatch;
};

FolderCheck CheckFolder(const std::string& folder, const AprilgridTarget& target) {
  FolderCheck check;
  for (const auto& entry : fs::directory_iterator(folder)) {
    if (entry.path().extension() != ".csv") continue;
    ++check.files;
    std::ifstream in(entry.path());
    std::string line;
    long number = 0;
    while (std::getline(in, line)) {
      ++number;
      if (line.empty() || line[0] == '#') continue;
      long long ts = 0;
      int rows = 0, cols = 0, tag_id = -1, corner_idx = -1;
      double size = 0, spacing = 0, kp_x = 0, kp_y = 0, p_x = 0, p_y = 0, p_z = 0;
      const int n =
          std::sscanf(line.c_str(), "%lld,%d,%d,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%d,%d", &ts, &rows,
                      &cols, &size, &spacing, &kp_x, &kp_y, &p_x, &p_y, &p_z, &tag_id, &corner_idx);
      ++check.rows;
      const bool grid_ok = n == 12 && rows == target.tag_rows && cols == target.tag_cols &&
                           std::abs(size - target.tag_size_m) <= 1e-6 &&
                           std::abs(spacing - target.tag_spacing) <= 1e-6 && tag_id >= 0 &&
                           tag_id < target.NumTags() && corner_idx >= 0 && corner_idx < 4;
      const bool point_ok =
          grid_ok && (AprilgridCorner(target, tag_id, corner_idx) - Eigen::Vector3d(p_x, p_y, p_z))
                             .cwiseAbs()
                             .maxCoeff() <= 1e-6;
      if (!point_ok) {
        if (check.mismatches++ == 0)
          check.first_mismatch = entry.path().string() + ":" + std::to_string(number) + ": " + line;
      } else {
        check.tag_ids.insert(tag_id);
      }
    }
  }
  return check;
}

TEST(Aprilgrid, KalibrConventionHoldsForEveryCornerOfTheEurocLogs) {
  if (!testing::HasSharedData()) GTEST_SKIP() << "../shared/data is absent";
  const std::string data = testing::SharedDataDir();
  long rows = 0;
  for (const char* log : {"euroc_imu_april", "euroc_cam_april"}) {
    for (const char* camera : {"cam0", "cam1"}) {
      const FolderCheck check = CheckFolder(data + "/" + log + "/" + camera, Euroc6x6());
      SCOPED_TRACE(std::string(log) + "/" + camera);
      EXPECT_EQ(check.files, std::string(log) == "euroc_imu_april" ? 1439 : 30);
      EXPECT_GT(check.rows, 20 * check.files);
      EXPECT_EQ(check.mismatches, 0) << "first: " << check.first_mismatch;
      // Every tag of the grid is seen somewhere in the 72 s log (34 of 36 in cam_april's cam0).
      if (std::string(log) == "euroc_imu_april") {
        EXPECT_EQ(check.tag_ids.size(), 36u);
      }
      rows += check.rows;
    }
  }
  EXPECT_EQ(rows, 366080);  // 2 x 1,439 + 2 x 30 files
  std::printf("checked %ld corner rows\n", rows);
}

}  // namespace
}  // namespace mavloc
