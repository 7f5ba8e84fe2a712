#include "evaluation/report_writer.h"

#include <fmt/format.h>

#include <cctype>
#include <cmath>
#include <filesystem>

#include "core/atomic_file.h"
#include "core/errors.h"
#include "core/interrupt.h"
#include "datasets/io/tum_io.h"
#include "evaluation/comparison.h"
#include "evaluation/report/report_folder.h"
#include "evaluation/report/report_markdown.h"

namespace mavloc {

size_t RowStride(size_t rows, size_t max_rows) {
  if (max_rows == 0 || rows <= max_rows) return 1;
  return (rows + max_rows - 1) / max_rows;
}

std::map<std::string, std::string> ComparisonTrajectoryFiles(
    const Dataset& dataset, const std::vector<EstimatorEvaluation>& evaluations, size_t max_rows,
    std::map<std::string, size_t>* strides) {
  std::map<std::string, std::string> files;
  // Every k-th pose of `poses` (all of them when they fit), k noted for the report.
  const auto thinned = [&](const std::string& name, std::vector<StampedPose> poses) {
    const size_t stride = RowStride(poses.size(), max_rows);
    if (stride > 1) {
      size_t kept = 0;
      for (size_t i = 0; i < poses.size(); i += stride) poses[kept++] = poses[i];
      poses.resize(kept);
      if (strides) (*strides)[name] = stride;
    }
    files[name] = TumTrajectoryText(poses);
  };
  if (!dataset.ground_truth.empty()) {
    std::vector<StampedPose> truth;
    truth.reserve(dataset.ground_truth.size());
    for (const auto& state : dataset.ground_truth) truth.push_back({state.t_ns, state.T_W_B});
    thinned("truth.tum", std::move(truth));
  }
  for (const auto& evaluation : evaluations) {
    if (!evaluation.ran || evaluation.estimate.poses.empty()) continue;
    const Similarity S = evaluation.ate ? evaluation.ate->alignment : Similarity{};
    std::vector<StampedPose> poses;
    poses.reserve(evaluation.estimate.poses.size());
    for (const auto& pose : evaluation.estimate.poses)
      poses.push_back(
          {pose.t_ns, Pose(Eigen::Matrix3d(S.R * pose.T_W_B.R()), S.Apply(pose.T_W_B.p))});
    std::string name = evaluation.estimator;
    for (char& c : name)
      if (!std::isalnum(static_cast<unsigned char>(c)) && c != '-' && c != '.') c = '-';
    thinned("estimate_" + name + ".tum", std::move(poses));
  }
  return files;
}

std::string MarkdownTable(const std::vector<std::string>& header,
                          const std::vector<std::vector<std::string>>& rows) {
  return MarkdownTableOf(header, rows);
}

std::string FormatNumber(double value, int digits) {
  if (!std::isfinite(value)) return "-";
  return fmt::format("{:.{}f}", value, digits);
}

}  // namespace mavloc
