// `mavloc eval` builds what its outputs need and nothing more: report.json (--json) and the
// terminal table need the statistics alone, the report folder (--out) also the per-pair and
// per-segment series and the aligned estimates. The statistics, and so every number of
// report.json, are the same whichever was built: the JSON of `eval --json` equals the one written
// beside the full report folder.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <set>
#include <sstream>
#include <stdexcept>

#include "datasets/io/trajectory_formats/trajectory_format.h"
#include "evaluation/eval/eval_report.h"
#include "evaluation/eval/eval_run.h"
#include "evaluation/report/report_folder.h"
#include "tests/test_support.h"

namespace fs = std::filesystem;

namespace mavloc {
namespace {

using testing::CliPath;
using testing::RunCommand;

// A 30 s flight at 100 Hz (a figure eight with a height wave, yaw following it) as TUM text; the
// estimate at half the rate, 1 ms after the truth's stamps, in a world turned by 0.2 rad and
// shifted, with seeded position noise.
std::string FlightTum(bool estimate, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, 0.01);
  const Eigen::Quaterniond q_V_W(Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitZ()));
  const Eigen::Vector3d p_V_W(1.0, -2.0, 0.3);
  std::ostringstream out;
  out.precision(12);
  out << std::fixed;
  for (int i = 0; i < 3000; i += estimate ? 2 : 1) {
    const double t = 50.0 + 0.01 * i + (estimate ? 0.001 : 0.0);
    const double a = 0.3 * (t - 50.0);
    Eigen::Vector3d p(4 * std::sin(a), 2 * std::sin(2 * a), 1.5 + 0.3 * std::sin(3 * a));
    Eigen::Quaterniond q(Eigen::AngleAxisd(a, Eigen::Vector3d::UnitZ()) *
                         Eigen::AngleAxisd(0.05 * std::sin(a), Eigen::Vector3d::UnitX()));
    if (estimate) {
      p = q_V_W * p + p_V_W + Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
      q = q_V_W * q;
    }
    out << t << " " << p.x() << " " << p.y() << " " << p.z() << " " << q.x() << " " << q.y() << " "
        << q.z() << " " << q.w() << "\n";
  }
  return out.str();
}

// report.json without the provenance's command line and elapsed time (they differ between runs).
nlohmann::json WithoutTiming(nlohmann::json j) {
  j["provenance"].erase("command");
  j["provenance"].erase("elapsed_s");
  return j;
}

nlohmann::json ReportNumbers(const std::string& path) {
  std::ifstream in(path);
  return WithoutTiming(nlohmann::json::parse(in));
}

class EvalOutputsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = testing::MakeTempDir();
    testing::WriteFileBytes(dir_ + "/gt.txt", FlightTum(false, 0));
    testing::WriteFileBytes(dir_ + "/a.txt", FlightTum(true, 1));
    fs::create_directories(dir_ + "/runs");
    for (unsigned k = 0; k < 2; ++k)
      testing::WriteFileBytes(dir_ + "/runs/run" + std::to_string(k) + ".txt",
                              FlightTum(true, 10 + k));
  }

  // The inputs as the command reads them: a file and a folder of two runs.
  std::vector<EvalInput> Inputs() const {
    std::vector<EvalInput> inputs(2);
    inputs[0].label = "a";
    inputs[0].source = dir_ + "/a.txt";
    inputs[0].runs.emplace_back(inputs[0].source, ReadTrajectory(inputs[0].source));
    inputs[1].label = "runs";
    inputs[1].source = dir_ + "/runs";
    inputs[1].is_folder = true;
    for (const char* name : {"/runs/run0.txt", "/runs/run1.txt"})
      inputs[1].runs.emplace_back(dir_ + name, ReadTrajectory(dir_ + name));
    return inputs;
  }

  // An RPE over metres and over all pairs besides the default frame delta, so that every series
  // kind (listed pairs, visited pairs) is covered.
  static EvaluationProtocol Protocol() {
    EvaluationProtocol p;
    p.association = AssociationMode::kInterpolate;
    p.rpe_deltas = {RpeDelta{1.0, DeltaUnit::kFrames, false},
                    RpeDelta{2.0, DeltaUnit::kMetres, false},
                    RpeDelta{5.0, DeltaUnit::kFrames, true}};
    return p;
  }

  EvalReport Evaluate(const EvalOutputs& outputs) const {
    return EvaluateInputs(ReadTrajectory(dir_ + "/gt.txt"), dir_ + "/gt.txt", Inputs(), Protocol(),
                          outputs);
  }

  std::string dir_;
};

TEST_F(EvalOutputsTest, ReportJsonAloneBuildsNoSeriesAndNoAlignedEstimate) {
  EvalOutputs json_only;
  json_only.report_json = true;
  const EvalReport report = Evaluate(json_only);
  EXPECT_FALSE(report.protocol.keep_series);
  size_t runs = 0;
  for (const auto& estimate : report.estimates)
    for (const auto& run : estimate.runs) {
      ++runs;
      const TrajectoryEvaluation& ev = run.evaluation;
      EXPECT_GT(ev.pair_count, 1000u);
      EXPECT_EQ(ev.ape_translation_m.count, ev.pair_count);  // the statistics are there
      EXPECT_TRUE(run.aligned_estimate.empty());
      EXPECT_TRUE(ev.pair_t_ns.empty());
      EXPECT_TRUE(ev.ape.translation_m.empty());
      EXPECT_TRUE(ev.ape.rotation_deg.empty());
      EXPECT_TRUE(ev.ape.rotation_part.empty());
      EXPECT_TRUE(ev.ape.full.empty());
      ASSERT_EQ(ev.rpe.size(), 3u);
      for (const auto& rpe : ev.rpe) {
        EXPECT_GT(rpe.translation_m.count, 0u);
        EXPECT_TRUE(rpe.t_ns.empty());
        EXPECT_TRUE(rpe.errors.empty());
      }
      ASSERT_FALSE(ev.relative.empty());
      for (const auto& rel : ev.relative) {
        EXPECT_GT(rel.count(), 0u);
        EXPECT_TRUE(rel.start_t_ns.empty());
        EXPECT_TRUE(rel.translation_m.empty());
        EXPECT_TRUE(rel.translation_percent.empty());
        EXPECT_TRUE(rel.rotation_deg.empty());
        EXPECT_TRUE(rel.rotation_deg_per_m.empty());
        EXPECT_TRUE(rel.yaw_deg.empty());
        EXPECT_TRUE(rel.tilt_deg.empty());
      }
    }
  EXPECT_EQ(runs, 3u);
  // The report folder's files cannot be made from it (they would be empty): refused.
  EXPECT_THROW(EvalReportFiles(report), std::logic_error);
}

TEST_F(EvalOutputsTest, ReportFolderBuildsEverySeries) {
  EvalOutputs folder;
  folder.report_folder = true;
  const EvalReport report = Evaluate(folder);
  EXPECT_TRUE(report.protocol.keep_series);
  for (const auto& estimate : report.estimates)
    for (const auto& run : estimate.runs) {
      const TrajectoryEvaluation& ev = run.evaluation;
      EXPECT_EQ(run.aligned_estimate.size(), ev.estimate_count);
      EXPECT_EQ(ev.pair_t_ns.size(), ev.pair_count);
      EXPECT_EQ(ev.ape.translation_m.size(), ev.pair_count);
      for (const auto& rpe : ev.rpe) EXPECT_EQ(rpe.errors.size(), rpe.translation_m.count);
      for (const auto& rel : ev.relative) EXPECT_EQ(rel.translation_m.size(), rel.count());
    }
}

TEST_F(EvalOutputsTest, ReportJsonIsTheSameWhetherTheSeriesWereBuiltOrNot) {
  EvalOutputs json_only, both;
  json_only.report_json = true;
  both.report_folder = both.report_json = true;
  const EvalReport lean = Evaluate(json_only);
  const EvalReport full = Evaluate(both);
  const Report lean_model = EvalModel(lean);
  const Report full_model = EvalModel(full);
  // Every number and every text (the coverage's estimate span included).
  EXPECT_EQ(WithoutTiming(nlohmann::json::parse(ReportJsonText(lean_model))),
            WithoutTiming(nlohmann::json::parse(ReportJsonText(full_model))));
  // The same files listed; without the series their contents are not built.
  std::set<std::string> lean_names, full_names;
  for (const auto& [name, contents] : lean_model.files) {
    lean_names.insert(name);
    EXPECT_TRUE(contents.empty()) << name;
  }
  for (const auto& [name, contents] : full_model.files) {
    full_names.insert(name);
    EXPECT_FALSE(contents.empty()) << name;
  }
  EXPECT_EQ(lean_names, full_names);
  const std::vector<std::string> names = EvalReportFileNames(full);
  EXPECT_EQ(std::set<std::string>(names.begin(), names.end()), full_names);
  ASSERT_FALSE(lean_model.estimators.empty());
  ASSERT_TRUE(lean_model.estimators[0].coverage.has_value());
  EXPECT_GT(lean_model.estimators[0].coverage->estimate_span_s, 29.0);
}

TEST_F(EvalOutputsTest, EvalJsonEqualsTheJsonWrittenWithTheReportFolder) {
  const std::string common = "MAVLOC_FIGURES=0 " + CliPath() + " eval --gt " + dir_ +
                             "/gt.txt --est " + dir_ + "/a.txt --est " + dir_ +
                             "/runs --align se3 --rpe-distance 2 --all-pairs";
  const auto lean = RunCommand(common + " --json " + dir_ + "/lean.json");
  ASSERT_EQ(lean.exit_code, 0) << lean.output;
  const auto full = RunCommand(common + " --json " + dir_ + "/full.json --out " + dir_ + "/report");
  ASSERT_EQ(full.exit_code, 0) << full.output;
  const nlohmann::json lean_json = ReportNumbers(dir_ + "/lean.json");
  EXPECT_EQ(lean_json, ReportNumbers(dir_ + "/full.json"));
  EXPECT_EQ(lean_json, ReportNumbers(dir_ + "/report/report.json"));
  // The same terminal output up to the report folder's lines.
  EXPECT_EQ(full.output.rfind(lean.output, 0), 0u) << lean.output << "\n---\n" << full.output;
  // The report folder holds every file report.json lists, with content.
  for (const auto& name : lean_json["files"]) {
    const std::string path = dir_ + "/report/" + name.get<std::string>();
    ASSERT_TRUE(fs::is_regular_file(path)) << path;
    EXPECT_GT(fs::file_size(path), 0u) << path;
  }
}

}  // namespace
}  // namespace mavloc
