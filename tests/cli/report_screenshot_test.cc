// What a reader of report.html sees: `mavloc compare` writes a short simulated comparison with its
// figures, headless Chromium (Debian's chromium, when installed; skipped otherwise) renders the
// page into a PNG screenshot, and the screenshot must decode and show the figures: not a blank
// page (pixel standard deviation above a floor) and the estimators' colors present (the text,
// tables and axes of the page are black, white and gray). Every program runs with an argument
// vector (core/subprocess.h): no shell sees the paths.
#include <gtest/gtest.h>
#include <stdlib.h>

#include <algorithm>
#include <filesystem>
#include <map>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <string>
#include <vector>

#include "core/image_codec.h"
#include "core/subprocess.h"
#include "tests/test_support.h"

namespace fs = std::filesystem;

namespace mavloc {
namespace {

using testing::CliPath;
using testing::MakeTempDir;

constexpr const char* kChromium = "/usr/bin/chromium";
constexpr int kWidth = 1280, kHeight = 4000;

bool HasMatplotlib() {
  static const bool has =
      RunProgram({"/usr/bin/python3", "-c", "import matplotlib, numpy"}).exit_code == 0;
  return has;
}

// Pixels whose channels differ by more than 60 (a colored line, box or colormap, not text, grid or
// background), counted per color bin of 32 levels per channel.
std::map<int, int> ColoredBins(const cv::Mat& bgr, int* colored) {
  std::map<int, int> bins;
  *colored = 0;
  for (int r = 0; r < bgr.rows; ++r) {
    for (int c = 0; c < bgr.cols; ++c) {
      const cv::Vec3b& p = bgr.at<cv::Vec3b>(r, c);
      if (std::max({p[0], p[1], p[2]}) - std::min({p[0], p[1], p[2]}) <= 60) continue;
      ++*colored;
      ++bins[(p[0] / 32) * 64 + (p[1] / 32) * 8 + p[2] / 32];
    }
  }
  return bins;
}

TEST(ReportScreenshot, ChromiumRendersTheCompareReportWithItsFigures) {
  if (!fs::exists(kChromium))
    GTEST_SKIP() << kChromium << " not installed (Debian: apt-get install chromium); the report "
                 << "page is not rendered";
  if (!HasMatplotlib())
    GTEST_SKIP() << "/usr/bin/python3 cannot import matplotlib: install python3-matplotlib "
                    "(scripts/setup)";
  ::setenv("MAVLOC_QUIET", "1", 1);
  testing::FiguresOn();
  const std::string work = MakeTempDir();
  const std::string report = work + "/report";

  // Two fast estimators with poses (the trajectory figures) and one attitude-only estimator.
  const ProgramRun compare =
      RunProgram({CliPath(), "compare", "--duration", "6", "--seed", "3", "--estimators",
                  "imu-dead-reckoning,gravity-ekf", "--report", report},
                 {.merge_stderr = true});
  ASSERT_TRUE(compare.started) << compare.error;
  ASSERT_EQ(compare.exit_code, 0) << compare.out;
  ASSERT_TRUE(fs::exists(report + "/report.html")) << compare.out;
  for (const char* figure : {"errors_over_time.png", "trajectory.png"})
    ASSERT_TRUE(fs::exists(report + "/" + figure)) << figure << " not drawn: " << compare.out;

  // The proxy points at a closed port: the page must not need the network. The report's tables
  // take about the first 900 px of the page, the figures follow.
  const std::string screenshot = work + "/screenshot.png";
  const ProgramRun chromium =
      RunProgram({kChromium, "--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars",
                  "--no-first-run", "--disable-extensions", "--proxy-server=127.0.0.1:9",
                  "--user-data-dir=" + work + "/profile",
                  "--window-size=" + std::to_string(kWidth) + "," + std::to_string(kHeight),
                  "--virtual-time-budget=10000", "--screenshot=" + screenshot,
                  "file://" + report + "/report.html"},
                 {.merge_stderr = true});
  ASSERT_TRUE(chromium.started) << chromium.error;
  ASSERT_EQ(chromium.exit_code, 0) << chromium.out;
  ASSERT_TRUE(fs::exists(screenshot)) << chromium.out;

  std::string why;
  cv::Mat image =
      DecodeImage(testing::ReadFileBytes(screenshot), ImageDecodeMode::kUnchanged, &why);
  ASSERT_FALSE(image.empty()) << screenshot << " does not decode: " << why;
  if (image.channels() == 4) cv::cvtColor(image, image, cv::COLOR_BGRA2BGR);
  EXPECT_EQ(image.cols, kWidth);
  EXPECT_EQ(image.rows, kHeight);

  // Not blank: a white page has standard deviation 0 (this page: about 34; without its figures,
  // text and tables alone, about 24).
  cv::Mat gray;
  cv::cvtColor(image, gray, cv::COLOR_BGR2GRAY);
  cv::Scalar mean, stddev;
  cv::meanStdDev(gray, mean, stddev);
  EXPECT_GT(stddev[0], 15.0) << "the page looks blank (mean gray " << mean[0] << ")";

  // The figures rendered: many colored pixels in several distinct colors (each estimator's color,
  // the error colormap), not only links and a note box. Measured: about 32000 colored pixels in
  // 14 bins of at least 500 with the figures, 3700 in 2 such bins without them.
  int colored = 0;
  const std::map<int, int> bins = ColoredBins(image, &colored);
  int distinct = 0;
  for (const auto& [bin, count] : bins) distinct += count >= 500 ? 1 : 0;
  EXPECT_GT(colored, 15000) << "few colored pixels: the figures did not render";
  EXPECT_GE(distinct, 5) << "colored pixels in " << bins.size() << " bins, " << distinct
                         << " with at least 500 pixels: the figures' colors are missing";
}

}  // namespace
}  // namespace mavloc
