// Outlier rejection over a frame pair when the rotation between the frames is known from the gyro:
// the 2-point RANSAC over the translation direction of
//   C. Troiani, A. Martinelli, C. Laugier, D. Scaramuzza, "2-Point-based Outlier Rejection for
//   Camera-IMU Systems with applications to Micro Aerial Vehicles", ICRA 2014.
// The paper is not in ../shared/papers, so its equation numbers are not quoted; the equations
// below are the ones implemented here, derived from the epipolar constraint.
//
// A match is a pair of unit bearings of one point: f0 in camera C0 (previous frame) and f1 in C1
// (current frame), with lambda1 f1 = lambda0 R f0 + t for depths lambda0, lambda1 > 0, where
// R = R_C1_C0 (the gyro's rotation between the frames mapped through the camera extrinsic) and
// t = t_C1_C0 (C0's centre in C1: p_C1 = R_C1_C0 p_C0 + t_C1_C0). With g = R f0:
//
//   (1) epipolar constraint   f1^T [t]x R f0 = 0  <=>  t . n = 0,   n = g x f1
//       Linear in t: each match says t is orthogonal to the normal n of its epipolar plane.
//   (2) minimal solution      t = (n_1 x n_2) / |n_1 x n_2|        (two matches; sign open)
//   (3) error of t            e_t = |t . n| / sqrt(|t x g|^2 + |t x f1|^2)
//       Sampson's first-order distance on the sphere: the smallest angular correction of the two
//       bearings, sqrt(|d0|^2 + |d1|^2), that satisfies (1).
//   (4) error of R alone      e_R = angle(g, f1) / sqrt(2)
//       The same correction for the rotation-only model (no translation, or a point at infinity):
//       both bearings turn by half the angle. e_R is the match's parallax in these units.
//   (5) cheirality            lambda0 = -(t x f1) . n / |n|^2,   lambda1 = -(t x g) . n / |n|^2
//       A match with parallax (e_R > threshold) is an inlier of t when e_t <= threshold and both
//       depths are positive; a match without parallax only needs e_t <= threshold (its depth sign
//       is noise). Each sample is scored for t and -t, which also fixes the sign of t.
//   (6) score                 MSAC (Torr and Zisserman, CVIU 2000): sum_i min(e_i^2, threshold^2)
//   (7) iterations            N = ceil(log(1 - confidence) / log(1 - w^2)), w the best
//       hypothesis' inlier share, updated when the best improves, at most max_iterations. It
//       assumes that a sample of two inliers gives a t near the best; with little parallax and
//       many outliers it need not (tests/frontends/two_point_ransac_test.cc, a weak scene).
//   (8) refit                 t = the eigenvector of the smallest eigenvalue of
//       M = sum_i n_i n_i^T / (|t' x g_i|^2 + |t' x f1_i|^2) over the inliers (least squares on
//       the Sampson errors (3), weights from the previous t'); the inliers are found again with
//       the new t, refine_rounds times at most, until they stop changing or the cost (6) stops
//       falling.
//   (9) one epipolar plane    t_perp = N x t / |N x t|, N the unit eigenvector of the largest
//       eigenvalue of sum_i n_i n_i^T over the parallax inliers (their dominant plane normal).
//       When every point lies on one plane through both centres, every direction in that plane
//       fits: t_perp, the farthest of them from t, explains the inliers as well as t does. The
//       direction counts as determined when enough parallax inliers of t have e_t(t_perp) >
//       threshold (the same count as for the pure-rotation test below).
//
// Pure rotation. When the translation is zero, or every point is far or on the epipole direction,
// the rotation alone explains the matches and t is not observable: any t fits, and the best one
// only gathers outliers that happen to lie near its epipolar circles. The translation is taken as
// observed when its inliers include enough matches with parallax (e_R > threshold):
// at least max(min_parallax_inliers, min_parallax_share x inliers). Otherwise the status is
// kPureRotation, t is undefined (zero) and the inliers are the matches with e_R <= threshold.
//
// Degenerate input gives a status with a reason, never an exception (DESIGN.md "Errors"): fewer
// than 2 usable matches; every epipolar plane the same (all normals n parallel: the points lie on
// one plane through both centres), detected when no sample has independent normals, when fewer
// than the required parallax inliers reject t_perp of (9), or when the refit leaves t uncertain
// by more than max_direction_uncertainty_rad. The last, local, test alone does not find the
// plane with noisy bearings: near the epipole the weights of (8) grow as 1 / |t x f|^2 and the
// curvature of the cost at t says nothing about directions 90 deg away.
//
// Thresholds are angles in radians; ThresholdFromPixels converts pixels at a focal length.
// five_point_ransac.h is OpenCV's 5-point essential-matrix RANSAC on the same matches with the
// same options and result, the baseline this method is compared with.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace mavloc {

struct EpipolarRansacOptions {
  // Inlier threshold on the errors (3) and (4), radians (ThresholdFromPixels: 1.4 px at 460 px).
  double threshold_rad = 0.003;
  double confidence = 0.999;  // of drawing one all-inlier sample, for the adaptive count (7)
  int max_iterations = 500;   // samples drawn at most
  // Samples drawn at least, whatever the adaptive count (7) says: (7) assumes that any all-inlier
  // sample gives the model, which a pair of matches with little parallax or close normals does
  // not (its direction is off by the noise over their small cross product). A 2-point sample costs
  // one cross product and one scoring pass: 100 of them cost about what one 5-point sample does.
  int min_iterations = 100;
  uint64_t seed = 1;  // sampling (the 5-point baseline uses OpenCV's fixed generator)
  // 2-point only: when the translation counts as observed (see "Pure rotation" above).
  int min_parallax_inliers = 6;
  double min_parallax_share = 0.2;
  int refine_rounds = 3;  // refits (8) after the sampling
  // The direction is degenerate when the refit fixes it only to within this angle (one sigma of
  // the rotation of t towards its weakest direction, with errors of half the threshold).
  double max_direction_uncertainty_rad = 0.2;
};

// The angle that threshold_px spans at the image centre of a camera with focal length focal_px.
inline double ThresholdFromPixels(double threshold_px, double focal_px) {
  return threshold_px / focal_px;
}

enum class EpipolarRansacStatus {
  kOk,             // t_C1_C0 estimated; inlier: the matches consistent with (R_C1_C0, t_C1_C0)
  kPureRotation,   // no parallax: t_C1_C0 undefined (zero); inlier: e_R <= threshold
  kTooFewMatches,  // fewer usable matches than a sample (2-point: 2, 5-point: 5)
  kDegenerate,     // the matches do not fix the direction of t (one common epipolar plane)
  kNoConsensus,    // no model gathered enough inliers (5-point: OpenCV found no matrix)
  kInvalidInput,   // f_C0 and f_C1 differ in size
};

std::string_view EpipolarRansacStatusName(EpipolarRansacStatus status);

struct EpipolarRansacResult {
  EpipolarRansacStatus status = EpipolarRansacStatus::kTooFewMatches;
  std::string reason;  // empty when kOk
  // One per match; every entry false unless kOk or kPureRotation. Unusable matches (a bearing not
  // finite or of zero length; for the 5-point also one at or behind the image plane) are outliers.
  std::vector<bool> inlier;
  int num_inliers = 0;
  int num_parallax_inliers = 0;                       // inliers with e_R > threshold (2-point only)
  Eigen::Vector3d t_C1_C0 = Eigen::Vector3d::Zero();  // unit when kOk, zero otherwise
  // The rotation used: the one given (2-point), or the one recovered from E (5-point, kOk).
  Eigen::Matrix3d R_C1_C0 = Eigen::Matrix3d::Identity();
  // 2-point: samples drawn. 5-point: the count OpenCV's adaptive rule stops at for the final
  // consensus, min(max_iterations, log(1 - confidence) / log(1 - w^5)): a lower bound on the
  // samples it drew (OpenCV does not report them).
  int iterations = 0;
  // 2-point, kOk: one sigma of the direction of t (radians) from the refit (8) with errors of
  // half the threshold; infinite when undetermined.
  double direction_uncertainty_rad = 0.0;

  bool ok() const { return status == EpipolarRansacStatus::kOk; }
  // The inlier mask is meaningful (kOk or kPureRotation).
  bool has_inliers() const { return ok() || status == EpipolarRansacStatus::kPureRotation; }
};

// The start of both RANSACs' results: false, with status kInvalidInput and the reason, when the
// two bearing lists differ in size; otherwise every match marked an outlier.
bool StartEpipolarResult(const std::vector<Eigen::Vector3d>& f_C0,
                         const std::vector<Eigen::Vector3d>& f_C1, EpipolarRansacResult* out);

// Rotation-aided 2-point RANSAC over the translation direction (equations (1)-(8) above). f_C0[i]
// and f_C1[i] are the bearings of match i (normalised here, so any positive length will do).
EpipolarRansacResult TwoPointRansac(const std::vector<Eigen::Vector3d>& f_C0,
                                    const std::vector<Eigen::Vector3d>& f_C1,
                                    const Eigen::Matrix3d& R_C1_C0,
                                    const EpipolarRansacOptions& options = {});

// The errors (3) and (4) of one match (unit bearings; t of any non-zero length).
double EpipolarSampsonError(const Eigen::Vector3d& f_C0, const Eigen::Vector3d& f_C1,
                            const Eigen::Matrix3d& R_C1_C0, const Eigen::Vector3d& t_C1_C0);
double RotationOnlyError(const Eigen::Vector3d& f_C0, const Eigen::Vector3d& f_C1,
                         const Eigen::Matrix3d& R_C1_C0);

// The adaptive count (7) for samples of sample_size matches: ceil(log(1 - confidence) /
// log(1 - w^sample_size)) within [1, max_iterations] (max_iterations when w = 0).
int RansacIterations(double confidence, double inlier_share, int sample_size, int max_iterations);

}  // namespace mavloc
