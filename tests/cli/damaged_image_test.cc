// A damaged image (a real frame of the shared data cut short or with a corrupt byte) is one error:
// exactly one stderr line from mavloc naming the file, exit code 2 — never libpng's or libjpeg's
// own line before it ("libpng error: Read Error"), and never a truncated JPEG decoded into a
// half-grey image (core/image_check.h).
#include <gtest/gtest.h>
#include <rosbag/bag.h>

#include <algorithm>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "datasets/io/rosbag/ros_messages.h"
#include "tests/test_support.h"

namespace fs = std::filesystem;

namespace mavloc {
namespace {

const std::string kEurocFrame = "/euroc_v1_01_easy/mav0/cam0/data/1403715273262142976.png";
const std::string kD435Frame = "/d435i_aprilgrid/cam0/data/1606153907495166540.jpg";

std::string Shared(const std::string& relative) { return testing::SharedDataDir() + relative; }

// The real file cut to its first `bytes` bytes.
std::string Truncated(const std::string& relative, size_t bytes) {
  return testing::ReadFileBytes(Shared(relative)).substr(0, bytes);
}

// The real file with four bytes zeroed at `offset` (inside the PNG's image data: a CRC error).
std::string Corrupted(const std::string& relative, size_t offset) {
  std::string bytes = testing::ReadFileBytes(Shared(relative));
  std::fill_n(bytes.begin() + static_cast<std::ptrdiff_t>(offset), 4, '\0');
  return bytes;
}

// An EuRoC dataset in `dir`: symbolic links to the shared dataset's files, except cam0's frame
// `damaged_name`, written with `damaged`.
void LinkedDatasetWith(const std::string& dir, const std::string& damaged_name,
                       const std::string& damaged) {
  const fs::path source = Shared("/euroc_v1_01_easy");
  fs::create_directories(dir);
  for (const auto& entry : fs::recursive_directory_iterator(source)) {
    const fs::path target = dir / fs::relative(entry.path(), source);
    if (entry.is_directory()) {
      fs::create_directories(target);
    } else if (entry.path().filename() == damaged_name) {
      testing::WriteFileBytes(target.string(), damaged);
    } else {
      fs::create_symlink(entry.path(), target);
    }
  }
}

// A bag with one sensor_msgs/CompressedImage on /cam0 holding `bytes` as a "png".
void CompressedImageBag(const std::string& path, const std::string& bytes) {
  rosbag::Bag bag(path, rosbag::bagmode::Write);
  ros1::CompressedImageMsg message;
  message.header.stamp = ros::Time(1000, 0);
  message.format = "png";
  message.data.assign(bytes.begin(), bytes.end());
  bag.write("/cam0", message.header.stamp, message);
}

struct DamagedCase {
  const char* name;
  // Writes the inputs into `dir` and returns the arguments of the command.
  std::function<std::string(const std::string& dir)> prepare;
  std::string names;  // the stderr line names this
  std::string says;   // and says this
};

const DamagedCase kCases[] = {
    {"TruncatedPng",
     [](const std::string& dir) {
       testing::WriteFileBytes(dir + "/frame.png", Truncated(kEurocFrame, 20000));
       return "detect-tags --images frame.png --out tags.csv";
     },
     "frame.png", "cannot decode image: PNG: Read Error"},
    {"PngCutInItsHeader",
     [](const std::string& dir) {
       testing::WriteFileBytes(dir + "/frame.png", Truncated(kEurocFrame, 40));
       return "detect-tags --images frame.png --out tags.csv";
     },
     "frame.png", "cannot decode image: PNG:"},
    {"PngWithACorruptByte",
     [](const std::string& dir) {
       testing::WriteFileBytes(dir + "/frame.png", Corrupted(kEurocFrame, 100000));
       return "detect-tags --images frame.png --out tags.csv";
     },
     "frame.png", "cannot decode image: PNG: IDAT: CRC error"},
    {"TruncatedJpeg",
     [](const std::string& dir) {
       testing::WriteFileBytes(dir + "/frame.jpg", Truncated(kD435Frame, 12000));
       return "detect-tags --images frame.jpg --out tags.csv";
     },
     "frame.jpg", "cannot decode image: JPEG: Premature end of JPEG file"},
    {"TruncatedFrameOfADataset",
     [](const std::string& dir) {
       LinkedDatasetWith(
           dir + "/dataset", "1403715273312143104.png",
           Truncated("/euroc_v1_01_easy/mav0/cam0/data/1403715273312143104.png", 30000));
       return "detect-tags --dataset dataset --out tags.csv";
     },
     "1403715273312143104.png", "cannot decode image: PNG: Read Error"},
    {"TruncatedCompressedImageInABag",
     [](const std::string& dir) {
       CompressedImageBag(dir + "/images.bag", Truncated(kEurocFrame, 20000));
       return "log import images.bag --images /cam0 --calibration cam0=" +
              Shared("/euroc_v1_01_easy/mav0/cam0/sensor.yaml") + " --out dataset";
     },
     "images.bag: topic /cam0, message 0", "PNG: Read Error"},
};

class DamagedImage : public ::testing::TestWithParam<DamagedCase> {};

TEST_P(DamagedImage, OneStderrLineNamingTheFile) {
  REQUIRE_SHARED_DATA();
  const DamagedCase& c = GetParam();
  const std::string dir = testing::MakeTempDir();
  const std::string args = c.prepare(dir);
  const testing::CliRun r = testing::RunCliIn(dir, args);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_EQ(r.err.rfind("mavloc: error: ", 0), 0u) << r.err;
  EXPECT_NE(r.err.find(c.names), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(c.says), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir + "/tags.csv"));
}

INSTANTIATE_TEST_SUITE_P(RealFrames, DamagedImage, ::testing::ValuesIn(kCases),
                         [](const auto& row) { return std::string(row.param.name); });

// The undamaged frames still decode (to the pixels OpenCV gives).
TEST(DamagedImageControl, RealFramesDecode) {
  REQUIRE_SHARED_DATA();
  const std::string dir = testing::MakeTempDir();
  for (const std::string& frame : {kEurocFrame, kD435Frame}) {
    const testing::CliRun r =
        testing::RunCliIn(dir, "detect-tags --images " + Shared(frame) + " --out tags.csv");
    EXPECT_EQ(r.exit_code, 0) << frame << ": " << r.err;
    EXPECT_EQ(r.err, "") << frame;
  }
}

}  // namespace
}  // namespace mavloc
