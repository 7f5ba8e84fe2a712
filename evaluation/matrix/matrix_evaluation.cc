#include "evaluation/matrix/matrix_evaluation.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <regex>
#include <utility>

#include "core/errors.h"
#include "core/folder_walk.h"
#include "core/input_file.h"
#include "datasets/io/trajectory_formats/trajectory_format.h"
#include "evaluation/relative_error.h"

namespace mavloc {
namespace {

namespace fs = std::filesystem;

// An entry that must be a file or a folder and is neither readable one (a loop of links, a link to
// nothing): refused, naming it.
void RefuseBroken(const FolderEntry& entry) {
  if (!entry.problem.empty()) throw InputError(entry.path, 0, "", entry.problem);
}

// The subfolders of `folder`; every other entry is listed in `skipped` with `what` it is not.
std::vector<FolderEntry> Subfolders(const std::string& folder, const std::string& what,
                                    std::vector<SkippedFile>* skipped) {
  std::vector<FolderEntry> out;
  for (const FolderEntry& entry : ListFolder(folder)) {
    RefuseBroken(entry);
    if (entry.is_folder())
      out.push_back(entry);
    else
      skipped->push_back({entry.path, "not " + what + " (a file)"});
  }
  return out;
}

constexpr const char* kTruthName = "stamped_groundtruth.txt";
constexpr const char* kSingleRunName = "stamped_traj_estimate.txt";
constexpr int kMaxRunNumber = 999999;

// The ground truth and runs of one sequence folder: stamped_traj_estimate.txt, or
// stamped_traj_estimate<k>.txt in the order of k. Every other entry is listed in `skipped` with
// the reason; a truth or run name that is not a regular file (a named pipe) is refused.
void ReadSequenceFolder(const std::string& folder, MatrixCellFiles* cell,
                        std::vector<SkippedFile>* skipped) {
  const std::regex numbered(R"(stamped_traj_estimate([0-9]+)\.txt)");
  std::map<long, FolderEntry> by_index;
  const FolderEntry* single = nullptr;
  const std::vector<FolderEntry> entries = ListFolder(folder);
  for (const FolderEntry& entry : entries) {
    std::smatch match;
    const bool is_truth = entry.name == kTruthName;
    const bool is_single = entry.name == kSingleRunName;
    const bool is_numbered = std::regex_match(entry.name, match, numbered);
    if (!is_truth && !is_single && !is_numbered) {
      skipped->push_back({entry.path, "not a file of the rpg layout (" + std::string(kTruthName) +
                                          ", stamped_traj_estimate[<k>].txt)"});
      continue;
    }
    RefuseBroken(entry);
    RequireRegularFile(entry.path);  // a pipe named like a run would block the reader
    if (is_truth) {
      cell->truth_path = entry.path;
    } else if (is_single) {
      single = &entry;
    } else if (match[1].str().size() > 6 || std::stol(match[1].str()) > kMaxRunNumber) {
      skipped->push_back(
          {entry.path, fmt::format("run number beyond {} (stamped_traj_estimate<k>.txt, k from 0 "
                                   "to {})",
                                   kMaxRunNumber, kMaxRunNumber)});
    } else {
      const long k = std::stol(match[1].str());
      const auto [at, added] = by_index.emplace(k, entry);
      if (!added)
        skipped->push_back(
            {entry.path, fmt::format("run {} again (already {})", k, at->second.name)});
    }
  }
  for (const auto& [index, entry] : by_index) cell->run_paths.push_back(entry.path);
  if (single && cell->run_paths.empty())
    cell->run_paths.push_back(single->path);
  else if (single)
    skipped->push_back({single->path,
                        "an unnumbered run beside numbered ones: only stamped_traj_estimate<k>.txt "
                        "are used"});
}

double Mean(const std::vector<double>& v) {
  double sum = 0.0;
  for (const double x : v) sum += x;
  return v.empty() ? std::nan("") : sum / static_cast<double>(v.size());
}

double SampleStd(const std::vector<double>& v) {
  if (v.size() < 2) return 0.0;
  const double m = Mean(v);
  double squares = 0.0;
  for (const double x : v) squares += (x - m) * (x - m);
  return std::sqrt(squares / static_cast<double>(v.size() - 1));
}

// A seed per cell from the report's seed and the cell's position, so that every cell's interval
// is reproducible on its own.
uint64_t CellSeed(uint64_t seed, size_t index) {
  return seed * 0x9E3779B97F4A7C15ULL + static_cast<uint64_t>(index) + 1;
}

MatrixRun EvaluateRun(const std::string& path, const std::vector<StampedPose>& truth,
                      const EvaluationProtocol& protocol) {
  const std::vector<StampedPose> estimate = std::move(ReadTrajectory(path).poses);
  std::string why;
  const auto result = EvaluateTrajectory(estimate, truth, protocol, &why);
  if (!result)
    throw InputError(path, 0, "", "cannot be evaluated against the ground truth: " + why);
  MatrixRun run;
  run.path = path;
  run.pairs = result->pair_count;
  run.ate_rmse_m = result->ape_translation_m.rmse;
  run.ate_rotation_rmse_rad = result->ape_rotation_deg.rmse * M_PI / 180.0;
  run.relative = result->relative;
  return run;
}

}  // namespace

RpgLayout FindRpgLayout(const std::string& root) {
  RequireFolder(root);
  const std::string platform = fs::path(root).lexically_normal().filename().string() == ""
                                   ? fs::path(root).parent_path().filename().string()
                                   : fs::path(root).lexically_normal().filename().string();
  RpgLayout layout;
  for (const FolderEntry& estimator_dir :
       Subfolders(root, "an estimator folder", &layout.skipped)) {
    const std::string estimator = estimator_dir.name;
    const std::string prefix = platform + "_" + estimator + "_";
    for (const FolderEntry& sequence_dir :
         Subfolders(estimator_dir.path, "a sequence folder", &layout.skipped)) {
      std::string sequence = sequence_dir.name;
      if (sequence.rfind(prefix, 0) == 0 && sequence.size() > prefix.size())
        sequence = sequence.substr(prefix.size());
      MatrixCellFiles cell{estimator, sequence, "", {}};
      ReadSequenceFolder(sequence_dir.path, &cell, &layout.skipped);
      if (cell.truth_path.empty())
        throw InputError(sequence_dir.path, 0, "",
                         "no stamped_groundtruth.txt (the rpg layout: " + estimator +
                             "/<platform>_<estimator>_<sequence>/stamped_groundtruth.txt)");
      if (cell.run_paths.empty())
        throw InputError(sequence_dir.path, 0, "",
                         "no stamped_traj_estimate.txt or stamped_traj_estimate<k>.txt");
      layout.cells.push_back(std::move(cell));
    }
  }
  if (layout.cells.empty())
    throw InputError(root, 0, "",
                     "no <estimator>/<platform>_<estimator>_<sequence>/ folders (the "
                     "rpg_trajectory_evaluation layout)");
  return layout;
}

MatrixResult EvaluateMatrix(const RpgLayout& layout, const EvaluationProtocol& protocol,
                            uint64_t seed) {
  const std::vector<MatrixCellFiles>& files = layout.cells;
  MatrixResult result;
  result.skipped = layout.skipped;
  result.protocol = protocol;
  result.seed = seed;
  // The relative-error lengths of a sequence come from its first ground truth, so that every
  // estimator's boxes stand at the same lengths.
  std::map<std::string, std::vector<double>> lengths_of_sequence;
  for (const auto& f : files) {
    if (lengths_of_sequence.count(f.sequence)) continue;
    const std::vector<StampedPose> truth = std::move(ReadTrajectory(f.truth_path).poses);
    double path_m = 0.0;
    for (size_t i = 1; i < truth.size(); ++i)
      path_m += (truth[i].T_W_B.p - truth[i - 1].T_W_B.p).norm();
    lengths_of_sequence[f.sequence] =
        protocol.relative_lengths_m.empty()
            ? DefaultRelativeLengths(path_m, protocol.relative_length_fractions)
            : protocol.relative_lengths_m;
  }
  for (size_t index = 0; index < files.size(); ++index) {
    const MatrixCellFiles& f = files[index];
    EvaluationProtocol cell_protocol = protocol;
    cell_protocol.relative_lengths_m = lengths_of_sequence[f.sequence];
    const std::vector<StampedPose> truth = std::move(ReadTrajectory(f.truth_path).poses);
    MatrixCell cell;
    cell.estimator = f.estimator;
    cell.sequence = f.sequence;
    std::vector<double> rmse;
    for (const auto& path : f.run_paths) {
      cell.runs.push_back(EvaluateRun(path, truth, cell_protocol));
      rmse.push_back(cell.runs.back().ate_rmse_m);
    }
    cell.mean_m = Mean(rmse);
    cell.std_m = SampleStd(rmse);
    cell.interval = BootstrapMeanInterval(rmse, CellSeed(seed, index));
    result.cells.push_back(std::move(cell));
    if (std::find(result.estimators.begin(), result.estimators.end(), f.estimator) ==
        result.estimators.end())
      result.estimators.push_back(f.estimator);
    if (std::find(result.sequences.begin(), result.sequences.end(), f.sequence) ==
        result.sequences.end())
      result.sequences.push_back(f.sequence);
  }
  std::sort(result.estimators.begin(), result.estimators.end());
  std::sort(result.sequences.begin(), result.sequences.end());
  auto mean_of = [&](const std::string& e, const std::string& s) -> std::optional<double> {
    for (const auto& c : result.cells)
      if (c.estimator == e && c.sequence == s) return c.mean_m;
    return std::nullopt;
  };
  for (size_t i = 0; i < result.estimators.size(); ++i)
    for (size_t j = i + 1; j < result.estimators.size(); ++j) {
      PairedComparison p;
      p.a = result.estimators[i];
      p.b = result.estimators[j];
      std::vector<double> differences;
      for (const auto& s : result.sequences) {
        const auto a = mean_of(p.a, s), b = mean_of(p.b, s);
        if (!a || !b) continue;
        differences.push_back(*a - *b);
        p.a_better += *a < *b;
      }
      p.sequences = static_cast<int>(differences.size());
      p.test = WilcoxonSignedRank(differences);
      result.pairs.push_back(p);
    }
  return result;
}

}  // namespace mavloc
