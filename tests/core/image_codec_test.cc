// core/image_codec.h: the pixels of every PNG and JPEG image of ../shared/data equal OpenCV's
// cv::imdecode's (gray and unchanged), PNG encoding round-trips 8- and 16-bit images of 1, 3 and
// 4 channels, and damaged or foreign bytes are refused with a reason.
#include "core/image_codec.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <vector>

#include "tests/test_support.h"

namespace fs = std::filesystem;

namespace mavloc {
namespace {

std::vector<std::string> SharedImages() {
  std::vector<std::string> paths;
  const fs::path root = testing::SharedDataDir();
  if (!fs::exists(root)) return paths;
  for (const auto& entry : fs::recursive_directory_iterator(root)) {
    const std::string ext = entry.path().extension().string();
    if (ext == ".png" || ext == ".jpg" || ext == ".jpeg") paths.push_back(entry.path().string());
  }
  return paths;
}

bool SamePixels(const cv::Mat& a, const cv::Mat& b) {
  return a.type() == b.type() && a.size() == b.size() && cv::norm(a, b, cv::NORM_INF) == 0.0;
}

TEST(ImageCodec, SharedImagesDecodeAsOpenCvDecodesThem) {
  const std::vector<std::string> paths = SharedImages();
  if (paths.empty()) GTEST_SKIP() << "../shared/data is absent";
  ASSERT_GT(paths.size(), 100u);
  for (const std::string& path : paths) {
    SCOPED_TRACE(path);
    const std::string bytes = testing::ReadFileBytes(path);
    const cv::Mat encoded(1, static_cast<int>(bytes.size()), CV_8UC1,
                          const_cast<char*>(bytes.data()));
    std::string why;
    const cv::Mat gray = DecodeImage(bytes, ImageDecodeMode::kGray8, &why);
    ASSERT_FALSE(gray.empty()) << why;
    EXPECT_TRUE(SamePixels(gray, cv::imdecode(encoded, cv::IMREAD_GRAYSCALE)));
    const cv::Mat unchanged = DecodeImage(bytes, ImageDecodeMode::kUnchanged, &why);
    ASSERT_FALSE(unchanged.empty()) << why;
    EXPECT_TRUE(SamePixels(unchanged, cv::imdecode(encoded, cv::IMREAD_UNCHANGED)));
  }
}

TEST(ImageCodec, PngRoundTripsEveryLayoutItWrites) {
  for (const int depth : {CV_8U, CV_16U}) {
    for (const int channels : {1, 3, 4}) {
      SCOPED_TRACE(::testing::Message() << "depth " << depth << " channels " << channels);
      cv::Mat image(13, 17, CV_MAKETYPE(depth, channels));
      cv::randu(image, 0, depth == CV_8U ? 256 : 65536);
      std::string why;
      const std::string png = EncodePng(image);
      const cv::Mat back = DecodeImage(png, ImageDecodeMode::kUnchanged, &why);
      EXPECT_TRUE(SamePixels(back, image)) << why;
      // What OpenCV reads from it: the same pixels.
      const cv::Mat encoded(1, static_cast<int>(png.size()), CV_8UC1,
                            const_cast<char*>(png.data()));
      EXPECT_TRUE(SamePixels(cv::imdecode(encoded, cv::IMREAD_UNCHANGED), image));
      EXPECT_TRUE(SamePixels(DecodeImage(png, ImageDecodeMode::kGray8, &why),
                             cv::imdecode(encoded, cv::IMREAD_GRAYSCALE)));
    }
  }
  EXPECT_THROW(EncodePng(cv::Mat(2, 2, CV_32FC1)), std::invalid_argument);
  EXPECT_THROW(EncodePng(cv::Mat()), std::invalid_argument);
}

TEST(ImageCodec, DamagedAndForeignBytesAreRefusedWithAReason) {
  cv::Mat image(40, 30, CV_8UC1);
  cv::randu(image, 0, 256);
  const std::string png = EncodePng(image);
  std::string why;
  EXPECT_TRUE(DecodeImage(png.substr(0, png.size() / 2), ImageDecodeMode::kGray8, &why).empty());
  EXPECT_EQ(why.rfind("PNG: ", 0), 0u) << why;
  EXPECT_TRUE(DecodeImage("P5\n2 2\n255\n....", ImageDecodeMode::kGray8, &why).empty());
  EXPECT_NE(why.find("not a PNG or JPEG"), std::string::npos) << why;
  EXPECT_TRUE(DecodeImage("", ImageDecodeMode::kGray8, &why).empty());
  EXPECT_NE(why.find("empty"), std::string::npos) << why;
  const std::string jpeg_start("\xff\xd8\xff\xe0\x00\x10JFIF\x00", 11);
  EXPECT_TRUE(DecodeImage(jpeg_start, ImageDecodeMode::kGray8, &why).empty());
  EXPECT_EQ(why.rfind("JPEG: ", 0), 0u) << why;
}

}  // namespace
}  // namespace mavloc
