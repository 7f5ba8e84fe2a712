// Output folders are written whole (cli/output_folder.h): a dataset
// simulated into the folder of another keeps none of the old streams, a report folder keeps no
// file of an earlier report, and a folder that is neither empty nor of the same kind is refused
// untouched. No staging folder "*.tmp-<pid>" is left beside the output.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/file.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "tests/test_support.h"

namespace mavloc {
namespace {

namespace fs = std::filesystem;
using testing::CliPath;
using testing::MakeTempDir;
using testing::RunCommand;

testing::CommandResult Mavloc(const std::string& args) {
  return RunCommand("MAVLOC_FIGURES=0 " + CliPath() + " " + args);
}

// Names in `folder` that look like staging or swapped-out folders.
int LeftoverCount(const std::string& folder) {
  int count = 0;
  for (const auto& entry : fs::directory_iterator(folder)) {
    const std::string name = entry.path().filename().string();
    count += name.find(".tmp-") != std::string::npos || name.find(".old-") != std::string::npos;
  }
  return count;
}

TEST(OutputIntegrity, SimulateIntoAnotherDatasetKeepsNoOldStream) {
  const std::string dir = MakeTempDir();
  const std::string out = dir + "/dataset";
  auto r = Mavloc("simulate --scenario tag-arena-hover --duration 3 --out " + out);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  ASSERT_TRUE(fs::exists(out + "/mav0/tags0/data.csv"));
  ASSERT_FALSE(fs::exists(out + "/mav0/features0"));
  r = Mavloc("simulate --scenario mav-figure-eight --duration 2 --force --out " + out + "/");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_FALSE(fs::exists(out + "/mav0/tags0")) << "a stream of the old dataset survived";
  EXPECT_TRUE(fs::exists(out + "/mav0/features0/data.csv"));
  std::ifstream scenario(out + "/scenario.yaml");
  std::string text((std::istreambuf_iterator<char>(scenario)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("mav-figure-eight"), std::string::npos);
  EXPECT_EQ(LeftoverCount(dir), 0);
}

TEST(OutputIntegrity, SimulateRefusesAFolderThatIsNotADataset) {
  const std::string dir = MakeTempDir();
  const std::string out = dir + "/notes";
  fs::create_directories(out);
  std::ofstream(out + "/thesis.tex") << "do not delete\n";
  const auto r = Mavloc("simulate --scenario mav-figure-eight --duration 2 --out " + out);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("not a mavloc dataset"), std::string::npos) << r.output;
  EXPECT_TRUE(fs::exists(out + "/thesis.tex"));
  EXPECT_FALSE(fs::exists(out + "/mav0"));
  EXPECT_EQ(LeftoverCount(dir), 0);
}

TEST(OutputIntegrity, SimulateIntoAnEmptyFolderWorks) {
  const std::string dir = MakeTempDir();
  fs::create_directories(dir + "/empty");
  const auto r =
      Mavloc("simulate --scenario mav-figure-eight --duration 2 --out " + dir + "/empty");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(fs::exists(dir + "/empty/mav0/imu0/data.csv"));
  EXPECT_EQ(LeftoverCount(dir), 0);
}

TEST(OutputIntegrity, CompareReportKeepsNoStaleFile) {
  const std::string dir = MakeTempDir();
  const std::string report = dir + "/report";
  fs::create_directories(report);
  std::ofstream(report + "/report.json") << "{}\n";
  std::ofstream(report + "/estimate_old-estimator.tum") << "stale\n";
  const auto r =
      Mavloc("compare --duration 2 --estimators imu-dead-reckoning --force --report " + report);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_FALSE(fs::exists(report + "/estimate_old-estimator.tum")) << "stale file kept";
  EXPECT_TRUE(fs::exists(report + "/report.json"));
  EXPECT_TRUE(fs::exists(report + "/errors.csv"));
  EXPECT_EQ(r.output.find(".tmp-"), std::string::npos) << "staging path shown: " << r.output;
  EXPECT_EQ(LeftoverCount(dir), 0);
}

TEST(OutputIntegrity, CompareRefusesAFolderThatIsNotAReport) {
  const std::string dir = MakeTempDir();
  const std::string report = dir + "/photos";
  fs::create_directories(report);
  std::ofstream(report + "/holiday.jpg") << "jpeg\n";
  const auto r = Mavloc("compare --duration 2 --estimators imu-dead-reckoning --report " + report);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("not a mavloc report"), std::string::npos) << r.output;
  EXPECT_TRUE(fs::exists(report + "/holiday.jpg"));
  EXPECT_FALSE(fs::exists(report + "/report.json"));
  EXPECT_EQ(LeftoverCount(dir), 0);
}

TEST(OutputIntegrity, EvalReportKeepsNoStaleFile) {
  const std::string dir = MakeTempDir();
  {
    std::ofstream gt(dir + "/gt.txt");
    std::ofstream est(dir + "/est.txt");
    for (int i = 0; i < 50; ++i) {
      gt << i * 0.1 << " " << i * 0.05 << " 0 0 0 0 0 1\n";
      est << i * 0.1 << " " << i * 0.05 + 0.01 << " 0 0 0 0 0 1\n";
    }
  }
  const std::string out = dir + "/eval";
  fs::create_directories(out);
  std::ofstream(out + "/report.json") << "{}\n";
  std::ofstream(out + "/estimate_from_last_week.tum") << "stale\n";
  const auto r = Mavloc("eval --align none --gt " + dir + "/gt.txt --est " + dir +
                        "/est.txt --out " + out + " --force");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_FALSE(fs::exists(out + "/estimate_from_last_week.tum")) << "stale file kept";
  EXPECT_TRUE(fs::exists(out + "/report.json"));
  EXPECT_EQ(LeftoverCount(dir), 0);
}

TEST(OutputIntegrity, FailedRunLeavesTheOldReportUntouched) {
  const std::string dir = MakeTempDir();
  const std::string report = dir + "/report";
  fs::create_directories(report);
  std::ofstream(report + "/report.json") << "{\"old\": true}\n";
  // Fails after the staging folder exists (the scenario rejects the key).
  const auto r = Mavloc("compare --set typo_key=1 --report " + report);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  std::ifstream json(report + "/report.json");
  std::string text((std::istreambuf_iterator<char>(json)), std::istreambuf_iterator<char>());
  EXPECT_EQ(text, "{\"old\": true}\n");
  EXPECT_EQ(LeftoverCount(dir), 0);
}

// A second command writing the same --out while the first still works is refused: the first
// holds the folder (cli/output_folder.h). Here the test process holds it as a command would.
TEST(OutputIntegrity, AFolderAnotherCommandIsWritingIsRefused) {
  const std::string dir = MakeTempDir();
  {
    std::ofstream gt(dir + "/gt.txt");
    for (int i = 0; i < 50; ++i) gt << i * 0.1 << " " << i * 0.05 << " 0 0 0 0 0 1\n";
  }
  const std::string eval =
      "eval --align none --gt " + dir + "/gt.txt --est " + dir + "/gt.txt --out " + dir + "/out";
  for (const bool existing : {false, true}) {
    SCOPED_TRACE(existing ? "an existing report, --force" : "a new folder");
    fs::remove_all(dir + "/out");
    fs::create_directories(dir + "/out");  // what the first command's mkdir made
    if (existing) std::ofstream(dir + "/out/report.json") << "{\"first\": true}\n";
    const int fd = ::open((dir + "/out").c_str(), O_RDONLY | O_DIRECTORY);
    ASSERT_GE(fd, 0);
    ASSERT_EQ(::flock(fd, LOCK_EX), 0);
    const auto r = Mavloc(eval + (existing ? " --force" : ""));
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find("is being written by another mavloc command"), std::string::npos)
        << r.output;
    EXPECT_EQ(fs::exists(dir + "/out/report.json"), existing);
    ::close(fd);
    EXPECT_EQ(LeftoverCount(dir), 0);
  }
  // Without a holder the same command runs, and takes a new folder itself.
  fs::remove_all(dir + "/out");
  const auto r = Mavloc(eval);
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(fs::exists(dir + "/out/report.json"));
  EXPECT_EQ(LeftoverCount(dir), 0);
}

}  // namespace
}  // namespace mavloc
