#include "frontends/features/five_point_ransac.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>

namespace mavloc {

namespace {

// OpenCV's stopping rule for the final consensus: its RANSAC loop runs while the sample index is
// below min(max_iterations, round(log(1 - p) / log(1 - w^5))), that count being lowered each time
// the best model improves, so at least this many samples were drawn (one when every match agrees).
int FivePointIterationsLowerBound(double confidence, double inlier_share, int max_iterations) {
  const double all_inlier = std::pow(std::clamp(inlier_share, 0.0, 1.0), 5);
  if (all_inlier >= 1.0) return 1;
  if (all_inlier <= 0.0) return max_iterations;
  const double n = std::log(1.0 - confidence) / std::log1p(-all_inlier);
  if (!(n < static_cast<double>(max_iterations))) return max_iterations;
  return std::max(1, static_cast<int>(std::lround(n)));
}

}  // namespace

EpipolarRansacResult FivePointRansac(const std::vector<Eigen::Vector3d>& f_C0,
                                     const std::vector<Eigen::Vector3d>& f_C1,
                                     const EpipolarRansacOptions& options) {
  EpipolarRansacResult out;
  if (!StartEpipolarResult(f_C0, f_C1, &out)) return out;

  // Normalized image coordinates of the usable matches (finite, in front of the image plane).
  std::vector<size_t> index;
  std::vector<cv::Point2d> x0, x1;
  for (size_t i = 0; i < f_C0.size(); ++i) {
    const Eigen::Vector3d& a = f_C0[i];
    const Eigen::Vector3d& b = f_C1[i];
    if (!a.allFinite() || !b.allFinite() || !(a.z() > 1e-9 * a.norm()) ||
        !(b.z() > 1e-9 * b.norm()))
      continue;
    index.push_back(i);
    x0.emplace_back(a.x() / a.z(), a.y() / a.z());
    x1.emplace_back(b.x() / b.z(), b.y() / b.z());
  }
  const int count = static_cast<int>(index.size());
  if (count < 5) {
    out.status = EpipolarRansacStatus::kTooFewMatches;
    out.reason = fmt::format(
        "{} usable matches (finite, in front of the image plane); the 5-point RANSAC needs at "
        "least 5",
        count);
    return out;
  }

  const cv::Mat K = cv::Mat::eye(3, 3, CV_64F);
  cv::Mat mask;
  const cv::Mat E = cv::findEssentialMat(x0, x1, K, cv::RANSAC, options.confidence,
                                         options.threshold_rad, options.max_iterations, mask);
  if (E.empty() || E.rows % 3 != 0 || E.cols != 3 || mask.total() != index.size()) {
    out.status = EpipolarRansacStatus::kNoConsensus;
    out.reason = "cv::findEssentialMat found no essential matrix";
    out.iterations = options.max_iterations;
    return out;
  }

  // The decomposition with the most points in front (one candidate, or up to 10 for 5 matches).
  int best_in_front = -1;
  cv::Mat best_R, best_t;
  for (int k = 0; k < E.rows / 3; ++k) {
    cv::Mat R, t;
    cv::Mat cheirality = mask.clone();
    const int in_front = cv::recoverPose(E.rowRange(3 * k, 3 * k + 3), x0, x1, K, R, t, cheirality);
    if (in_front > best_in_front) {
      best_in_front = in_front;
      best_R = R;
      best_t = t;
    }
  }

  const uchar* m = mask.ptr<uchar>();
  for (int i = 0; i < count; ++i) {
    if (!m[i]) continue;
    out.inlier[index[i]] = true;
    ++out.num_inliers;
  }
  out.iterations = FivePointIterationsLowerBound(
      options.confidence, static_cast<double>(out.num_inliers) / count, options.max_iterations);
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) out.R_C1_C0(r, c) = best_R.at<double>(r, c);
    out.t_C1_C0[r] = best_t.at<double>(r, 0);
  }
  out.t_C1_C0.normalize();
  out.status = EpipolarRansacStatus::kOk;
  return out;
}

}  // namespace mavloc
