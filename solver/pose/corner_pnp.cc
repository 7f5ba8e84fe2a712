#include "solver/pose/corner_pnp.h"

#include <Eigen/SVD>
#include <cmath>
#include <limits>
#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
#include <opencv2/core/eigen.hpp>

#include "core/tag_geometry.h"

namespace mavloc {

namespace {

CornerPnpResult PnpFailure(std::string reason) {
  CornerPnpResult result;
  result.reason = std::move(reason);
  return result;
}

// Largest distance of a point from the least-squares plane of the points.
double PlanarityResidual(const std::vector<Eigen::Vector3d>& X) {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& x : X) mean += x;
  mean /= static_cast<double>(X.size());
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (const auto& x : X) scatter += (x - mean) * (x - mean).transpose();
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(scatter, Eigen::ComputeFullU);
  const Eigen::Vector3d normal = svd.matrixU().col(2);
  double worst = 0.0;
  for (const auto& x : X) worst = std::max(worst, std::abs(normal.dot(x - mean)));
  return worst;
}

Pose PoseFromRvecTvec(const cv::Mat& rvec, const cv::Mat& tvec) {
  cv::Mat R_cv;
  cv::Rodrigues(rvec, R_cv);
  Eigen::Matrix3d R_C_W;
  cv::cv2eigen(R_cv, R_C_W);
  Eigen::Vector3d t_C_W;
  cv::cv2eigen(tvec, t_C_W);
  return Pose(Eigen::Quaterniond(R_C_W).normalized(), t_C_W);  // T_C_W
}

double RmsReprojection(const Pose& T_C_W, const std::vector<Eigen::Vector3d>& X_W,
                       const std::vector<Eigen::Vector2d>& uv, const Eigen::Matrix3d& K) {
  double sum = 0.0;
  for (size_t i = 0; i < X_W.size(); ++i) {
    const Eigen::Vector3d p_C = T_C_W * X_W[i];
    if (p_C.z() <= 0.0) return std::numeric_limits<double>::infinity();
    const Eigen::Vector3d h = K * (p_C / p_C.z());
    sum += (h.head<2>() - uv[i]).squaredNorm();
  }
  return std::sqrt(sum / static_cast<double>(X_W.size()));
}

}  // namespace

CornerPnpResult CornerPnpFromCorrespondences(const std::vector<Eigen::Vector3d>& X_W,
                                             const std::vector<Eigen::Vector2d>& uv_ideal,
                                             const CameraSensor& camera,
                                             const CornerPnpOptions& options) {
  if (X_W.size() != uv_ideal.size()) return PnpFailure("point and pixel counts differ");
  if (X_W.size() < 4) return PnpFailure("fewer than 4 corners");

  std::vector<cv::Point3d> object;
  std::vector<cv::Point2d> image;
  object.reserve(X_W.size());
  image.reserve(X_W.size());
  for (size_t i = 0; i < X_W.size(); ++i) {
    object.emplace_back(X_W[i].x(), X_W[i].y(), X_W[i].z());
    image.emplace_back(uv_ideal[i].x(), uv_ideal[i].y());
  }
  const Eigen::Matrix3d K = camera.model.K();
  cv::Mat K_cv;
  cv::eigen2cv(K, K_cv);

  const bool coplanar = PlanarityResidual(X_W) <= options.coplanar_tolerance_m;
  std::vector<cv::Mat> rvecs, tvecs;
  int count = 0;
  try {
    if (coplanar) {
      count = cv::solvePnPGeneric(object, image, K_cv, cv::noArray(), rvecs, tvecs, false,
                                  cv::SOLVEPNP_IPPE);
    }
    if (count == 0) {
      count = cv::solvePnPGeneric(object, image, K_cv, cv::noArray(), rvecs, tvecs, false,
                                  cv::SOLVEPNP_SQPNP);
    }
  } catch (const cv::Exception& e) {
    return PnpFailure(std::string("solvePnP failed: ") + e.what());
  }
  if (count == 0) return PnpFailure("solvePnP found no pose");

  // Best candidate by reprojection error (IPPE gives the two planar candidates).
  std::vector<double> rms(count);
  int best = 0;
  for (int i = 0; i < count; ++i) {
    rms[i] = RmsReprojection(PoseFromRvecTvec(rvecs[i], tvecs[i]), X_W, uv_ideal, K);
    if (rms[i] < rms[best]) best = i;
  }
  cv::Mat rvec = rvecs[best].clone();
  cv::Mat tvec = tvecs[best].clone();
  if (options.refine) {
    try {
      cv::solvePnPRefineLM(object, image, K_cv, cv::noArray(), rvec, tvec);
    } catch (const cv::Exception& e) {
      return PnpFailure(std::string("solvePnPRefineLM failed: ") + e.what());
    }
  }
  const Pose T_C_W = PoseFromRvecTvec(rvec, tvec);
  if (!T_C_W.p.allFinite() || !T_C_W.q.coeffs().allFinite()) return PnpFailure("non-finite pose");

  CornerPnpResult result;
  result.ok = true;
  result.num_corners = static_cast<int>(X_W.size());
  result.T_W_C = T_C_W.Inverse();
  result.T_W_B = result.T_W_C * camera.T_B_C.Inverse();
  result.rms_reprojection_px = RmsReprojection(T_C_W, X_W, uv_ideal, K);
  result.ambiguity_rms_px = std::numeric_limits<double>::quiet_NaN();
  if (coplanar && count >= 2) result.ambiguity_rms_px = rms[1 - best];
  return result;
}

CornerPnpResult CornerPnp(const std::vector<TagObservation>& observations,
                          const std::map<int, TagInfo>& tags, const CameraSensor& camera,
                          const CornerPnpOptions& options) {
  std::vector<Eigen::Vector3d> X_W;
  std::vector<Eigen::Vector2d> uv_ideal;
  int num_tags = 0;
  for (const auto& observation : observations) {
    const auto it = tags.find(observation.tag_id);
    if (it == tags.end()) continue;
    ++num_tags;
    const auto corners_W = TagCornersInWorld(it->second);
    for (int k = 0; k < 4; ++k) {
      const auto xy = camera.model.PixelToNormalized(observation.corners_px[k]);
      if (!xy) continue;
      X_W.push_back(corners_W[k]);
      uv_ideal.push_back(Eigen::Vector2d(camera.model.fu() * xy->x() + camera.model.cu(),
                                         camera.model.fv() * xy->y() + camera.model.cv()));
    }
  }
  if (num_tags == 0) return PnpFailure("no observed tag is in the map");
  CornerPnpResult result = CornerPnpFromCorrespondences(X_W, uv_ideal, camera, options);
  result.num_tags = num_tags;
  return result;
}

}  // namespace mavloc
