// StereoBM on a real rectified pair with ground truth: Middlebury 2006 "Aloe" (full size,
// 1282 x 1110) from OpenCV's samples, ../shared/data/stereo_aloe. aloeGT.png holds the left-view
// disparity in pixels (8-bit, 0 = unknown, mostly occlusions).
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <opencv2/imgproc.hpp>

#include "core/image_codec.h"
#include "frontends/image_io.h"
#include "frontends/stereo/disparity.h"
#include "tests/test_support.h"

namespace mavloc {
namespace {

struct BadPixelStats {
  long gt_valid = 0;        // pixels with known disparity
  long matched = 0;         // of those, pixels with a disparity from the matcher
  long bad1 = 0, bad3 = 0;  // matched pixels with |d - d_gt| > 1 px, > 3 px
  long band = 0;            // matched pixels within half a block of a discontinuity
  long bad3_band = 0;       // bad-3 pixels among them
  long bad1_band = 0;
  double density() const { return static_cast<double>(matched) / gt_valid; }
  double bad1_rate() const { return static_cast<double>(bad1) / matched; }
  double bad3_rate() const { return static_cast<double>(bad3) / matched; }
  double band_rate() const { return static_cast<double>(band) / matched; }
  double bad1_outside_band_rate() const {
    return static_cast<double>(bad1 - bad1_band) / (matched - band);
  }
  double bad3_outside_band_rate() const {
    return static_cast<double>(bad3 - bad3_band) / (matched - band);
  }
};

// The discontinuity band: pixels within `radius` of a disparity jump (> 2 px between neighbours)
// or of an unknown (occluded) pixel. A block matcher compares whole blocks, so there it mixes two
// surfaces (foreground fattening) or has no true match at all.
cv::Mat DiscontinuityBand(const cv::Mat& gt, int radius) {
  cv::Mat dilated, eroded;
  const cv::Mat kernel3 = cv::getStructuringElement(cv::MORPH_RECT, {3, 3});
  cv::dilate(gt, dilated, kernel3);
  cv::erode(gt, eroded, kernel3);
  cv::Mat jumps = (dilated - eroded) > 2;
  jumps |= (gt == 0);
  cv::Mat band;
  cv::dilate(jumps, band,
             cv::getStructuringElement(cv::MORPH_RECT, {2 * radius + 1, 2 * radius + 1}));
  return band;
}

BadPixelStats Evaluate(const cv::Mat& disparity_px, const cv::Mat& gt, int block_size) {
  const cv::Mat band = DiscontinuityBand(gt, block_size / 2);
  BadPixelStats s;
  for (int v = 0; v < gt.rows; ++v) {
    for (int u = 0; u < gt.cols; ++u) {
      const int d_gt = gt.at<uint8_t>(v, u);
      if (d_gt == 0) continue;
      ++s.gt_valid;
      const float d = disparity_px.at<float>(v, u);
      if (d < 0.0f) continue;
      ++s.matched;
      const double error = std::abs(d - d_gt);
      const bool in_band = band.at<uint8_t>(v, u) != 0;
      s.bad1 += error > 1.0;
      s.bad3 += error > 3.0;
      s.band += in_band;
      s.bad3_band += in_band && error > 3.0;
      s.bad1_band += in_band && error > 1.0;
    }
  }
  return s;
}

class StereoAloeTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = testing::SharedDataDir() + "/stereo_aloe";
    if (!std::filesystem::exists(dir_ + "/aloeGT.png")) {
      GTEST_SKIP() << "shared data not found: " << dir_ << " (../shared/data is absent)";
    }
    left_ = LoadGrayImage(dir_ + "/aloeL.jpg");
    right_ = LoadGrayImage(dir_ + "/aloeR.jpg");
    std::string why;
    gt_ = DecodeImage(testing::ReadFileBytes(dir_ + "/aloeGT.png"), ImageDecodeMode::kUnchanged,
                      &why);
    ASSERT_FALSE(left_.empty());
    ASSERT_FALSE(right_.empty());
    ASSERT_EQ(gt_.type(), CV_8UC1);
  }
  std::string dir_;
  cv::Mat left_, right_, gt_;
};

// The settings reported in docs/commands/obstacles.md: DisparityOptions defaults (StereoBM, 15 x 15
// SAD block, x-Sobel prefilter capped at 31, texture threshold 10, uniqueness ratio 15 %, speckle
// window 100 px / range 2 px, left-right check 1 px) with the search range widened to 224 px
// because Aloe's disparities reach 211 px.
DisparityOptions AloeOptions(StereoMatcherType matcher) {
  DisparityOptions options;
  options.matcher = matcher;
  options.num_disparities = 224;
  if (matcher == StereoMatcherType::kSemiGlobal) options.block_size_px = 11;
  return options;
}

void Print(const char* name, const BadPixelStats& s) {
  std::printf(
      "%s: GT-valid %ld px, matched %.1f %%; over matched GT-valid pixels: bad-1 %.2f %%, "
      "bad-3 %.2f %% (counting unmatched as bad: bad-1 %.1f %%, bad-3 %.1f %%); "
      "discontinuity band %.1f %% of matched, bad-3 outside it %.3f %%, bad-1 outside it %.2f %%\n",
      name, s.gt_valid, 100 * s.density(), 100 * s.bad1_rate(), 100 * s.bad3_rate(),
      100.0 * (s.gt_valid - s.matched + s.bad1) / s.gt_valid,
      100.0 * (s.gt_valid - s.matched + s.bad3) / s.gt_valid, 100 * s.band_rate(),
      100 * s.bad3_outside_band_rate(), 100 * s.bad1_outside_band_rate());
}

TEST_F(StereoAloeTest, GroundTruthCoversTheSearchRange) {
  double max_gt = 0.0;
  cv::minMaxLoc(gt_, nullptr, &max_gt);
  EXPECT_LT(max_gt, AloeOptions(StereoMatcherType::kBlockMatching).num_disparities);
}

// Bounds from how StereoBM works, not from its output on this pair:
// - A SAD block matcher assumes one disparity over the block, which fails only within half a
//   block of a depth discontinuity (foreground fattening) and where the right view has no match
//   (occlusion). The texture, uniqueness (15 %) and left-right checks reject ambiguous winners, so
//   gross errors (> 3 px) are rare elsewhere: at most 1 % outside the band, and overall no more
//   than the band's share of matched pixels.
// - Off the band the residual error is sub-pixel: the ground truth is rounded to whole pixels
//   (<= 0.5 px) and BM's parabolic refinement of SAD costs is biased towards integers by up to
//   about a quarter pixel, so an error above 1 px needs a gross mismatch or a surface slanted
//   within the block: at most 5 % of matched pixels outside the band.
// - BM leaves the first num_disparities columns unmatched (the search would leave the right
//   image), so the density cannot exceed (width - 224) / width; Aloe is textured (leaves, cloth)
//   and the texture filter removes only flat regions, so at least half of the known pixels match.
TEST_F(StereoAloeTest, BlockMatchingBadPixelRates) {
  const DisparityOptions options = AloeOptions(StereoMatcherType::kBlockMatching);
  ASSERT_EQ(ValidateDisparityOptions(options), "");
  DisparityMatcher matcher(options);
  const cv::Mat disparity_px = matcher.Compute(left_, right_);
  ASSERT_EQ(disparity_px.size(), gt_.size());
  const BadPixelStats s = Evaluate(disparity_px, gt_, options.block_size_px);
  Print("StereoBM", s);
  EXPECT_GT(s.density(), 0.5);
  EXPECT_LT(s.density(), static_cast<double>(gt_.cols - options.num_disparities) / gt_.cols);
  EXPECT_LE(s.bad3_rate(), s.band_rate());
  EXPECT_LE(s.bad3_outside_band_rate(), 0.01);
  EXPECT_LE(s.bad1_outside_band_rate(), 0.05);
  EXPECT_LE(s.bad3_rate(), s.bad1_rate());
}

// SGBM's smoothness term propagates disparities into weakly textured regions that BM's texture
// threshold leaves empty, so it matches more pixels; its gross errors stay within the band too.
TEST_F(StereoAloeTest, SemiGlobalMatchingIsDenser) {
  DisparityMatcher bm(AloeOptions(StereoMatcherType::kBlockMatching));
  const DisparityOptions options = AloeOptions(StereoMatcherType::kSemiGlobal);
  ASSERT_EQ(ValidateDisparityOptions(options), "");
  DisparityMatcher sgbm(options);
  const BadPixelStats s_bm = Evaluate(bm.Compute(left_, right_), gt_, 15);
  const BadPixelStats s_sgbm = Evaluate(sgbm.Compute(left_, right_), gt_, options.block_size_px);
  Print("StereoSGBM", s_sgbm);
  EXPECT_GT(s_sgbm.density(), s_bm.density());
  EXPECT_LE(s_sgbm.bad3_rate(), s_sgbm.band_rate());
}

TEST(DisparityOptionsTest, RejectsUnusableSettings) {
  DisparityOptions options;
  EXPECT_EQ(ValidateDisparityOptions(options), "");
  options.num_disparities = 60;
  EXPECT_NE(ValidateDisparityOptions(options), "");
  options = DisparityOptions();
  options.block_size_px = 4;
  EXPECT_NE(ValidateDisparityOptions(options), "");
  options.block_size_px = 3;  // odd, but below StereoBM's minimum
  EXPECT_NE(ValidateDisparityOptions(options), "");
  options.matcher = StereoMatcherType::kSemiGlobal;  // SGBM accepts small blocks
  EXPECT_EQ(ValidateDisparityOptions(options), "");
  options.min_disparity_px = -4;
  EXPECT_NE(ValidateDisparityOptions(options), "");
}

// A synthetic pair with a known shift: every matched pixel of a textured, constant-disparity
// image must have that disparity (sub-pixel), and a flat image must give no match at all.
TEST(DisparityMatcherTest, ConstantShiftOfRandomTexture) {
  cv::Mat wide(240, 400, CV_8U);
  cv::RNG rng(7);
  rng.fill(wide, cv::RNG::UNIFORM, 0, 256);
  cv::GaussianBlur(wide, wide, {3, 3}, 0.8);
  const int shift_px = 23;
  const cv::Mat left = wide(cv::Rect(0, 0, 320, 240)).clone();
  const cv::Mat right = wide(cv::Rect(shift_px, 0, 320, 240)).clone();
  DisparityMatcher matcher{DisparityOptions()};
  const cv::Mat disparity_px = matcher.Compute(left, right);
  int matched = 0, correct = 0;
  for (int v = 0; v < disparity_px.rows; ++v) {
    for (int u = 0; u < disparity_px.cols; ++u) {
      const float d = disparity_px.at<float>(v, u);
      if (d == kNoDisparity) continue;
      ++matched;
      correct += std::abs(d - shift_px) < 0.25f;
    }
  }
  EXPECT_GT(matched, 320 * 240 / 2);
  EXPECT_EQ(correct, matched);

  const cv::Mat flat(240, 320, CV_8U, cv::Scalar(128));
  const cv::Mat flat_disparity = matcher.Compute(flat, flat);
  EXPECT_EQ(cv::countNonZero(flat_disparity != kNoDisparity), 0);
}

}  // namespace
}  // namespace mavloc
