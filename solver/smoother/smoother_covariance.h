// Marginal covariances of the batch smoother (solver/smoother/smoother_problem.h) in time linear in
// the number of keyframes: the blocks ceres::Covariance would return, computed from the problem's
// structure instead of by one sparse triangular solve per requested column.
//
// 1. The Jacobian J at the solution, in the tangent space (Problem::Evaluate with a CRS Jacobian,
//    robust-loss corrections applied: the same rows ceres::Covariance evaluates), over the
//    parameter blocks that are not constant and appear in a residual (ceres::Covariance's set; the
//    others have zero covariance), in an explicit order:
//    keyframe 0's blocks, the blocks whose last residual is at keyframe 0, keyframe 1's blocks, ...
//    A block's "last keyframe" is the latest keyframe any residual that touches it also touches;
//    blocks no keyframe residual touches come last. So the calibration blocks (extrinsics, time
//    offset, board tilt), the plane and the landmarks seen through the whole flight form the border
//    of an arrow-head matrix, and a landmark seen over a few keyframes is eliminated right after
//    them.
// 2. H = J^T J, lower triangle, as a sparse matrix, plus explicit zeros where a requested block is
//    not already in the pattern (so every requested entry is in the factor's pattern).
// 3. H = L L^T by a simplicial sparse Cholesky (Eigen) in that order, no fill-reducing permutation:
//    eliminating the chain in time order fills nothing outside the band of two keyframes (IMU
//    factors couple consecutive keyframes only) plus the border rows, so L has O(n) entries.
//    Eliminating the landmarks first (Schur complement) would instead couple every keyframe that
//    sees a landmark: for the ground features of the three-point world (seen from every keyframe)
//    the reduced system is dense, O(n^2) memory and O(n^3) time (the solver avoids SPARSE_SCHUR for
//    the same reason).
// 4. The entries of Z = H^-1 on the pattern of L by Takahashi's recurrences (selected inversion),
//    from the last column to the first:
//      Z_ij = -(1 / L_jj) sum_{k > j} L_kj Z_ik   (i > j in the pattern of column j),
//      Z_jj = 1 / L_jj^2 - (1 / L_jj) sum_{k > j} L_kj Z_kj.
//    The symbolic pattern of a Cholesky factor is closed (L_ij and L_kj in it imply L_ik or L_ki in
//    it), so every Z_ik needed is already computed. Cost: sum over columns of (entries of the
//    column)^2, the same order as the factorization.
//
// Precision. H, L and Z are computed in extended precision (long double: the x87 80-bit format on
// x86-64, eps = 1.1e-19; J is Ceres' double). Cholesky of J^T J loses twice the digits a QR
// factorization of J loses (cond(J^T J) = cond(J)^2): in double the pose covariances of
// three-point-hover and aprilgrid-calibration differed from ceres::Covariance's QR by up to
// 7e-9 relative; in extended precision by at most 3e-12 (tests/evaluation/
// smoother_covariance_test.cc). On a platform whose long double is double, the 1e-9 agreement
// would not hold for the worse-conditioned problems; where it is a software quad, it is slow.
//
// Rank deficiency (gauge freedom) makes Compute return false, as ceres::Covariance does
// (SPARSE_QR: the rank SuiteSparseQR finds is below the number of columns). A column j is taken as
// dependent on the earlier ones when
// - its pivot is not positive (the factorization stops), or
// - L_jj <= 20 (m + n) eps_double max_k |J_k|, SuiteSparseQR's default tolerance on the same
//   quantity (in exact arithmetic L_jj is the norm of what is left of column j of J after the
//   earlier ones, as |R_jj| is in QR), or
// - L_jj^2 <= min_relative_pivot H_jj (1e-10): the rounding of a long chain leaves the pivot of an
//   exact null direction well above eps |J_j|^2. Measured in extended precision, the smallest
//   pivot of a rank-deficient problem: 9e-20 (a landmark seen once), 1e-17 (free landmarks of
//   mav-figure-eight triangulated from nearly parallel rays), 3e-15..7e-13 (laser-plane, 10-120 s:
//   its spots leave three directions free besides the gauge the smoother fixes; its other null
//   pivots reach 5e-11 or come out negative); of the well-posed problems 1.4e-5..7e-3, flat in
//   the flight length (mav-figure-eight: 5.6e-5 at 60, 300 and 600 s). A problem whose weakest
//   direction lies between the two (scaled condition number above 1e10; laser-plane's weak
//   in-plane modes: 4e-11..1e-8) is reported as rank deficient where Ceres' QR might still invert
//   it: its covariance would not be accurate to 1e-9 here anyway.
#pragma once

#include <ceres/problem.h>
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace mavloc {

// Which parameter blocks are keyframes (in time order); see the header comment for the order.
struct SmootherCovarianceLayout {
  // Per keyframe, in time order, its parameter blocks (q, p, v, b_g, b_a in the smoother).
  std::vector<std::vector<const double*>> keyframes;
  // The other blocks (landmarks, plane, calibration): placed after their last keyframe, in this
  // order among blocks of the same keyframe. Blocks of the problem in neither list are appended
  // after these, ordered by address.
  std::vector<const double*> others;
};

struct SmootherCovarianceOptions {
  int num_threads = 1;  // Jacobian evaluation
  // A pivot L_jj^2 <= min_relative_pivot H_jj makes the problem rank deficient (header comment).
  double min_relative_pivot = 1e-10;
  // > 0: H + regularization diag(H) is factored and the rank tests are skipped. For the residual
  // group fit of a problem with free directions (laser-only data): those directions are null in
  // every residual, so tr((H + eps D)^-1 J_g^T J_g) tends to tr(H^+ J_g^T J_g) as eps -> 0. The
  // covariance blocks of a regularized problem are not the problem's.
  double regularization = 0.0;
};

struct SmootherCovarianceStatistics {
  int dimension = 0;  // tangent-space columns of J
  int residuals = 0;  // rows of J
  long long jacobian_nonzeros = 0;
  long long information_nonzeros = 0;  // lower triangle of H, with the explicit zeros
  long long factor_nonzeros = 0;       // L
  double min_relative_pivot = 0.0;     // min_j L_jj^2 / H_jj
  int weakest_column = -1;             // where it is attained
  double jacobian_s = 0.0;             // ordering + Problem::Evaluate
  double assembly_s = 0.0;             // J^T J
  double factorization_s = 0.0;
  double inversion_s = 0.0;  // selected inversion + extraction of the blocks
};

// How much of a group of residuals the solution explains (variance component estimation:
// Koch, "Parameter Estimation and Hypothesis Testing in Linear Models", 1999, sec. 3.6.4; Förstner
// 1979). For whitened residuals v_g of n_g rows and Jacobian J_g at the solution, with
// H = J^T J over all residuals, the group's redundancy is r_g = n_g - tr(H^-1 J_g^T J_g), and
// E[v_g^T v_g] = r_g when the group's stated noise is right, so chi2 / redundancy estimates the
// factor by which its variances are off. The trace needs H^-1 only on the blocks the group's rows
// touch together, which lie on the factor's pattern when each residual of the group couples
// consecutive keyframes (IMU factors).
struct ResidualGroupFit {
  int residuals = 0;        // n_g
  double chi2 = 0.0;        // v_g^T v_g at the solution
  double redundancy = 0.0;  // n_g - tr(H^-1 J_g^T J_g)
  double VarianceFactor() const { return redundancy > 0.0 ? chi2 / redundancy : 0.0; }
};

class SmootherCovariance {
 public:
  explicit SmootherCovariance(const SmootherCovarianceOptions& options = {});

  // Computes the requested blocks (pairs of parameter blocks of the problem, as for
  // ceres::Covariance::Compute). False when the Jacobian is rank deficient or cannot be evaluated
  // (message() says which); the blocks are then unavailable.
  // With group (residual blocks of the problem), also the group's fit (group_fit()); Compute is
  // false when a pair of columns that one of its residual blocks touches is not on the factor's
  // pattern.
  bool Compute(const SmootherCovarianceLayout& layout,
               const std::vector<std::pair<const double*, const double*>>& covariance_blocks,
               ceres::Problem* problem, const std::vector<ceres::ResidualBlockId>* group = nullptr);

  // As ceres::Covariance::GetCovarianceBlockInTangentSpace: the row-major tangent_size(a) x
  // tangent_size(b) block; zeros when either block is constant or in no residual. False when the
  // pair (in either order) was not requested or Compute failed.
  bool GetCovarianceBlockInTangentSpace(const double* a, const double* b, double* block) const;

  const std::string& message() const { return message_; }
  const SmootherCovarianceStatistics& statistics() const { return statistics_; }
  const ResidualGroupFit& group_fit() const { return group_fit_; }

 private:
  bool FitGroup(const std::vector<ceres::ResidualBlockId>& group,
                const std::vector<double*>& ordered, const Eigen::SparseMatrix<long double>& Z,
                ceres::Problem* problem);

  ResidualGroupFit group_fit_;
  SmootherCovarianceOptions options_;
  bool valid_ = false;
  std::string message_;
  SmootherCovarianceStatistics statistics_;
  std::map<std::pair<const double*, const double*>, Eigen::MatrixXd> blocks_;  // as requested
};

// Selected inversion: L a lower-triangular Cholesky factor (column-major, row indices sorted in
// each column, the diagonal first, a closed pattern as a symbolic factorization gives), returns
// Z = (L L^T)^-1 on the pattern of L (lower triangle, same layout). False, leaving *Z unchanged,
// when the pattern is not closed or the diagonal is not positive.
bool SelectedInverse(const Eigen::SparseMatrix<double>& L, Eigen::SparseMatrix<double>* Z);

}  // namespace mavloc
