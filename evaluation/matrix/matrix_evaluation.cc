#include "evaluation/matrix/matrix_evaluation.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <regex>
#include <utility>

#include "core/errors.h"
#include "datasets/io/trajectory_formats/trajectory_format.h"
#include "evaluation/relative_error.h"

namespace mavloc {
namespace {

namespace fs = std::filesystem;

std::vector<fs::path> SortedSubfolders(const fs::path& folder) {
  std::vector<fs::path> out;
  for (const auto& entry : fs::directory_iterator(folder))
    if (entry.is_directory()) out.push_back(entry.path());
  std::sort(out.begin(), out.end());
  return out;
}

// stamped_traj_estimate.txt, or stamped_traj_estimate<k>.txt in the order of k.
std::vector<std::string> RunFiles(const fs::path& folder) {
  const std::regex numbered(R"(stamped_traj_estimate([0-9]{1,6})\.txt)");
  std::map<int, std::string> by_index;
  for (const auto& entry : fs::directory_iterator(folder)) {
    std::smatch match;
    const std::string name = entry.path().filename().string();
    if (std::regex_match(name, match, numbered))
      by_index[std::stoi(match[1].str())] = entry.path().string();
  }
  std::vector<std::string> runs;
  for (const auto& [index, path] : by_index) runs.push_back(path);
  if (runs.empty() && fs::exists(folder / "stamped_traj_estimate.txt"))
    runs.push_back((folder / "stamped_traj_estimate.txt").string());
  return runs;
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

std::vector<MatrixCellFiles> FindRpgLayout(const std::string& root) {
  if (!fs::is_directory(root)) throw InputError(root, 0, "", "not a folder");
  const std::string platform = fs::path(root).lexically_normal().filename().string() == ""
                                   ? fs::path(root).parent_path().filename().string()
                                   : fs::path(root).lexically_normal().filename().string();
  std::vector<MatrixCellFiles> cells;
  for (const fs::path& estimator_dir : SortedSubfolders(root)) {
    const std::string estimator = estimator_dir.filename().string();
    const std::string prefix = platform + "_" + estimator + "_";
    for (const fs::path& sequence_dir : SortedSubfolders(estimator_dir)) {
      std::string sequence = sequence_dir.filename().string();
      if (sequence.rfind(prefix, 0) == 0 && sequence.size() > prefix.size())
        sequence = sequence.substr(prefix.size());
      MatrixCellFiles cell{estimator, sequence, (sequence_dir / "stamped_groundtruth.txt").string(),
                           RunFiles(sequence_dir)};
      if (!fs::exists(cell.truth_path))
        throw InputError(sequence_dir.string(), 0, "",
                         "no stamped_groundtruth.txt (the rpg layout: " + estimator +
                             "/<platform>_<estimator>_<sequence>/stamped_groundtruth.txt)");
      if (cell.run_paths.empty())
        throw InputError(sequence_dir.string(), 0, "",
                         "no stamped_traj_estimate.txt or stamped_traj_estimate<k>.txt");
      cells.push_back(std::move(cell));
    }
  }
  if (cells.empty())
    throw InputError(root, 0, "",
                     "no <estimator>/<platform>_<estimator>_<sequence>/ folders (the "
                     "rpg_trajectory_evaluation layout)");
  return cells;
}

MatrixResult EvaluateMatrix(const std::vector<MatrixCellFiles>& files,
                            const EvaluationProtocol& protocol, uint64_t seed) {
  MatrixResult result;
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
