// Figures and report.html of report folders: sample eval, compare and repro
// folders written here get their PNG figures and one self-contained report.html; without Python or
// without matplotlib the page and the Markdown report are still written and say how to get them.
#include "evaluation/report_figures.h"

#include <gtest/gtest.h>
#include <stdlib.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <algorithm>
#include <opencv2/imgproc.hpp>

#include <sys/stat.h>

#include "core/image_codec.h"
#include "core/subprocess.h"
#include "evaluation/report_html.h"
#include "tests/test_support.h"

namespace fs = std::filesystem;

namespace mavloc {
namespace {

using testing::MakeTempDir;

std::string ReadAll(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

void Write(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
}

size_t Count(const std::string& text, const std::string& what) {
  size_t n = 0;
  for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

// Whether /usr/bin/python3 can import matplotlib (scripts/setup installs python3-matplotlib).
bool HasMatplotlib() {
  static const bool has =
      std::system("/usr/bin/python3 -c 'import matplotlib, numpy' >/dev/null 2>&1") == 0;
  return has;
}
#define SKIP_WITHOUT_MATPLOTLIB()                                                          \
  if (!HasMatplotlib())                                                                    \
  GTEST_SKIP() << "/usr/bin/python3 cannot import matplotlib: install python3-matplotlib " \
                  "(scripts/setup) to run the figure tests"

// This suite checks figures: they are drawn (tests/test_support.h).
class FiguresOnEnvironment : public ::testing::Environment {
 public:
  void SetUp() override { testing::FiguresOn(); }
};
const auto* const kFiguresOn = ::testing::AddGlobalTestEnvironment(new FiguresOnEnvironment);

// Sets an environment variable for one scope (the tests of one file run in one process, serially).
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const std::string& value) : name_(name) {
    if (const char* old = std::getenv(name)) old_ = old;
    ::setenv(name, value.c_str(), 1);
  }
  ~ScopedEnv() {
    if (old_.empty())
      ::unsetenv(name_);
    else
      ::setenv(name_, old_.c_str(), 1);
  }

 private:
  const char* name_;
  std::string old_;
};

// A figure file: a PNG (signature, RFC 2083 section 12.12) that decodes to a plot with data drawn
// on it: axes, text and grid are black, white or gray, the data colored (matplotlib's tab10 cycle),
// so an empty canvas or empty axes have no colored pixels.
void ExpectPng(const std::string& path) {
  const std::string bytes = ReadAll(path);
  ASSERT_GT(bytes.size(), 8u) << path;
  EXPECT_EQ(bytes.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8)) << path;
  std::string why;
  cv::Mat image = DecodeImage(bytes, ImageDecodeMode::kUnchanged, &why);
  ASSERT_FALSE(image.empty()) << path << ": does not decode: " << why;
  ASSERT_EQ(image.depth(), CV_8U) << path;
  if (image.channels() == 4) cv::cvtColor(image, image, cv::COLOR_BGRA2BGR);
  if (image.channels() == 1) cv::cvtColor(image, image, cv::COLOR_GRAY2BGR);
  EXPECT_GE(image.cols, 400) << path;
  EXPECT_GE(image.rows, 300) << path;
  int colored = 0;
  for (int r = 0; r < image.rows; ++r) {
    for (int c = 0; c < image.cols; ++c) {
      const cv::Vec3b& p = image.at<cv::Vec3b>(r, c);
      const int spread = std::max({p[0], p[1], p[2]}) - std::min({p[0], p[1], p[2]});
      colored += spread > 60 ? 1 : 0;
    }
  }
  EXPECT_GT(colored, 1000) << path << ": no data drawn";
}

// A figure-eight trajectory (TUM lines), with an offset and a per-run wobble for the estimates.
std::string TumText(double offset_m, int run) {
  std::string text = "# timestamp tx ty tz qx qy qz qw\n";
  for (int i = 0; i <= 200; ++i) {
    const double t = 100.0 + 0.1 * i;
    const double s = 0.1 * i;
    const double x = 2.0 * std::sin(0.3 * s) + offset_m * (1 + 0.3 * run) * std::sin(s);
    const double y = 1.0 * std::sin(0.6 * s) + offset_m;
    const double z = 1.0 + 0.1 * std::sin(0.2 * s) - 0.5 * offset_m;
    char line[160];
    std::snprintf(line, sizeof line, "%.3f %.6f %.6f %.6f 0 0 %.6f %.6f\n", t, x, y, z,
                  std::sin(0.05 * s), std::cos(0.05 * s));
    text += line;
  }
  return text;
}

// The eval folder contract (`mavloc eval --out DIR`): one estimate "vio" and three runs of "lio".
std::string SampleEvalFolder() {
  const std::string dir = MakeTempDir() + "/eval";
  fs::create_directories(dir);
  Write(dir + "/truth.tum", TumText(0.0, 0));
  Write(dir + "/estimate_vio.tum", TumText(0.05, 0));
  for (int k = 0; k < 3; ++k)
    Write(dir + "/estimate_lio_run" + std::to_string(k) + ".tum", TumText(0.12, k));
  std::string errors = "label,run,t_s,translation_error_m,rotation_error_deg\n";
  std::string relative = "label,run,length_m,translation_error_pct,rotation_error_deg_per_m\n";
  for (int i = 0; i <= 200; ++i) {
    const double t = 100.0 + 0.1 * i;
    char line[160];
    std::snprintf(line, sizeof line, "vio,0,%.3f,%.5f,%.5f\n", t, 0.05 + 0.002 * i,
                  0.3 + 0.01 * std::sin(0.1 * i));
    errors += line;
    for (int k = 0; k < 3; ++k) {
      std::snprintf(line, sizeof line, "lio,%d,%.3f,%.5f,%.5f\n", k, t, 0.1 + 0.001 * i * (1 + k),
                    0.5 + 0.1 * k);
      errors += line;
    }
  }
  for (const double length : {2.0, 4.0, 6.0}) {
    for (int j = 0; j < 12; ++j) {
      char line[160];
      std::snprintf(line, sizeof line, "vio,0,%.1f,%.4f,%.5f\n", length, 1.0 + 0.1 * j,
                    0.01 * (1 + j % 4));
      relative += line;
      for (int k = 0; k < 3; ++k) {
        std::snprintf(line, sizeof line, "lio,%d,%.1f,%.4f,%.5f\n", k, length,
                      2.0 + 0.2 * j + 0.1 * k, 0.02 * (1 + j % 3));
        relative += line;
      }
    }
  }
  Write(dir + "/errors_over_time.csv", errors);
  Write(dir + "/relative_errors.csv", relative);
  Write(dir + "/eval.json", "{\"report_kind\": \"eval\"}\n");
  Write(dir + "/report.md",
        "# mavloc eval: sample\n\n| estimate | ATE rmse [m] |\n| --- | ---: |\n| vio | 0.0500 |\n"
        "| lio | 0.1200 |\n");
  return dir;
}

// The compare folder (`mavloc compare`): errors.csv, report.md, report.json and trajectories.
std::string SampleCompareFolder() {
  const std::string dir = MakeTempDir() + "/compare";
  fs::create_directories(dir);
  std::string csv = "estimator,quantity,unit,t_s,estimate,truth,error\n";
  for (const char* estimator : {"imu-dead-reckoning", "smoother"}) {
    for (const char* quantity : {"x", "yaw"}) {
      for (int i = 0; i < 150; ++i) {
        const double e = (estimator[0] == 'i' ? 0.01 : 0.001) * std::sin(0.1 * i) * (1 + i / 50.0);
        char line[200];
        std::snprintf(line, sizeof line, "%s,%s,%s,%.3f,%.6f,0,%.6f\n", estimator, quantity,
                      quantity[0] == 'x' ? "m" : "deg", 1000.0 + 0.02 * i, e, e);
        csv += line;
      }
    }
  }
  Write(dir + "/errors.csv", csv);
  Write(dir + "/report.json", "{\"report_kind\": \"compare\", \"estimators\": {}}\n");
  Write(
      dir + "/report.md",
      "# mavloc compare: sample\n\n| estimator | x [m] |\n| --- | ---: |\n| smoother | 0.001 |\n");
  Write(dir + "/truth.tum", TumText(0.0, 0));
  Write(dir + "/estimate_smoother.tum", TumText(0.02, 0));
  return dir;
}

// A repro folder: report.json tables (a statistic with the paper's value; per-run values) and a
// CSV with one row per seed.
std::string SampleReproFolder() {
  const std::string dir = MakeTempDir() + "/repro";
  fs::create_directories(dir);
  Write(dir + "/report.json", R"({"report_kind": "repro", "paper": "sample", "tables": {
    "table1": {"estimators": {
      "three-point": {"quantities": {"roll": {"mean_abs": 0.5, "paper": 0.4, "unit": "deg"},
                                     "x": {"mean_abs": 2.0, "paper": 2.5, "unit": "%"}}},
      "two-point": {"quantities": {"roll": {"mean_abs": 0.7, "unit": "deg"},
                                   "x": {"mean_abs": 3.0, "unit": "%"}}}}},
    "scenario_a": {"estimators": {
      "smoother": {"quantity_rmse": {"yaw": {"rmse": 0.2, "per_run_rmse": [0.1, 0.2, 0.3, 0.25],
                                             "unit": "deg"}}},
      "filter": {"quantity_rmse": {"yaw": {"rmse": 0.4, "per_run_rmse": [0.3, 0.5, 0.4, 0.45],
                                           "unit": "deg"}}}}}}})");
  std::string runs = "table,seed,quantity,unit,final_error,mae_all\n";
  for (int seed = 1; seed <= 10; ++seed) {
    runs += "\"simulated, no bias\"," + std::to_string(seed) + ",roll,deg," +
            std::to_string(0.1 * seed) + "," + std::to_string(0.05 * seed) + "\n";
    runs += "\"simulated, bias\"," + std::to_string(seed) + ",roll,deg," +
            std::to_string(0.2 * seed) + "," + std::to_string(0.08 * seed) + "\n";
  }
  Write(dir + "/runs.csv", runs);
  Write(dir + "/report.md", "# mavloc repro sample\n\n| a | b |\n| --- | ---: |\n| x | 1 |\n");
  return dir;
}

TEST(ReportFigures, DetectsTheKindOfFolder) {
  EXPECT_EQ(DetectReportKind(SampleEvalFolder()), ReportKind::kEval);
  EXPECT_EQ(DetectReportKind(SampleCompareFolder()), ReportKind::kCompare);
  EXPECT_EQ(DetectReportKind(SampleReproFolder()), ReportKind::kRepro);
  EXPECT_EQ(DetectReportKind(MakeTempDir()), ReportKind::kUnknown);
}

TEST(ReportFigures, EvalFolderGetsTrajectoryErrorAndRelativeErrorFigures) {
  SKIP_WITHOUT_MATPLOTLIB();
  const std::string dir = SampleEvalFolder();
  const FigureOutcome outcome = WriteReportFigures(dir);
  EXPECT_TRUE(outcome.ok()) << outcome.reason;
  EXPECT_EQ(outcome.kind, ReportKind::kEval);
  ASSERT_EQ(outcome.figures,
            (std::vector<std::string>{"trajectory.png", "trajectory_ape.png",
                                      "trajectory_xyz_rpy.png", "errors_over_time.png",
                                      "ape_over_time.png", "relative_errors.png"}));
  for (const auto& figure : outcome.figures) ExpectPng(dir + "/" + figure);
  const std::string html = ReadAll(dir + "/report.html");
  EXPECT_EQ(outcome.html_path, dir + "/report.html");
  EXPECT_EQ(Count(html, "src=\"data:image/png;base64,"), 6u);
  EXPECT_NE(html.find("<td style=\"text-align:right\">0.0500</td>"), std::string::npos);
  EXPECT_NE(html.find("Monte-Carlo"), std::string::npos) << "the runs of lio have an envelope";
  // Self-contained: nothing is fetched (no http(s) resource, no external src).
  EXPECT_EQ(html.find("src=\"http"), std::string::npos);
  EXPECT_EQ(html.find("<link"), std::string::npos);
  // The Markdown report points at the figures.
  const std::string md = ReadAll(dir + "/report.md");
  EXPECT_EQ(Count(md, "## Figures"), 1u) << md;
  EXPECT_NE(md.find("![trajectory.png](trajectory.png)"), std::string::npos) << md;
}

TEST(ReportFigures, CompareFolderGetsErrorsBoxplotsAndTrajectories) {
  SKIP_WITHOUT_MATPLOTLIB();
  const std::string dir = SampleCompareFolder();
  const FigureOutcome outcome = WriteReportFigures(dir);
  EXPECT_TRUE(outcome.ok()) << outcome.reason;
  ASSERT_EQ(outcome.figures,
            (std::vector<std::string>{"errors_over_time.png", "error_boxplots.png",
                                      "trajectory.png", "trajectory_ape.png", "ape_over_time.png",
                                      "trajectory_xyz_rpy.png"}));
  for (const auto& figure : outcome.figures) ExpectPng(dir + "/" + figure);
  const std::string html = ReadAll(dir + "/report.html");
  EXPECT_EQ(Count(html, "src=\"data:image/png;base64,"), 6u);
  EXPECT_NE(html.find("<h1>mavloc compare: sample</h1>"), std::string::npos);
  EXPECT_NE(html.find("<a href=\"errors.csv\">errors.csv</a>"), std::string::npos);
}

TEST(ReportFigures, ReproFolderGetsTableAndRunFigures) {
  SKIP_WITHOUT_MATPLOTLIB();
  const std::string dir = SampleReproFolder();
  const FigureOutcome outcome = WriteReportFigures(dir);
  EXPECT_TRUE(outcome.ok()) << outcome.reason;
  ASSERT_EQ(outcome.figures, (std::vector<std::string>{"runs.png", "table_01_table1.png",
                                                       "table_02_scenario_a.png"}));
  for (const auto& figure : outcome.figures) ExpectPng(dir + "/" + figure);
  const std::string html = ReadAll(dir + "/report.html");
  EXPECT_NE(html.find("the paper&#39;s value"), std::string::npos) << "diamond marker caption";
  EXPECT_NE(html.find("boxplots over the Monte-Carlo runs"), std::string::npos);
}

TEST(ReportFigures, WithoutPythonTheReportIsWrittenAndSaysHowToGetFigures) {
  const std::string dir = SampleCompareFolder();
  const ScopedEnv env("MAVLOC_PYTHON", "/nonexistent/python3");
  const FigureOutcome outcome = WriteReportFigures(dir);
  EXPECT_TRUE(outcome.figures.empty());
  EXPECT_NE(outcome.reason.find("no Python interpreter at /nonexistent/python3"), std::string::npos)
      << outcome.reason;
  EXPECT_NE(outcome.how_to_get_figures.find("sudo apt-get install python3-matplotlib"),
            std::string::npos);
  EXPECT_NE(outcome.how_to_get_figures.find("mavloc figures " + dir), std::string::npos);
  const std::string html = ReadAll(dir + "/report.html");
  EXPECT_NE(html.find("<h1>mavloc compare: sample</h1>"), std::string::npos) << "tables kept";
  EXPECT_NE(html.find("id=\"figures-note\""), std::string::npos);
  EXPECT_NE(html.find("python3-matplotlib"), std::string::npos);
  EXPECT_EQ(html.find("<img"), std::string::npos);
  // The section is replaced, not appended again, when the figures are drawn once more.
  WriteReportFigures(dir);
  const std::string md = ReadAll(dir + "/report.md");
  EXPECT_NE(md.find("To get them: the figures need Python 3 with matplotlib"), std::string::npos)
      << md;
  EXPECT_EQ(Count(md, "## Figures"), 1u) << md;
  EXPECT_NE(md.find("| smoother | 0.001 |"), std::string::npos) << "the table is kept";
  EXPECT_NE(DescribeFigureOutcome(outcome).find("apt-get install python3-matplotlib"),
            std::string::npos);
}

TEST(ReportFigures, WithoutMatplotlibTheReportSaysWhichPackage) {
  // An interpreter whose "matplotlib" fails to import, as on a system without python3-matplotlib.
  const std::string dir = SampleEvalFolder();
  const std::string fake = dir + "/../fake_python";
  fs::create_directories(fake + "/site/matplotlib");
  Write(fake + "/site/matplotlib/__init__.py",
        "raise ImportError(\"No module named 'matplotlib' (test stand-in)\")\n");
  Write(fake + "/python3",
        "#!/bin/sh\nPYTHONPATH=" + fake + "/site exec /usr/bin/python3 \"$@\"\n");
  fs::permissions(fake + "/python3", fs::perms::owner_all);
  if (!fs::exists("/usr/bin/python3")) GTEST_SKIP() << "no /usr/bin/python3";
  const ScopedEnv env("MAVLOC_PYTHON", fake + "/python3");
  const FigureOutcome outcome = WriteReportFigures(dir);
  EXPECT_TRUE(outcome.figures.empty());
  EXPECT_NE(outcome.reason.find("matplotlib is not available"), std::string::npos)
      << outcome.reason;
  EXPECT_NE(outcome.reason.find("test stand-in"), std::string::npos) << outcome.reason;
  EXPECT_NE(outcome.how_to_get_figures.find("python3-matplotlib"), std::string::npos);
  EXPECT_TRUE(fs::exists(dir + "/report.html"));
  EXPECT_NE(ReadAll(dir + "/report.md").find("To get them"), std::string::npos);
}

TEST(ReportFigures, MissingFolderOrUnknownFolderDoesNotThrow) {
  const FigureOutcome missing = WriteReportFigures("/nonexistent/report");
  EXPECT_TRUE(missing.figures.empty());
  EXPECT_TRUE(missing.html_path.empty());
  EXPECT_NE(missing.reason.find("not a folder"), std::string::npos);
  const std::string empty = MakeTempDir();
  const FigureOutcome unknown = WriteReportFigures(empty);
  EXPECT_TRUE(unknown.figures.empty());
  EXPECT_NE(unknown.reason.find("no mavloc report"), std::string::npos);
}

// ---- The safe-write rule: figures and pages are renamed into place, never written through ----

// Names in `dir` that are temporaries of a write (".tmp-" in the name).
int Temporaries(const std::string& dir) {
  int count = 0;
  for (const auto& entry : fs::directory_iterator(dir))
    count += entry.path().filename().string().find(".tmp-") != std::string::npos;
  return count;
}

TEST(ReportFigures, PlantedLinksAreReplacedNotWrittenThrough) {
  SKIP_WITHOUT_MATPLOTLIB();
  const std::string dir = SampleCompareFolder();
  const std::string victim = dir + "/../victim.txt";
  Write(victim, "victim\n");
  for (const char* name : {"trajectory.png", "errors_over_time.png", "report.html"})
    fs::create_symlink("../victim.txt", dir + "/" + name);
  const FigureOutcome outcome = WriteReportFigures(dir);
  EXPECT_TRUE(outcome.ok()) << outcome.reason;
  EXPECT_EQ(ReadAll(victim), "victim\n") << "a figure was written through a planted link";
  for (const char* name : {"trajectory.png", "errors_over_time.png", "report.html"})
    EXPECT_FALSE(fs::is_symlink(dir + "/" + name)) << name << " is still the planted link";
  ExpectPng(dir + "/trajectory.png");
  EXPECT_EQ(Temporaries(dir), 0);
}

TEST(ReportFigures, TheScriptRunByHandReplacesALinkToo) {
  SKIP_WITHOUT_MATPLOTLIB();
  const std::string dir = SampleEvalFolder();
  Write(dir + "/../victim.txt", "victim\n");
  fs::create_symlink("../victim.txt", dir + "/trajectory.png");
  const ProgramRun run =
      RunProgram({"/usr/bin/python3", testing::SourceDir() + "/scripts/figures/report_figures.py",
                  dir, "--kind", "eval"});
  EXPECT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(ReadAll(dir + "/../victim.txt"), "victim\n");
  EXPECT_FALSE(fs::is_symlink(dir + "/trajectory.png"));
  ExpectPng(dir + "/trajectory.png");
  EXPECT_EQ(Temporaries(dir), 0);
}

TEST(ReportFigures, ANamedPipeAmongTheFilesIsNeverOpened) {
  SKIP_WITHOUT_MATPLOTLIB();
  // The script would block in open() on a FIFO named like an input: it is not handed to it.
  const std::string dir = SampleCompareFolder();
  fs::remove(dir + "/errors.csv");
  ASSERT_EQ(::mkfifo((dir + "/errors.csv").c_str(), 0644), 0);
  ASSERT_EQ(::mkfifo((dir + "/estimate_other.tum").c_str(), 0644), 0);
  const FigureOutcome outcome = WriteReportFigures(dir);
  EXPECT_NE(outcome.reason.find("errors.csv"), std::string::npos) << outcome.reason;
  EXPECT_TRUE(fs::exists(dir + "/report.html"));
}

TEST(ReportFigures, AScriptFailureNamesTheFileInOneLine) {
  SKIP_WITHOUT_MATPLOTLIB();
  const std::string dir = SampleCompareFolder();
  Write(dir + "/errors.csv", ReadAll(dir + "/errors.csv") + "smoother,x,m,\xff\xfe,1,0,1\n");
  const FigureOutcome outcome = WriteReportFigures(dir);
  EXPECT_NE(outcome.reason.find("the plotting script failed"), std::string::npos) << outcome.reason;
  EXPECT_NE(outcome.reason.find("report_figures: errors.csv: "), std::string::npos)
      << outcome.reason;
  EXPECT_EQ(outcome.reason.find("Traceback"), std::string::npos) << outcome.reason;
}

TEST(ReportHtml, Base64MatchesTheRfc4648TestVectors) {
  EXPECT_EQ(Base64Encode(""), "");
  EXPECT_EQ(Base64Encode("f"), "Zg==");
  EXPECT_EQ(Base64Encode("fo"), "Zm8=");
  EXPECT_EQ(Base64Encode("foo"), "Zm9v");
  EXPECT_EQ(Base64Encode("foob"), "Zm9vYg==");
  EXPECT_EQ(Base64Encode("fooba"), "Zm9vYmE=");
  EXPECT_EQ(Base64Encode("foobar"), "Zm9vYmFy");
  EXPECT_EQ(Base64Encode(std::string("\xff\x00\xfe", 3)), "/wD+");
}

TEST(ReportHtml, MarkdownTablesHeadingsListsAndEscaping) {
  const std::string html = MarkdownToHtml(
      "# Title <x>\n\nSome **bold** and `a<b` text, *a paper*, 2 * 3 * 4.\n<!-- hidden -->\n\n"
      "| name | value [m] |\n| --- | ---: |\n| `a\\|b` | 1.5 |\n\n- one\n- two\n  continued\n\n"
      "1. first\n2. second\n\n```\n<raw>\n```\n\n[link](errors.csv) [bad](javascript:alert(1))\n");
  EXPECT_NE(html.find("<h1>Title &lt;x&gt;</h1>"), std::string::npos) << html;
  EXPECT_NE(html.find("<p>Some <strong>bold</strong> and <code>a&lt;b</code> text, <em>a "
                      "paper</em>, 2 * 3 * 4.</p>"),
            std::string::npos)
      << html;
  EXPECT_EQ(html.find("hidden"), std::string::npos) << html;
  EXPECT_NE(html.find("<tr><th>name</th><th style=\"text-align:right\">value [m]</th></tr>"),
            std::string::npos)
      << html;
  EXPECT_NE(html.find("<td><code>a|b</code></td><td style=\"text-align:right\">1.5</td>"),
            std::string::npos)
      << html;
  EXPECT_NE(html.find("<ul>\n<li>one</li>\n<li>two continued</li>\n</ul>"), std::string::npos)
      << html;
  EXPECT_NE(html.find("<ol>\n<li>first</li>\n<li>second</li>\n</ol>"), std::string::npos) << html;
  EXPECT_NE(html.find("<pre><code>&lt;raw&gt;\n</code></pre>"), std::string::npos) << html;
  EXPECT_NE(html.find("<a href=\"errors.csv\">link</a>"), std::string::npos) << html;
  EXPECT_EQ(html.find("href=\"javascript"), std::string::npos) << html;
}

}  // namespace
}  // namespace mavloc
