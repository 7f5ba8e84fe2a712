// Report folders get their figures and one self-contained report.html without a second command:
// `mavloc compare` and `mavloc repro` draw them; without Python the report is still written, the
// exit code is unchanged and the output says how to get the figures (`mavloc figures DIR` then
// draws them); headless Chromium (Debian's chromium, when installed) loads the page with the
// network cut off and decodes every image.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include "tests/test_support.h"

namespace fs = std::filesystem;

namespace mavloc {
namespace {

using testing::CliPath;
using testing::MakeTempDir;
using testing::RunCommand;

constexpr const char* kChromium = "/usr/bin/chromium";

std::string Cli(const std::string& args) { return CliPath() + " " + args; }

std::string ReadAll(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

bool HasMatplotlib() {
  static const bool has =
      std::system("/usr/bin/python3 -c 'import matplotlib, numpy' >/dev/null 2>&1") == 0;
  return has;
}

size_t Count(const std::string& text, const std::string& what) {
  size_t n = 0;
  for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

// One short comparison per process, shared by the tests (two fast estimators, one with poses).
class ReportHtml : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    testing::FiguresOn();
    dir_ = new std::string(fs::temp_directory_path() /
                           ("mavloc_report_html_" + std::to_string(::getpid())));
    fs::remove_all(*dir_);
    fs::create_directories(*dir_);
    compare_ = new testing::CommandResult(
        RunCommand(Cli("compare --duration 4 --seed 2 --estimators imu-dead-reckoning,gravity-ekf "
                       "--report " +
                       *dir_ + "/report")));
  }
  static void TearDownTestSuite() { fs::remove_all(*dir_); }
  void SetUp() override {
    ASSERT_EQ(compare_->exit_code, 0) << compare_->output;
    if (!HasMatplotlib())
      GTEST_SKIP() << "/usr/bin/python3 cannot import matplotlib: install python3-matplotlib "
                      "(scripts/setup)";
  }
  static std::string* dir_;
  static testing::CommandResult* compare_;
};
std::string* ReportHtml::dir_ = nullptr;
testing::CommandResult* ReportHtml::compare_ = nullptr;

TEST_F(ReportHtml, CompareWritesFiguresTrajectoriesAndThePage) {
  const std::string report = *dir_ + "/report";
  EXPECT_NE(compare_->output.find(
                "figures: errors_over_time.png, error_boxplots.png, trajectory.png, "
                "trajectory_ape.png, ape_over_time.png, trajectory_xyz_rpy.png; all in " +
                report + "/report.html"),
            std::string::npos)
      << compare_->output;
  for (const char* file : {"errors_over_time.png", "error_boxplots.png", "trajectory.png",
                           "truth.tum", "estimate_imu-dead-reckoning.tum", "report.html"})
    EXPECT_TRUE(fs::exists(report + "/" + file)) << file;
  // gravity-ekf gives roll and pitch only: no trajectory file for it.
  EXPECT_FALSE(fs::exists(report + "/estimate_gravity-ekf.tum"));
  const std::string html = ReadAll(report + "/report.html");
  EXPECT_EQ(Count(html, "src=\"data:image/png;base64,"), 6u);
  EXPECT_NE(html.find("<th style=\"text-align:right\">ATE RMSE [m]</th>"), std::string::npos);
  EXPECT_NE(ReadAll(report + "/report.md").find("[report.html](report.html)"), std::string::npos);
}

// A sweep draws the ATE boxplots over the seeds; an obstacles report the distances and stage
// times per frame; each page inlines its figure.
TEST_F(ReportHtml, SweepAndObstaclesDrawTheirFigures) {
  const std::string sweep = *dir_ + "/sweep";
  const auto s =
      RunCommand(Cli("sweep --scenario tag-arena-hover --duration 2 --seeds 1..3 "
                     "--estimators tag-pnp --jobs 1 --out " +
                     sweep));
  ASSERT_EQ(s.exit_code, 0) << s.output;
  EXPECT_TRUE(fs::exists(sweep + "/sweep_ate_boxplots.png")) << s.output;
  EXPECT_EQ(Count(ReadAll(sweep + "/report.html"), "src=\"data:image/png;base64,"), 1u);

  const std::string data = *dir_ + "/stereo";
  const auto simulate =
      RunCommand(Cli("simulate --scenario stereo-obstacles --render --duration 5 --out " + data));
  ASSERT_EQ(simulate.exit_code, 0) << simulate.output;
  const std::string obstacles = *dir_ + "/obstacles";
  const auto o = RunCommand(Cli("obstacles --dataset " + data + " --report " + obstacles));
  ASSERT_EQ(o.exit_code, 0) << o.output;
  EXPECT_TRUE(fs::exists(obstacles + "/obstacles_over_time.png")) << o.output;
  EXPECT_EQ(Count(ReadAll(obstacles + "/report.html"), "src=\"data:image/png;base64,"), 1u);
}

TEST_F(ReportHtml, WithoutPythonTheExitCodeIsUnchangedAndTheOutputSaysHow) {
  const std::string report = *dir_ + "/no_python";
  const auto r =
      RunCommand("MAVLOC_PYTHON=/nonexistent " +
                 Cli("compare --duration 3 --estimators imu-dead-reckoning --report " + report));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("no figures: no Python interpreter at /nonexistent"), std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("sudo apt-get install python3-matplotlib"), std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("mavloc figures " + report), std::string::npos) << r.output;
  for (const char* file : {"report.md", "report.json", "errors.csv", "report.html"})
    EXPECT_TRUE(fs::exists(report + "/" + file)) << file;
  EXPECT_FALSE(fs::exists(report + "/errors_over_time.png"));
  EXPECT_EQ(ReadAll(report + "/report.html").find("<img"), std::string::npos);

  // The command the message names draws them afterwards.
  const auto figures = RunCommand(Cli("figures " + report));
  ASSERT_EQ(figures.exit_code, 0) << figures.output;
  EXPECT_TRUE(fs::exists(report + "/errors_over_time.png"));
  const std::string html = ReadAll(report + "/report.html");
  EXPECT_EQ(Count(html, "src=\"data:image/png;base64,"), 6u);
  EXPECT_EQ(html.find("figures-note"), std::string::npos);
  EXPECT_EQ(Count(ReadAll(report + "/report.md"), "## Figures"), 1u);
}

TEST_F(ReportHtml, FiguresOnAFolderWithoutReportIsAnInputError) {
  const std::string empty = MakeTempDir();
  const auto r = RunCommand(Cli("figures " + empty));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("no mavloc report here"), std::string::npos) << r.output;
  EXPECT_EQ(RunCommand(Cli("figures " + empty + "/missing")).exit_code, 2);
}

TEST_F(ReportHtml, ReproWritesFiguresOfItsRuns) {
  const std::string report = *dir_ + "/repro";
  const auto r = RunCommand(Cli("repro laser --runs 3 --report " + report));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("figures: runs.png"), std::string::npos) << r.output;
  EXPECT_TRUE(fs::exists(report + "/runs.png"));
  EXPECT_GE(Count(ReadAll(report + "/report.html"), "src=\"data:image/png;base64,"), 1u);
}

// Headless Chromium opens a copy of report.html with a check script appended (the page itself has
// no script): after the load event it writes how many images there are and how many decoded
// (naturalWidth > 0) into the DOM, which --dump-dom prints. The proxy points at a closed port, so
// any network fetch would fail: the page must not need one.
TEST_F(ReportHtml, ChromiumLoadsThePageAndDecodesEveryImage) {
  if (!fs::exists(kChromium))
    GTEST_SKIP() << kChromium << " not installed (Debian: apt-get install chromium); the page "
                 << "is not checked in a browser";
  const std::string work = MakeTempDir();
  std::string html = ReadAll(*dir_ + "/report/report.html");
  ASSERT_FALSE(html.empty());
  const std::string check =
      "<script>window.addEventListener('load', () => {"
      "const images = Array.from(document.images);"
      "const decoded = images.filter(i => i.complete && i.naturalWidth > 0).length;"
      "const out = document.createElement('pre'); out.id = 'mavloc-check';"
      "out.textContent = 'images=' + images.length + ' decoded=' + decoded + ' tables=' + "
      "document.querySelectorAll('table').length;"
      "document.body.appendChild(out);});</script>\n";
  html.insert(html.rfind("</body>"), check);
  {
    std::ofstream out(work + "/check.html", std::ios::binary);
    out << html;
  }
  const auto r = RunCommand(std::string(kChromium) +
                            " --headless --no-sandbox --disable-gpu --no-first-run "
                            "--disable-extensions --proxy-server=127.0.0.1:9 --user-data-dir=" +
                            work + "/profile --virtual-time-budget=10000 --dump-dom file://" +
                            work + "/check.html");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto at = r.output.find("id=\"mavloc-check\"");
  ASSERT_NE(at, std::string::npos) << "the load handler did not run: " << r.output.substr(0, 2000);
  const std::string result = r.output.substr(at, 200);
  std::smatch m;
  ASSERT_TRUE(
      std::regex_search(result, m, std::regex(R"(images=(\d+) decoded=(\d+) tables=(\d+))")))
      << result;
  EXPECT_EQ(m[1].str(), "6");
  EXPECT_EQ(m[2].str(), "6") << "every image decodes";
  EXPECT_GE(std::stoi(m[3].str()), 1) << "the report's table is in the page";
}

}  // namespace
}  // namespace mavloc
