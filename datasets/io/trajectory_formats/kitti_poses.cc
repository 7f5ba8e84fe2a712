#include "datasets/io/trajectory_formats/kitti_poses.h"

#include <fmt/format.h>
#include <Eigen/SVD>
#include <algorithm>

#include "core/errors.h"
#include "core/number_text.h"
#include "datasets/io/trajectory_formats/trajectory_format.h"
#include "datasets/io/trajectory_formats/trajectory_stamps.h"

namespace mavloc {

namespace {

// r11 r12 r13 tx r21 r22 r23 ty r31 r32 r33 tz (row-major 3x4).
std::string KittiFieldName(size_t k) {
  const size_t row = k / 4, col = k % 4;
  if (col == 3) return std::string("t") + "xyz"[row];
  return fmt::format("r{}{}", row + 1, col + 1);
}

}  // namespace

KittiRowsResult ParseKittiRows(const TrajectoryText& text) {
  if (text.rows.empty()) throw InputError(text.path, 0, "", "file has no data rows");
  KittiRowsResult result;
  result.poses.reserve(text.rows.size());
  result.lines.reserve(text.rows.size());
  std::vector<std::string_view> fields;
  for (const TrajectoryRow& row : text.rows) {
    text.Fields(row, &fields);
    if (fields.size() != 12)
      throw InputError(
          text.path, row.line, fields.size() < 12 ? KittiFieldName(fields.size()) : "column 13",
          fmt::format("expected 12 fields (KITTI: 3x4 pose, row-major), found {}", fields.size()));
    Eigen::Matrix<double, 3, 4> T;
    for (size_t k = 0; k < 12; ++k) {
      const ParsedNumber<double> value = ParseDoubleText(fields[k]);
      if (!value.ok())
        throw InputError(text.path, row.line, KittiFieldName(k),
                         DescribeNumberText(fields[k], value, "a finite number"));
      T(k / 4, k % 4) = value.value;
    }
    const Eigen::Matrix3d R = T.leftCols<3>();
    const double error = (R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
    if (error > kQuaternionNormTolerance || R.determinant() <= 0.0)
      throw InputError(text.path, row.line, "r11",
                       fmt::format("the 3x3 block is not a rotation (max |R^T R - I| = {:.3g}, "
                                   "det = {:.3g}; accepted up to {})",
                                   error, R.determinant(), kQuaternionNormTolerance));
    Eigen::Matrix3d R_W_C = R;
    if (error > 1e-6) {
      // Nearest rotation in the Frobenius norm: U V^T of the SVD (det > 0 checked above).
      const Eigen::JacobiSVD<Eigen::Matrix3d> svd(R, Eigen::ComputeFullU | Eigen::ComputeFullV);
      R_W_C = svd.matrixU() * svd.matrixV().transpose();
      ++result.rotations_projected;
    }
    result.max_orthonormality_error = std::max(result.max_orthonormality_error, error);
    Pose pose(R_W_C, Eigen::Vector3d(T.col(3)));
    pose.q.normalize();
    result.poses.push_back(pose);
    result.lines.push_back(row.line);
  }
  return result;
}

KittiTimes ReadKittiTimes(const std::string& path) {
  const TrajectoryText text = ReadTrajectoryText(path);
  if (text.rows.empty()) throw InputError(path, 0, "", "times file has no data rows");
  KittiTimes times;
  times.t_ns.reserve(text.rows.size());
  times.lines.reserve(text.rows.size());
  std::vector<std::string_view> fields;
  for (const TrajectoryRow& row : text.rows) {
    text.Fields(row, &fields);
    if (fields.size() != 1)
      throw InputError(
          path, row.line, "column 2",
          fmt::format("expected 1 field (one stamp [s] per line), found {}", fields.size()));
    TimeNs t = 0;
    if (!ParseSecondsAsNs(fields[0], &t))
      throw InputError(path, row.line, "timestamp",
                       DescribeBadStamp(std::string(fields[0]), true, "KITTI times file"));
    times.t_ns.push_back(t);
    times.lines.push_back(row.line);
  }
  return times;
}

std::string KittiPosesText(const std::vector<StampedPose>& poses) {
  std::string text;
  for (const auto& pose : poses) {
    const Eigen::Matrix3d R = pose.T_W_B.R();
    const Eigen::Vector3d& p = pose.T_W_B.p;
    for (int r = 0; r < 3; ++r) {
      text += fmt::format("{:.17g} {:.17g} {:.17g} {:.17g}", R(r, 0), R(r, 1), R(r, 2), p(r));
      text += r < 2 ? " " : "\n";
    }
  }
  return text;
}

std::string KittiTimesText(const std::vector<StampedPose>& poses) {
  std::string text;
  for (const auto& pose : poses)
    text += fmt::format("{}.{:09d}\n", pose.t_ns / kNsPerSecond, pose.t_ns % kNsPerSecond);
  return text;
}

}  // namespace mavloc
