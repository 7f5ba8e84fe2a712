// Merge cost of a 10,000-run sweep (docs/performance.md): 10,000 units with two estimators
// and 15 metrics each (the shape of a tag-pnp + smoother run), written as N partial files
// (N = 10,000: one unit per shard, the worst case; N = 100: one shard per node of a 100-node
// study), then timed: MergePartials (read, parse and check every partial) + BuildSweepReport
// (cell statistics, runs.csv, report.json). Writing the partials is set-up, not timed.
#include <benchmark/benchmark.h>
#include <unistd.h>

#include <filesystem>

#include "evaluation/sweep/sweep_grid.h"
#include "evaluation/sweep/sweep_partial.h"
#include "evaluation/sweep/sweep_report.h"

namespace fs = std::filesystem;

namespace mavloc {
namespace {

constexpr size_t kUnits = 10000;

SweepGrid Grid() {
  SweepGrid grid;
  grid.scenarios = {"tag-arena-hover"};
  for (uint64_t s = 1; s <= kUnits; ++s) grid.seeds.push_back(s);
  grid.estimators = {"tag-pnp", "smoother"};
  return grid;
}

nlohmann::json FakeUnit(const SweepGrid& grid, size_t index) {
  const SweepUnit unit = SweepUnitAt(grid, index);
  nlohmann::json estimators = nlohmann::json::array();
  for (const auto& name : grid.estimators) {
    nlohmann::json row = {{"name", name}, {"ran", true}};
    const double x = 1e-3 * (1.0 + static_cast<double>(index % 97) / 97.0);
    row["metrics"]["ate_rmse"] = x;
    row["units"]["ate_rmse"] = "m";
    row["metrics"]["ate_rotation_rmse"] = 10.0 * x;
    row["units"]["ate_rotation_rmse"] = "deg";
    for (const char* q : {"x", "y", "z", "roll", "pitch", "yaw"}) {
      row["metrics"][std::string(q) + ".mean_abs"] = 0.8 * x;
      row["metrics"][std::string(q) + ".rmse"] = x;
      row["units"][std::string(q) + ".mean_abs"] = "m";
      row["units"][std::string(q) + ".rmse"] = "m";
    }
    row["metrics"]["failures"] = 0.0;
    row["units"]["failures"] = "frames";
    estimators.push_back(row);
  }
  return {{"index", index},
          {"scenario", unit.scenario},
          {"seed", unit.seed},
          {"settings", unit.settings},
          {"estimators", estimators}};
}

void BM_MergePartials(benchmark::State& state) {
  const int shards = static_cast<int>(state.range(0));
  const SweepGrid grid = Grid();
  const std::string dir =
      (fs::temp_directory_path() / ("mavloc_sweep_merge_bench_" + std::to_string(::getpid())))
          .string();
  fs::remove_all(dir);
  uintmax_t bytes = 0;
  for (int i = 1; i <= shards; ++i) {
    std::vector<nlohmann::json> units;
    for (const size_t k : ShardUnitIndices(kUnits, {i, shards})) units.push_back(FakeUnit(grid, k));
    bytes += fs::file_size(WritePartial(dir, grid, {i, shards}, units));
  }
  size_t report_bytes = 0;
  for (auto _ : state) {
    const MergedSweep merged = MergePartials({dir});
    const auto files = BuildSweepReport(merged.grid, merged.fingerprint, merged.units);
    report_bytes = 0;
    for (const auto& [name, text] : files) report_bytes += text.size();
    benchmark::DoNotOptimize(report_bytes);
  }
  state.counters["partials"] = shards;
  state.counters["partial_MB"] = static_cast<double>(bytes) / 1e6;
  state.counters["report_MB"] = static_cast<double>(report_bytes) / 1e6;
  fs::remove_all(dir);
}
BENCHMARK(BM_MergePartials)->Arg(10000)->Arg(100)->Unit(benchmark::kMillisecond)->Iterations(1);

}  // namespace
}  // namespace mavloc
