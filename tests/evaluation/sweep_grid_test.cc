// The sweep grid, shards and report (evaluation/sweep/): seed and setting ranges, the unit order,
// shards that partition the units, fingerprints that change with the grid, cell statistics, and a
// report that does not depend on how the units were produced.
#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "core/errors.h"
#include "evaluation/sweep/sweep_grid.h"
#include "evaluation/sweep/sweep_partial.h"
#include "evaluation/sweep/sweep_report.h"

namespace mavloc {
namespace {

SweepGrid SmallGrid() {
  SweepGrid grid;
  grid.scenarios = {"tag-arena-hover", "mav-figure-eight"};
  grid.seeds = {1, 2, 3};
  grid.settings = {{"a", {"1", "2"}}, {"b", {"x", "y", "z"}}};
  grid.estimators = {"tag-pnp"};
  return grid;
}

TEST(SweepGrid, SeedLists) {
  EXPECT_EQ(ParseSeedList("1..4", "--seeds"), (std::vector<uint64_t>{1, 2, 3, 4}));
  EXPECT_EQ(ParseSeedList("7, 1..2,20", "--seeds"), (std::vector<uint64_t>{7, 1, 2, 20}));
  EXPECT_THROW(ParseSeedList("4..2", "--seeds"), InputError);
  EXPECT_THROW(ParseSeedList("-1", "--seeds"), InputError);
  EXPECT_THROW(ParseSeedList("1..x", "--seeds"), InputError);
  EXPECT_THROW(ParseSeedList("", "--seeds"), InputError);
  EXPECT_EQ(SeedListText({1, 2, 3, 4, 9, 10, 20, 21, 22}), "1..4,9,10,20..22");
  EXPECT_EQ(ParseSeedList(SeedListText({5, 1, 2, 3}), "x"), (std::vector<uint64_t>{5, 1, 2, 3}));
}

TEST(SweepGrid, SettingAxes) {
  EXPECT_EQ(ParseSettingAxis("noise=1,2,4").second, (std::vector<std::string>{"1", "2", "4"}));
  EXPECT_EQ(ParseSettingAxis("h=1..3").second, (std::vector<std::string>{"1", "2", "3"}));
  // LO + i STEP, with the decimals of LO and STEP: the last value is HI.
  EXPECT_EQ(ParseSettingAxis("d=0..1:0.25").second,
            (std::vector<std::string>{"0", "0.25", "0.5", "0.75", "1"}));
  EXPECT_EQ(ParseSettingAxis("d=0.1..0.3:0.1").second,
            (std::vector<std::string>{"0.1", "0.2", "0.3"}));
  EXPECT_EQ(ParseSettingAxis("d=-1..1:0.5").second,
            (std::vector<std::string>{"-1", "-0.5", "0", "0.5", "1"}));
  EXPECT_EQ(ParseSettingAxis("mode=a..b,c").second,  // a list with dots is a list
            (std::vector<std::string>{"a..b", "c"}));
  EXPECT_THROW(ParseSettingAxis("d=2..1"), InputError);
  EXPECT_THROW(ParseSettingAxis("d=0..1:0"), InputError);
  EXPECT_THROW(ParseSettingAxis("novalue"), InputError);
}

TEST(SweepGrid, UnitOrderCoversTheGridOnce) {
  const SweepGrid grid = SmallGrid();
  ASSERT_EQ(SweepUnitCount(grid), 2u * 6u * 3u);
  std::set<std::string> seen;
  for (size_t k = 0; k < SweepUnitCount(grid); ++k) {
    const SweepUnit u = SweepUnitAt(grid, k);
    EXPECT_TRUE(
        seen.insert(u.scenario + "|" + SettingsLabel(u.settings) + "|" + std::to_string(u.seed))
            .second);
  }
  // Seed fastest, then the last setting key, then the first, then the scenario.
  EXPECT_EQ(SweepUnitAt(grid, 0).seed, 1u);
  EXPECT_EQ(SweepUnitAt(grid, 1).seed, 2u);
  EXPECT_EQ(SettingsLabel(SweepUnitAt(grid, 3).settings), "a=1; b=y");
  EXPECT_EQ(SettingsLabel(SweepUnitAt(grid, 9).settings), "a=2; b=x");
  EXPECT_EQ(SweepUnitAt(grid, 17).scenario, "tag-arena-hover");
  EXPECT_EQ(SweepUnitAt(grid, 18).scenario, "mav-figure-eight");
}

TEST(SweepGrid, ShardsPartitionTheUnits) {
  for (int n : {1, 3, 7, 36, 40}) {
    std::vector<int> hits(36, 0);
    for (int i = 1; i <= n; ++i)
      for (size_t k : ShardUnitIndices(36, {i, n})) ++hits[k];
    for (int h : hits) EXPECT_EQ(h, 1) << n << " shards";
  }
  EXPECT_EQ(ShardUnitIndices(10, {2, 3}), (std::vector<size_t>{1, 4, 7}));
  EXPECT_EQ(ParseShardSpec("3/10").shard, 3);
  EXPECT_THROW(ParseShardSpec("0/3"), InputError);
  EXPECT_THROW(ParseShardSpec("4/3"), InputError);
  EXPECT_THROW(ParseShardSpec("1-3"), InputError);
}

TEST(SweepGrid, FingerprintFollowsTheGrid) {
  const SweepGrid grid = SmallGrid();
  SweepGrid other = grid;
  other.seeds.push_back(4);
  EXPECT_EQ(SweepFingerprint(grid), SweepFingerprint(SmallGrid()));
  EXPECT_NE(SweepFingerprint(grid), SweepFingerprint(other));
  other = grid;
  other.options = {"smoother:threads=1"};
  EXPECT_NE(SweepFingerprint(grid), SweepFingerprint(other));
  // The canonical text round-trips (through the validation, so with settings both scenarios have).
  SweepGrid valid = grid;
  valid.settings = {{"imu_noise", {"0", "1"}}};
  valid.scenarios = {"tag-arena-hover"};
  EXPECT_EQ(CanonicalGridText(SweepGridFromJson(SweepGridToJson(valid), "test")),
            CanonicalGridText(valid));
  EXPECT_EQ(Fnv1a64Hex(""), "cbf29ce484222325");   // FNV-1a 64 offset basis
  EXPECT_EQ(Fnv1a64Hex("a"), "af63dc4c8601ec8c");  // published FNV-1a test vector
}

TEST(SweepGrid, ValidationNamesTheProblem) {
  SweepGrid grid = SmallGrid();
  grid.scenarios.push_back("no-such-scenario");
  EXPECT_THROW(ValidateSweepGrid(grid), InputError);
  grid = SmallGrid();
  grid.seeds = {1, 1};
  try {
    ValidateSweepGrid(grid);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("seed '1' listed twice"), std::string::npos);
  }
}

// Synthetic unit results: the report's statistics and layout, without running estimators.
std::vector<nlohmann::json> FakeUnits(const SweepGrid& grid) {
  std::vector<nlohmann::json> units;
  for (size_t k = 0; k < SweepUnitCount(grid); ++k) {
    const SweepUnit u = SweepUnitAt(grid, k);
    nlohmann::json row = {{"name", "tag-pnp"}, {"ran", true}};
    row["metrics"] = {{"ate_rmse", 0.001 * static_cast<double>(u.seed)}};
    row["units"] = {{"ate_rmse", "m"}};
    units.push_back({{"index", k},
                     {"scenario", u.scenario},
                     {"seed", u.seed},
                     {"settings", u.settings},
                     {"estimators", nlohmann::json::array({row})}});
  }
  return units;
}

TEST(SweepReport, CellStatisticsOverSeeds) {
  const SweepGrid grid = SmallGrid();
  const auto files = BuildSweepReport(grid, "fp", FakeUnits(grid));
  const auto json = nlohmann::json::parse(files.at("report.json"))["details"];
  ASSERT_EQ(json["cells"].size(), 12u);
  const auto& metric = json["cells"][0]["metrics"]["ate_rmse"];
  EXPECT_EQ(metric["n"], 3);
  EXPECT_NEAR(metric["mean"].get<double>(), 0.002, 1e-15);
  EXPECT_NEAR(metric["std"].get<double>(), 0.001, 1e-15);  // sample std of 1, 2, 3 mm
  EXPECT_NEAR(metric["median"].get<double>(), 0.002, 1e-15);
  EXPECT_NEAR(metric["min"].get<double>(), 0.001, 1e-15);
  EXPECT_NEAR(metric["max"].get<double>(), 0.003, 1e-15);
  EXPECT_EQ(json["cells"][0]["settings"], "a=1; b=x");
  // Same units, same bytes (report.json but its provenance: the elapsed time); a unit out of
  // place is refused.
  auto again = BuildSweepReport(grid, "fp", FakeUnits(grid));
  EXPECT_EQ(files.at("report.md"), again.at("report.md"));
  EXPECT_EQ(files.at("runs.csv"), again.at("runs.csv"));
  auto first_json = nlohmann::json::parse(files.at("report.json"));
  auto second_json = nlohmann::json::parse(again.at("report.json"));
  first_json.erase("provenance");
  second_json.erase("provenance");
  EXPECT_EQ(first_json, second_json);
  auto units = FakeUnits(grid);
  std::swap(units[0], units[1]);
  EXPECT_THROW(BuildSweepReport(grid, "fp", units), InputError);
  units.pop_back();
  EXPECT_THROW(BuildSweepReport(grid, "fp", units), InputError);
}

TEST(SweepReport, SkippedEstimatorsAreCountedNotAveraged) {
  SweepGrid grid = SmallGrid();
  grid.settings.clear();
  auto units = FakeUnits(grid);
  units[1]["estimators"][0] = {{"name", "tag-pnp"}, {"ran", false}, {"skipped", "no tags"}};
  const auto files = BuildSweepReport(grid, "fp", units);
  const auto json = nlohmann::json::parse(files.at("report.json"))["details"];
  EXPECT_EQ(json["cells"][0]["runs"], 3);
  EXPECT_EQ(json["cells"][0]["ran"], 2);
  EXPECT_EQ(json["cells"][0]["metrics"]["ate_rmse"]["n"], 2);
  EXPECT_NEAR(json["cells"][0]["metrics"]["ate_rmse"]["mean"].get<double>(), 0.002, 1e-15);
  EXPECT_NE(files.at("report.md").find("did not run in 1 of 3"), std::string::npos);
  EXPECT_NE(files.at("runs.csv").find("\n1,tag-arena-hover,,2,tag-pnp,0,,,\n"), std::string::npos);
}

}  // namespace
}  // namespace mavloc
