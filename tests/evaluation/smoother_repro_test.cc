// `mavloc repro smoother` end to end through the CLI: two short runs on every simulated scenario;
// the report's structure (one table per scenario with the smoother, its seeds and the paper's
// filter, the wins, the verdict lines) and finite numbers. The accuracy claims themselves are
// checked per scenario in smoother_test.cc and measured by the full command.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "tests/test_support.h"

namespace mavloc {
namespace {

bool IsFinite(const nlohmann::json& value) {
  return value.is_number() && std::isfinite(value.get<double>());
}

TEST(SmootherReproCli, SmallEndToEndRun) {
  const std::string dir = testing::MakeTempDir();
  const std::string scenarios =
      "tag-arena-hover,tag-arena-dynamic,marker-board-flight,three-point-hover,mav-figure-eight,"
      "laser-plane";
  const auto result = testing::RunCommand(
      testing::CliPath() + " repro smoother --runs 2 --seed 3 --report " + dir +
      " --set duration_s=8 --set duration_s.three-point-hover=20 --set scenarios=" + scenarios);
  ASSERT_EQ(result.exit_code, 0) << result.output;
  std::ifstream in(dir + "/report.json");
  ASSERT_TRUE(in.good());
  const nlohmann::json report = nlohmann::json::parse(in);
  EXPECT_EQ(report["provenance"]["runs"], 2);
  EXPECT_EQ(report["provenance"]["seeds"], nlohmann::json({3, 4}));
  const nlohmann::json& json = report["details"];  // the repro's own layout
  const auto& tables = json["tables"];
  ASSERT_EQ(tables.size(), 6u);
  EXPECT_FALSE(tables.contains("euroc-laser"));  // not asked for

  const std::map<std::string, std::vector<std::string>> expected = {
      {"tag-arena-hover", {"smoother", "tag-pnp", "tag-ekf"}},
      {"tag-arena-dynamic", {"smoother", "tag-pnp", "tag-ekf"}},
      {"marker-board-flight", {"smoother", "tag-pnp", "pnp", "upright-2p", "pixhawk-kf"}},
      {"three-point-hover", {"smoother", "three-point", "two-point", "gravity-ekf"}},
      {"mav-figure-eight", {"smoother", "landmark-pnp"}},
      {"laser-plane", {"smoother", "laser-ekf"}}};
  for (const auto& [scenario, estimators] : expected) {
    SCOPED_TRACE(scenario);
    ASSERT_TRUE(tables.contains(scenario));
    const auto& table = tables[scenario];
    const bool laser = scenario == "laser-plane";
    EXPECT_EQ(table["laser"].get<bool>(), laser);
    // The requested duration (some scenarios add a few seconds of take-off or hover around it).
    const double requested_s = scenario == "three-point-hover" ? 20.0 : 8.0;
    EXPECT_GE(table["duration_s"].get<double>(), requested_s - 0.5);
    EXPECT_LT(table["duration_s"].get<double>(), requested_s + 4.0);
    for (const auto& name : estimators) {
      SCOPED_TRACE(name);
      ASSERT_TRUE(table["estimators"].contains(name));
      const auto& e = table["estimators"][name];
      EXPECT_EQ(e["runs"], 2);
      EXPECT_EQ(e["per_run"].size(), 2u);
      if (laser) {
        for (const char* q : {"d", "v_o", "roll", "pitch", "alpha"}) {
          EXPECT_TRUE(IsFinite(e["quantity_rmse"][q]["rmse"])) << q;
          EXPECT_EQ(e["quantity_rmse"][q]["per_run_rmse"].size(), 2u) << q;
        }
      } else if (name == "gravity-ekf") {  // roll and pitch only
        EXPECT_TRUE(IsFinite(e["quantity_rmse"]["roll"]["rmse"]));
        EXPECT_TRUE(IsFinite(e["quantity_rmse"]["pitch"]["rmse"]));
      } else {
        EXPECT_TRUE(IsFinite(e["position_rmse_m"]));
        EXPECT_TRUE(IsFinite(e["attitude_rmse_rad"]));
        EXPECT_GT(e["position_rmse_m"].get<double>(), 0.0);
        EXPECT_LT(e["position_rmse_m"].get<double>(), 1.0);  // metres: no estimator is lost
        EXPECT_EQ(e["per_run_position_rmse_m"].size(), 2u);
        EXPECT_TRUE(e["per_run"][0].contains("ate"));  // the EvaluationToJson object
      }
      if (name != "smoother") {
        ASSERT_TRUE(table["smoother_wins"].contains(name));
        const auto& wins = table["smoother_wins"][name];
        EXPECT_EQ(wins["runs_judged"], 2);
        EXPECT_GE(wins["runs_better_on_all"].get<int>(), 0);
        EXPECT_LE(wins["runs_better_on_all"].get<int>(), 2);
      }
    }
    EXPECT_TRUE(IsFinite(table["estimators"]["smoother"]["mean_failures_per_run"]));
    ASSERT_FALSE(table["verdicts"].empty());
    EXPECT_EQ(table["verdicts"][0].get<std::string>().rfind("smoother more accurate than", 0), 0u)
        << table["verdicts"][0];
  }
  std::ifstream md_in(dir + "/report.md");
  std::stringstream md;
  md << md_in.rdbuf();
  EXPECT_NE(md.str().find("## tag-arena-dynamic (2 runs"), std::string::npos);
  EXPECT_NE(md.str().find("- smoother more accurate than tag-ekf on position and attitude in "),
            std::string::npos);
  EXPECT_NE(md.str().find("- smoother more accurate than laser-ekf on d, v_o, roll, pitch and "
                          "alpha in "),
            std::string::npos);

  const auto bad = testing::RunCommand(testing::CliPath() + " repro smoother --report " + dir +
                                       " --set nonsense=1");
  EXPECT_EQ(bad.exit_code, 2) << bad.output;
  const auto unknown = testing::RunCommand(testing::CliPath() + " repro smoother --report " + dir +
                                           " --set scenarios=stereo-obstacles");
  EXPECT_EQ(unknown.exit_code, 2) << unknown.output;
}

}  // namespace
}  // namespace mavloc
