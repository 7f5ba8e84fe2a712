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

namespace mavloc {

void WriteReportFolder(const std::string& folder, const ReportFiles& files) {
  std::error_code error;
  CreateOutputDirectories(folder, error);
  if (error || !std::filesystem::is_directory(folder))
    throw InputError(folder, 0, "",
                     "cannot create report folder" + (error ? ": " + error.message() : ""));
  const auto path = [&](const std::string& name) {
    return (std::filesystem::path(folder) / name).string();
  };
  for (const auto& [name, contents] : files.extra) WriteFileAtomically(path(name), contents);
  WriteFileAtomically(path("report.json"), files.json.dump(2) + "\n");
  WriteFileAtomically(path("report.md"), files.markdown);
}

std::map<std::string, std::string> ComparisonTrajectoryFiles(
    const Dataset& dataset, const std::vector<EstimatorEvaluation>& evaluations) {
  std::map<std::string, std::string> files;
  if (!dataset.ground_truth.empty()) {
    std::vector<StampedPose> truth;
    truth.reserve(dataset.ground_truth.size());
    for (const auto& state : dataset.ground_truth) truth.push_back({state.t_ns, state.T_W_B});
    files["truth.tum"] = TumTrajectoryText(truth);
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
    files["estimate_" + name + ".tum"] = TumTrajectoryText(poses);
  }
  return files;
}

std::string MarkdownTable(const std::vector<std::string>& header,
                          const std::vector<std::vector<std::string>>& rows) {
  std::string text = "|";
  for (const auto& h : header) text += " " + h + " |";
  text += "\n|";
  for (size_t k = 0; k < header.size(); ++k) text += k == 0 ? " --- |" : " ---: |";
  text += "\n";
  for (const auto& row : rows) {
    text += "|";
    for (const auto& cell : row) text += " " + cell + " |";
    text += "\n";
  }
  return text;
}

std::string FormatNumber(double value, int digits) {
  if (!std::isfinite(value)) return "-";
  return fmt::format("{:.{}f}", value, digits);
}

}  // namespace mavloc
