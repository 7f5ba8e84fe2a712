// `mavloc eval` on several estimates: two estimate files in different
// formats plus one folder of runs, the report folder and its file contract (the data files the
// figure writer reads), the protocol in report.json / report.md, KITTI files associated by index,
// and the exit code 2 with nothing written for bad option values and bad files.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>

#include "tests/test_support.h"

namespace fs = std::filesystem;

namespace mavloc {
namespace {

using testing::CliPath;
using testing::RunCommand;

// A smooth 20 s flight at 100 Hz: p(t) on an ellipse with a height wave, yaw turning with it.
struct Sample {
  double t;
  Eigen::Vector3d p;
  Eigen::Quaterniond q;
};

std::vector<Sample> Flight() {
  std::vector<Sample> s;
  for (int i = 0; i < 2000; ++i) {
    const double t = 100.0 + 0.01 * i;
    const double a = 0.5 * (t - 100.0);
    const Eigen::Vector3d p(3 * std::cos(a), 2 * std::sin(a), 1 + 0.2 * std::sin(2 * a));
    const Eigen::Quaterniond q(Eigen::AngleAxisd(a + 1.0, Eigen::Vector3d::UnitZ()) *
                               Eigen::AngleAxisd(0.1 * std::sin(a), Eigen::Vector3d::UnitY()));
    s.push_back({t, p, q});
  }
  return s;
}

std::string Tum(const std::vector<Sample>& s) {
  std::ostringstream out;
  out.precision(12);
  out << "# timestamp tx ty tz qx qy qz qw\n";
  for (const auto& x : s)
    out << std::fixed << x.t << " " << x.p.x() << " " << x.p.y() << " " << x.p.z() << " " << x.q.x()
        << " " << x.q.y() << " " << x.q.z() << " " << x.q.w() << "\n";
  return out.str();
}

// The flight with position noise (seeded) in the same frame.
std::vector<Sample> Noisy(const std::vector<Sample>& truth, unsigned seed, double sigma_m) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> n(0.0, sigma_m);
  std::vector<Sample> out = truth;
  for (auto& x : out) x.p += Eigen::Vector3d(n(rng), n(rng), n(rng));
  return out;
}

void Write(const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

std::string Read(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string FirstLine(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  return line;
}

size_t Lines(const std::string& path) {
  const std::string text = Read(path);
  return static_cast<size_t>(std::count(text.begin(), text.end(), '\n'));
}

std::string Cli(const std::string& args) {
  // No plotting interpreter: the report is written without figures (fast; the figure writer has
  // its own tests).
  return "MAVLOC_PYTHON=/nonexistent/python3 " + CliPath() + " " + args;
}

class EvalReport : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = testing::MakeTempDir();
    truth_ = Flight();
    Write(dir_ + "/gt.txt", Tum(truth_));
    // A: TUM with 1 cm noise.
    Write(dir_ + "/a.txt", Tum(Noisy(truth_, 1, 0.01)));
    // B: EuRoC/ASL CSV (ns, q_wxyz) of the truth seen from another world frame (rotated 30 deg
    // about z and shifted), with one repeated stamp: se3 alignment recovers it exactly.
    const Eigen::Quaterniond q_V_W(Eigen::AngleAxisd(0.5236, Eigen::Vector3d::UnitZ()));
    const Eigen::Vector3d p_V_W(5, -1, 0.5);
    std::ostringstream b;
    b.precision(12);
    b << "#timestamp [ns],x,y,z,qw,qx,qy,qz\n";
    for (size_t i = 0; i < truth_.size(); i += 2) {
      const Eigen::Vector3d p = q_V_W * truth_[i].p + p_V_W;
      const Eigen::Quaterniond q = q_V_W * truth_[i].q;
      const long long t_ns = static_cast<long long>(std::llround(truth_[i].t * 1e9));
      b << t_ns << "," << p.x() << "," << p.y() << "," << p.z() << "," << q.w() << "," << q.x()
        << "," << q.y() << "," << q.z() << "\n";
      if (i == 100)  // a repeated stamp (another pose): dropped, the first kept
        b << t_ns << ",9,9,9,1,0,0,0\n";
    }
    Write(dir_ + "/b.csv", b.str());
    // R: three runs of one estimator.
    fs::create_directories(dir_ + "/runs");
    for (unsigned k = 0; k < 3; ++k)
      Write(dir_ + "/runs/run" + std::to_string(k) + ".txt", Tum(Noisy(truth_, 10 + k, 0.02)));
  }
  std::string dir_;
  std::vector<Sample> truth_;
};

TEST_F(EvalReport, TwoEstimatesAndARunsFolderWriteTheReportContract) {
  const std::string out = dir_ + "/report";
  const auto r = RunCommand(Cli("eval --gt " + dir_ + "/gt.txt --est " + dir_ + "/a.txt --est " +
                                dir_ + "/b.csv --est " + dir_ + "/runs --label A --label B " +
                                "--label R --align se3 --delta 1 --delta-unit m --out " + out));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  // The dropped row is said once on stderr, with file and line.
  EXPECT_NE(r.output.find("b.csv: 1 row with a repeated timestamp dropped (kept the first), "
                          "first at " +
                          dir_ + "/b.csv:53"),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("| A | 1 |"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("| R | 3 |"), std::string::npos) << r.output;

  for (const char* f : {"report.md", "eval.tex", "report.json", "truth.tum", "estimate_A.tum",
                        "estimate_B.tum", "estimate_R_run1.tum", "estimate_R_run2.tum",
                        "estimate_R_run3.tum", "errors_over_time.csv", "relative_errors.csv"})
    EXPECT_TRUE(fs::exists(out + "/" + f)) << f;
  EXPECT_FALSE(fs::exists(out + "/estimate_R.tum"));
  EXPECT_EQ(FirstLine(out + "/errors_over_time.csv"),
            "label,run,t_s,translation_error_m,rotation_error_deg");
  EXPECT_EQ(FirstLine(out + "/relative_errors.csv"),
            "label,run,length_m,translation_error_pct,rotation_error_deg_per_m");

  std::ifstream in(out + "/report.json");
  const auto j = nlohmann::json::parse(in)["details"];  // eval's own layout
  ASSERT_EQ(j["estimates"].size(), 3u);
  EXPECT_EQ(j["estimates"][0]["label"], "A");
  EXPECT_EQ(j["estimates"][2]["kind"], "runs");
  ASSERT_EQ(j["estimates"][2]["runs"].size(), 3u);
  // Protocol: alignment, association, RPE and relative-error definitions, the files and formats.
  EXPECT_EQ(j["protocol"]["alignment"]["mode"], "se3");
  EXPECT_EQ(j["protocol"]["alignment"]["n_to_align"], -1);
  EXPECT_EQ(j["protocol"]["association"]["method"], "interpolated");
  EXPECT_DOUBLE_EQ(j["protocol"]["association"]["max_diff_s"].get<double>(), 0.01);
  EXPECT_DOUBLE_EQ(j["protocol"]["association"]["time_offset_s"].get<double>(), 0.0);
  EXPECT_DOUBLE_EQ(j["protocol"]["rpe"]["deltas"][0]["delta"].get<double>(), 1.0);
  EXPECT_FALSE(j["protocol"]["relative_error"]["lengths_m"].empty());
  EXPECT_FALSE(j["protocol"]["relative_error"]["lengths_given"].get<bool>());
  EXPECT_EQ(j["truth"]["format"], "tum");
  const auto& b = j["estimates"][1]["runs"][0];
  EXPECT_EQ(b["input"]["format"], "asl");
  EXPECT_EQ(b["input"]["duplicates_dropped"], 1);
  EXPECT_EQ(b["input"]["first_duplicate_line"], 53);
  EXPECT_EQ(b["input"]["sorted"], false);
  // B is the truth in another frame: after se3 alignment its error vanishes (12 digits in the CSV).
  EXPECT_LT(b["ape"]["translation_m"]["rmse"].get<double>(), 1e-5);
  EXPECT_LT(b["metrics"]["ape_translation_rmse_m"].get<double>(), 1e-5);
  // A: 1 cm noise per axis -> APE RMSE near sqrt(3) cm.
  const double a_rmse = j["estimates"][0]["summary"]["ape_translation_rmse_m"]["mean"];
  EXPECT_NEAR(a_rmse, 0.0173, 0.002);
  // R: mean and std over 3 runs of 2 cm noise.
  const auto& rs = j["estimates"][2]["summary"]["ape_translation_rmse_m"];
  EXPECT_EQ(rs["runs"], 3);
  EXPECT_NEAR(rs["mean"].get<double>(), 0.0346, 0.003);
  EXPECT_GT(rs["std"].get<double>(), 0.0);
  EXPECT_LT(rs["std"].get<double>(), 0.003);

  // estimate_B.tum is in the truth's frame: its poses equal the truth's at the same stamps.
  std::istringstream est(Read(out + "/estimate_B.tum"));
  std::string line;
  size_t checked = 0;
  while (std::getline(est, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream row(line);
    double t, x, y, z;
    row >> t >> x >> y >> z;
    const size_t i = static_cast<size_t>(std::llround((t - 100.0) * 100.0));
    ASSERT_LT(i, truth_.size());
    EXPECT_LT((Eigen::Vector3d(x, y, z) - truth_[i].p).norm(), 1e-5) << line;
    ++checked;
  }
  EXPECT_EQ(checked, 1000u);
  // One error row per associated pair, one relative row per sub-trajectory.
  size_t pairs = 0;
  for (const auto& e : j["estimates"])
    for (const auto& run : e["runs"]) pairs += run["pairs"].get<size_t>();
  EXPECT_EQ(Lines(out + "/errors_over_time.csv"), pairs + 1);
  size_t segments = 0;
  for (const auto& e : j["estimates"])
    for (const auto& run : e["runs"])
      for (const auto& rel : run["relative"]) segments += rel["segments"].get<size_t>();
  EXPECT_GT(segments, 0u);
  EXPECT_EQ(Lines(out + "/relative_errors.csv"), segments + 1);
  EXPECT_NE(Read(out + "/relative_errors.csv").find("\nR,3,"), std::string::npos);
  EXPECT_NE(Read(out + "/errors_over_time.csv").find("\nA,0,0.000000000,"), std::string::npos);

  // Markdown and LaTeX tables, protocol in report.md.
  const std::string md = Read(out + "/report.md");
  EXPECT_NE(md.find("| R | 3 |"), std::string::npos);
  EXPECT_NE(md.find(" ± "), std::string::npos);
  EXPECT_NE(md.find("## Protocol"), std::string::npos);
  EXPECT_NE(md.find("alignment: se3"), std::string::npos);
  EXPECT_NE(md.find("association: ground truth interpolated"), std::string::npos);
  EXPECT_NE(md.find("1 repeated-stamp row dropped, first at line 53"), std::string::npos);
  const std::string tex = Read(out + "/eval.tex");
  EXPECT_NE(tex.find("\\begin{tabular}"), std::string::npos);
  EXPECT_NE(tex.find("\\pm"), std::string::npos);
  EXPECT_NE(tex.find("\\end{tabular}"), std::string::npos);
}

TEST_F(EvalReport, EvoOptionsReachTheProtocol) {
  const auto r = RunCommand(
      Cli("eval --gt " + dir_ + "/gt.txt --est " + dir_ + "/a.txt --nearest --t-max-diff 0.005 " +
          "--t-offset 0.001 --align sim3 --n-to-align 500 --pose-relation full --delta 10 " +
          "--delta-unit f --all-pairs --rel-lengths 2 4 --json " + dir_ + "/e.json"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::ifstream in(dir_ + "/e.json");
  const auto j = nlohmann::json::parse(in)["details"];  // eval's own layout
  EXPECT_EQ(j["protocol"]["association"]["method"], "nearest");
  EXPECT_DOUBLE_EQ(j["protocol"]["association"]["max_diff_s"].get<double>(), 0.005);
  EXPECT_DOUBLE_EQ(j["protocol"]["association"]["time_offset_s"].get<double>(), 0.001);
  EXPECT_EQ(j["protocol"]["alignment"]["mode"], "sim3");
  EXPECT_EQ(j["protocol"]["alignment"]["n_to_align"], 500);
  EXPECT_EQ(j["protocol"]["ape"]["pose_relation"], "full");
  EXPECT_EQ(j["protocol"]["rpe"]["deltas"][0]["all_pairs"], true);
  EXPECT_EQ(j["protocol"]["relative_error"]["lengths_m"], nlohmann::json({2.0, 4.0}));
  EXPECT_TRUE(j["protocol"]["relative_error"]["lengths_given"].get<bool>());
  EXPECT_EQ(j["estimates"][0]["runs"][0]["aligned_pairs"], 500);
  EXPECT_TRUE(j["estimates"][0]["runs"][0]["metrics"].contains("sim3_scale"));
  // The older keys stay for one estimate.
  EXPECT_GT(j["pairs"].get<int>(), 100);
  EXPECT_GE(j["ate"]["rmse"].get<double>(), 0.0);
}

TEST_F(EvalReport, KittiFilesWithoutTimesAreAssociatedByIndex) {
  // The truth and estimate B as KITTI pose files (mavloc convert), no times files.
  ASSERT_EQ(
      RunCommand(Cli("convert --in " + dir_ + "/gt.txt --out " + dir_ + "/gt.kitti --format kitti"))
          .exit_code,
      0);
  ASSERT_EQ(
      RunCommand(Cli("convert --in " + dir_ + "/a.txt --out " + dir_ + "/a.kitti --format kitti"))
          .exit_code,
      0);
  auto r = RunCommand(
      Cli("eval --gt " + dir_ + "/gt.kitti --est " + dir_ + "/a.kitti --json " + dir_ + "/k.json"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::ifstream in(dir_ + "/k.json");
  const auto j = nlohmann::json::parse(in)["details"];  // eval's own layout
  EXPECT_EQ(j["protocol"]["association"]["method"], "index");
  EXPECT_EQ(j["estimates"][0]["runs"][0]["pairs"], 2000);
  EXPECT_EQ(j["truth"]["has_stamps"], false);
  // Different pose counts cannot be paired by index; a stamped ground truth needs --est-times.
  Write(dir_ + "/short.kitti", "1 0 0 0 0 1 0 0 0 0 1 0\n1 0 0 1 0 1 0 0 0 0 1 0\n");
  r = RunCommand(Cli("eval --gt " + dir_ + "/gt.kitti --est " + dir_ + "/short.kitti"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("associated by index"), std::string::npos) << r.output;
  r = RunCommand(Cli("eval --gt " + dir_ + "/gt.txt --est " + dir_ + "/a.kitti"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--est-times"), std::string::npos) << r.output;
}

void ExpectRefused(const testing::CommandResult& r, const std::string& must_contain,
                   const std::string& out) {
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find(must_contain), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(out)) << "partial output left at " << out;
}

TEST_F(EvalReport, BadOptionValuesAndFilesExitTwoWithNothingWritten) {
  const std::string out = dir_ + "/never";
  const std::string base =
      "eval --gt " + dir_ + "/gt.txt --est " + dir_ + "/a.txt --out " + out + " ";
  ExpectRefused(RunCommand(Cli(base + "--delta -1")), "--delta: -1: the RPE delta must be > 0",
                out);
  ExpectRefused(RunCommand(Cli(base + "--delta 1.5")), "whole number", out);
  ExpectRefused(RunCommand(Cli(base + "--t-max-diff 0")), "--t-max-diff", out);
  ExpectRefused(RunCommand(Cli(base + "--delta-unit km")), "--delta-unit", out);
  ExpectRefused(RunCommand(Cli(base + "--align affine")), "--align", out);
  ExpectRefused(RunCommand(Cli(base + "--n-to-align 0")), "--n-to-align", out);
  ExpectRefused(RunCommand(Cli(base + "--rel-lengths 0")), "--rel-lengths", out);
  ExpectRefused(RunCommand(Cli(base + "--label X --label Y")), "--label", out);
  ExpectRefused(RunCommand(Cli(base + "--est-format xyz")), "--est-format", out);
  // A bad file among the runs: file:line:field, and no report.
  Write(dir_ + "/runs/run9.txt", "100.0 0 0 0 0 0 0 1\n100.01 0 zero 0 0 0 0 1\n");
  ExpectRefused(
      RunCommand(Cli("eval --gt " + dir_ + "/gt.txt --est " + dir_ + "/runs --out " + out)),
      "run9.txt:2: field 'ty': 'zero' is not a number", out);
  fs::remove(dir_ + "/runs/run9.txt");
  // Rows out of order: an error naming file and line, unless --sort.
  Write(dir_ + "/unsorted.txt", "100.5 0 0 0 0 0 0 1\n100.2 0 0 0 0 0 0 1\n101.0 0 0 0 0 0 0 1\n");
  ExpectRefused(
      RunCommand(Cli("eval --gt " + dir_ + "/gt.txt --est " + dir_ + "/unsorted.txt --out " + out)),
      "unsorted.txt:2: field 'timestamp'", out);
  const auto sorted = RunCommand(Cli("eval --gt " + dir_ + "/gt.txt --est " + dir_ +
                                     "/unsorted.txt --sort --align none --out " + out));
  ASSERT_EQ(sorted.exit_code, 0) << sorted.output;
  std::ifstream in(out + "/report.json");
  const auto j = nlohmann::json::parse(in)["details"];  // eval's own layout
  EXPECT_TRUE(j["estimates"][0]["runs"][0]["input"]["sorted"].get<bool>());
  EXPECT_EQ(j["estimates"][0]["runs"][0]["input"]["rows_out_of_order"], 1);
}

}  // namespace
}  // namespace mavloc
