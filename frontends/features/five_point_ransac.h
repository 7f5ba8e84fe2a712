// The baseline for two_point_ransac.h: OpenCV's cv::findEssentialMat (Nister's 5-point solver,
// D. Nister, "An efficient solution to the five-point relative pose problem", PAMI 2004, inside
// OpenCV's RANSAC) on the same matches, with the same options and result, for frames whose
// rotation is not known or to measure what the gyro buys.
//
// The bearings are passed as normalized image coordinates (x/z, y/z) with the identity camera
// matrix (focal 1, principal point 0). OpenCV then keeps a match when the Sampson distance of
// x1^T E x0 on the normalized plane, e^2 / ((E x0)_1^2 + (E x0)_2^2 + (E^T x1)_1^2 +
// (E^T x1)_2^2), is at most threshold_rad^2: at focal 1 one unit of the plane is one radian at the
// image centre, so the same threshold_rad (pixels / focal length) gates both methods. Off the
// axis a fixed angle spans more of the plane (up to 1 / cos^2 of the off-axis angle: 1.26 at
// 27 deg), so there the 5-point's gate is slightly tighter in angle than the 2-point's.
//
// R_C1_C0 and t_C1_C0 (unit; C0's centre in C1) come from cv::recoverPose on the E found (its
// cheirality test picks one of the four decompositions); the inlier mask is findEssentialMat's
// (recoverPose's own mask is not applied). With exactly 5 matches OpenCV returns every solution
// of the minimal problem; the one recoverPose puts the most points in front of is kept.
//
// What the baseline does not do: OpenCV's RANSAC scores by inlier count with no cheirality test
// and no refit on the inliers, its generator has a fixed seed (options.seed is ignored) and it
// does not report how many samples it drew (result.iterations is the lower bound that its
// stopping rule implies); it has no pure-rotation or degeneracy test (an essential matrix of a
// pure rotation is arbitrary: status kOk with a meaningless t). num_parallax_inliers and
// direction_uncertainty_rad stay zero. Bearings at or behind the image plane (z <= 0) cannot be
// normalized and are outliers.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "frontends/features/two_point_ransac.h"

namespace mavloc {

// Fewer than 5 usable matches: kTooFewMatches; no essential matrix found: kNoConsensus.
EpipolarRansacResult FivePointRansac(const std::vector<Eigen::Vector3d>& f_C0,
                                     const std::vector<Eigen::Vector3d>& f_C1,
                                     const EpipolarRansacOptions& options = {});

}  // namespace mavloc
