// Shards of a sweep and their partial results (docs/commands/sweep.md, "Shards and the exact
// merge").
//
// Shard I of N (1-based) holds the units with index % N == I - 1 (strided rather than contiguous
// blocks, so that every shard gets a similar mix of scenarios and settings and the shards take
// similar time). A shard writes one partial file, "partial-I-of-N.json", atomically
// (core/atomic_file.h: a temporary name renamed when complete), holding
//   {"format": "mavloc-sweep-partial 1", "grid": canonical grid, "grid_hash", "executable",
//    "fingerprint", "shard": I, "shards": N, "units": [unit results by index], "complete": true}
// so an interrupted shard leaves at most "partial-I-of-N.json.tmp-PID", never the final name, and
// a file without the complete marker (or cut short) is refused.
//
// The merge reads partials in any order and checks: every file parses and is complete, all carry
// the same fingerprint (same grid, same mavloc build) and shard count, no shard appears twice,
// none is missing, each holds exactly its shard's units, and each unit is the grid's unit of its
// index (scenario, seed, settings) with one row per estimator of the grid, in the grid's order.
// Any failure throws InputError naming the partial, the unit and the field (the CLI exits with 2).
// A unit that lacks a metric others have is merged: the report names the short cells
// (sweep_report.h).
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/folder_walk.h"
#include "evaluation/sweep/sweep_grid.h"

namespace mavloc {

struct ShardSpec {
  int shard = 1;   // 1-based
  int shards = 1;  // N
};

// "I/N" with 1 <= I <= N; throws InputError.
ShardSpec ParseShardSpec(const std::string& text);
std::vector<size_t> ShardUnitIndices(size_t unit_count, const ShardSpec& spec);
std::string PartialFileName(const ShardSpec& spec);  // "partial-I-of-N.json"

// Writes folder/PartialFileName(spec) atomically (creating folder); returns its path.
std::string WritePartial(const std::string& folder, const SweepGrid& grid, const ShardSpec& spec,
                         const std::vector<nlohmann::json>& units);

struct MergedSweep {
  SweepGrid grid;
  std::string fingerprint;
  std::vector<nlohmann::json> units;  // every unit, by index
  // The entries of the input folders that are not partials (nor an interrupted shard's temporary
  // file), each with the reason: the merge names them (core/folder_walk.h).
  std::vector<SkippedFile> skipped;
};

// `inputs`: partial files and/or folders (each folder contributes its partial-*-of-*.json files;
// the folders are walked with ListFolder, a partial that is not a regular file is refused).
MergedSweep MergePartials(const std::vector<std::string>& inputs);

// Which shards of N have a complete partial with this fingerprint in `folder` (1-based flags,
// index 0 unused), without throwing for bad files (they count as absent).
std::vector<bool> CompleteShards(const std::string& folder, int shards,
                                 const std::string& fingerprint);

}  // namespace mavloc
