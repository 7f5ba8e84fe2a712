// The aprilgrid description in both spellings (Kalibr's target.yaml camelCase, yac's snake_case at
// the top level or under calib_target), on the real files of ../shared/data and on bad input; the
// target kept in map parameters.
#include "datasets/io/aprilgrid_target_io.h"

#include <gtest/gtest.h>

#include <fstream>

#include "core/errors.h"
#include "datasets/io/yaml_util.h"
#include "tests/test_support.h"

namespace mavloc {
namespace {

void ExpectEuroc6x6(const AprilgridTarget& t) {
  EXPECT_EQ(t.tag_rows, 6);
  EXPECT_EQ(t.tag_cols, 6);
  EXPECT_DOUBLE_EQ(t.tag_size_m, 0.088);
  EXPECT_DOUBLE_EQ(t.tag_spacing, 0.3);
}

std::string WriteYaml(const std::string& name, const std::string& text) {
  const std::string path = testing::MakeTempDir() + "/" + name;
  std::ofstream(path) << text;
  return path;
}

std::string ErrorOf(const std::string& path) {
  try {
    ReadAprilgridTarget(path);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(AprilgridTargetIo, ReadsTheRealTargetAndConfigFiles) {
  REQUIRE_SHARED_DATA();
  const std::string data = testing::SharedDataDir();
  ExpectEuroc6x6(ReadAprilgridTarget(data + "/euroc_cam_april/target.yaml"));  // top level
  ExpectEuroc6x6(ReadAprilgridTarget(data + "/euroc_imu_april/config.yaml"));  // calib_target
  ExpectEuroc6x6(ReadAprilgridTarget(data + "/euroc_cam_april/stereo_config.yaml"));
}

TEST(AprilgridTargetIo, KalibrCamelCaseKeys) {
  const std::string path = WriteYaml("target.yaml",
                                     "target_type: 'aprilgrid'\ntagCols: 7\ntagRows: 5\n"
                                     "tagSize: 0.025\ntagSpacing: 0.25\n");
  const AprilgridTarget t = ReadAprilgridTarget(path);
  EXPECT_EQ(t.tag_rows, 5);
  EXPECT_EQ(t.tag_cols, 7);
  EXPECT_DOUBLE_EQ(t.tag_size_m, 0.025);
  EXPECT_DOUBLE_EQ(t.tag_spacing, 0.25);
}

TEST(AprilgridTargetIo, NoTargetInAFileIsNulloptOrAnError) {
  const std::string path = WriteYaml("camchain.yaml", "cam0: {intrinsics: [1, 1, 0, 0]}\n");
  EXPECT_FALSE(FindAprilgridTarget(LoadYamlFile(path), path).has_value());
  EXPECT_NE(ErrorOf(path).find("no aprilgrid description"), std::string::npos);
}

TEST(AprilgridTargetIo, BadDescriptionsNameFileLineAndField) {
  {
    const std::string e = ErrorOf(
        WriteYaml("t.yaml", "target_type: 'checkerboard'\ntagRows: 6\ntagCols: 6\ntagSize: 1\n"));
    EXPECT_NE(e.find("t.yaml:1: field 'target_type'"), std::string::npos) << e;
    EXPECT_NE(e.find("checkerboard"), std::string::npos) << e;
  }
  {
    const std::string e = ErrorOf(
        WriteYaml("t.yaml", "tag_rows: 6\ntag_cols: 6.5\ntag_size: 0.1\ntag_spacing: 0.3\n"));
    EXPECT_NE(e.find("t.yaml:2: field 'tag_cols'"), std::string::npos) << e;
  }
  {
    const std::string e = ErrorOf(
        WriteYaml("t.yaml", "calib_target:\n  tag_rows: 6\n  tag_cols: 6\n  tag_size: 0.1\n"));
    EXPECT_NE(e.find("tag_spacing"), std::string::npos) << e;
    EXPECT_NE(e.find("missing"), std::string::npos) << e;
  }
  {
    const std::string e =
        ErrorOf(WriteYaml("t.yaml", "tagRows: 6\ntagCols: 6\ntagSize: -0.1\ntagSpacing: 0.3\n"));
    EXPECT_NE(e.find("tag_size must be a positive length"), std::string::npos) << e;
  }
  {
    const std::string e =
        ErrorOf(WriteYaml("t.yaml", "tagRows: 6\ntagCols: 6\ntagSize: abc\ntagSpacing: 0.3\n"));
    EXPECT_NE(e.find("t.yaml:3: field 'tagSize': 'abc' is not a number"), std::string::npos) << e;
  }
}

TEST(AprilgridTargetIo, MapParametersRoundTrip) {
  const AprilgridTarget t{5, 7, 0.025, 0.25};
  WorldMap map;
  EXPECT_FALSE(AprilgridFromMap(map).has_value());
  map.parameters = AprilgridMapParameters(t);
  const auto back = AprilgridFromMap(map);
  ASSERT_TRUE(back.has_value());
  EXPECT_EQ(back->tag_rows, 5);
  EXPECT_EQ(back->tag_cols, 7);
  EXPECT_DOUBLE_EQ(back->tag_size_m, 0.025);
  EXPECT_DOUBLE_EQ(back->tag_spacing, 0.25);
  map.parameters.erase("aprilgrid_tag_cols");
  EXPECT_THROW(AprilgridFromMap(map), InputError);
}

}  // namespace
}  // namespace mavloc
