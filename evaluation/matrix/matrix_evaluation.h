// Many estimators on many sequences, several runs each: the table evo leaves to a user's script.
//
// Folder layout (rpg_trajectory_evaluation's, which users of rpg and many VIO papers already
// have): ROOT is a platform folder; each subfolder of ROOT is an estimator; each of its subfolders
// is one sequence, named <platform>_<estimator>_<sequence> (or just <sequence>), holding
//   stamped_groundtruth.txt                    the sequence's ground truth
//   stamped_traj_estimate.txt                  one run, or
//   stamped_traj_estimate0.txt, ...1.txt, ...  several runs
// Any trajectory format mavloc reads is accepted under these names (TUM in rpg's files).
//
// Per cell (estimator, sequence): the APE translation RMSE of every run (one trajectory-error
// engine, trajectory_evaluation.h, with the given protocol), its mean and sample standard
// deviation over runs and a bootstrap 95 % interval of that mean (matrix_statistics.h, seeded);
// the relative errors over the same sub-trajectory lengths for every estimator of a sequence
// (rpg's 10..50 % of the first ground truth's path length). Per pair of estimators: the Wilcoxon
// signed-rank test of their per-sequence mean RMSE over the sequences both ran.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/folder_walk.h"
#include "evaluation/matrix/matrix_statistics.h"
#include "evaluation/report/report.h"
#include "evaluation/trajectory_evaluation.h"

namespace mavloc {

struct MatrixCellFiles {
  std::string estimator, sequence;
  std::string truth_path;
  std::vector<std::string> run_paths;  // in run order
};

struct RpgLayout {
  std::vector<MatrixCellFiles> cells;  // sorted by estimator then sequence
  // Every entry of the walk that is not used, with the reason: files beside the estimator and
  // sequence folders, files of a sequence folder that are not part of the layout, a run number
  // beyond 999999, a run number given twice (run1 and run01), an unnumbered run beside numbered
  // ones. The report lists them.
  std::vector<SkippedFile> skipped;
};

// The cells found under `root` (layout above). Throws InputError naming the path when the layout
// holds no cell, a sequence folder has no ground truth or no estimate, a truth or run name is not
// a regular file (a named pipe, a folder) or an entry is a loop of symbolic links.
RpgLayout FindRpgLayout(const std::string& root);

struct MatrixRun {
  std::string path;
  size_t pairs = 0;
  double ate_rmse_m = 0.0;
  double ate_rotation_rmse_rad = 0.0;
  std::vector<RelativeErrorAtLength> relative;
};

struct MatrixCell {
  std::string estimator, sequence;
  std::vector<MatrixRun> runs;
  double mean_m = 0.0, std_m = 0.0;  // over runs (sample std, 0 for one run)
  ConfidenceInterval interval;       // bootstrap interval of the mean
};

struct PairedComparison {
  std::string a, b;
  int sequences = 0;    // sequences both ran
  int a_better = 0;     // sequences where a's mean RMSE is lower
  SignedRankTest test;  // of mean(a) - mean(b)
};

struct MatrixResult {
  std::vector<std::string> estimators, sequences;  // sorted
  std::vector<MatrixCell> cells;
  std::vector<PairedComparison> pairs;
  EvaluationProtocol protocol;
  uint64_t seed = 1;
  std::vector<SkippedFile> skipped;  // from the layout
};

MatrixResult EvaluateMatrix(const RpgLayout& layout, const EvaluationProtocol& protocol,
                            uint64_t seed);

// The Report (kind "matrix"): the cells as a table per statistic, the paired tests as a table,
// one estimator result per estimator (its per-sequence RMSE statistics over runs), and the files
// matrix.tex (best mean per sequence in bold), runs.csv and relative_errors.csv (for the grouped
// boxplots).
Report MatrixReport(const MatrixResult& result);

}  // namespace mavloc
