// scripts/bench, the script behind docs/performance.md's scale figures, on its quick sizes: every
// section runs to the end and writes bench.json, and what it reports besides times holds: mavloc's
// APE with the yardstick's association equals the numpy script's, and the windowed smoother stays
// within the Cramer-Rao bound of the batch. No time is asserted.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "tests/test_support.h"

namespace fs = std::filesystem;

namespace mavloc {
namespace {

using testing::CliPath;
using testing::MakeTempDir;
using testing::ReadFileBytes;
using testing::RunCommand;
using testing::SourceDir;

TEST(BenchScript, QuickRunReportsEverySection) {
  const fs::path build = fs::path(CliPath()).parent_path();
  if (!fs::exists(build / "benchmarks/smoother_benchmark"))
    GTEST_SKIP() << "built without benchmarks (MAVLOC_BUILD_BENCHMARKS=OFF)";
  if (RunCommand("/usr/bin/python3 -c 'import numpy'").exit_code != 0)
    GTEST_SKIP() << "python3-numpy is absent";
  const std::string out = MakeTempDir();
  const auto run = RunCommand("/usr/bin/python3 " + SourceDir() + "/scripts/bench --quick --out " +
                              out + " --build " + build.string());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const auto bench = nlohmann::json::parse(ReadFileBytes(out + "/bench.json"));
  for (const char* section : {"eval", "smoother", "covariance", "long-log", "repro"})
    EXPECT_TRUE(bench.contains(section)) << section << "\n" << run.output;

  const double ours = bench["eval"]["ape_rmse_m"]["mavloc"];
  const double numpy = bench["eval"]["ape_rmse_m"]["numpy"];
  EXPECT_NEAR(ours, numpy, 1e-12 * numpy);
  EXPECT_GT(bench["eval"]["wall_ratio_median"].get<double>(), 0.0);

  EXPECT_GT(bench["smoother"]["30s"]["analytic_ms_per_kf"].get<double>(), 0.0);
  EXPECT_GT(bench["covariance"]["60s_structured"]["keyframes"].get<double>(), 1000.0);
  EXPECT_GT(bench["long-log"]["compare"]["realtime_factor"].get<double>(), 0.0);
  const auto& windows = bench["long-log"]["windows_vs_batch"];
  EXPECT_GT(windows["rms_m"].get<double>(), 0.0);  // the windows do change the estimate...
  EXPECT_LT(windows["rms_m"].get<double>(),        // ...by much less than its uncertainty
            0.2 * windows["crlb_position_rms_m"].get<double>());
  EXPECT_GT(bench["repro"]["speedup_median"].get<double>(), 0.0);
  EXPECT_TRUE(fs::exists(out + "/bench.md"));
}

}  // namespace
}  // namespace mavloc
