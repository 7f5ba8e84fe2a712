#include "solver/smoother/smoother_covariance.h"

#include <ceres/ceres.h>

#include <Eigen/SparseCholesky>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <tuple>
#include <unordered_map>
#include <unordered_set>

namespace mavloc {

// A named namespace: the library is compiled as a unity build, where file-local names must be
// unique across its sources.
namespace smoother_covariance_internal {

double ElapsedSeconds(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

// Takahashi's recurrences on raw compressed-column arrays (see SelectedInverse). z has the layout
// of lx. False when the pattern is not closed or a diagonal entry is not positive.
template <typename Scalar>
bool TakahashiInverse(int n, const int* lp, const int* li, const Scalar* lx, Scalar* z) {
  std::vector<int> local(n, -1);  // row -> position in the current column's off-diagonal pattern
  std::vector<Scalar> acc;
  for (int j = n - 1; j >= 0; --j) {
    const int begin = lp[j] + 1;  // first off-diagonal entry of column j
    const int end = lp[j + 1];
    const int m = end - begin;
    const Scalar l_jj = lx[lp[j]];
    if (!(l_jj > 0) || li[lp[j]] != j) return false;
    acc.assign(m, Scalar(0));
    for (int a = 0; a < m; ++a) local[li[begin + a]] = a;
    // acc[a] = sum_b L(r_b, j) Z(r_a, r_b) over the off-diagonal rows r_a, r_b of column j. The
    // entries Z(r_c, r_b), c > b, lie in column r_b (closed pattern), below its diagonal.
    bool closed = true;
    for (int b = 0; b < m; ++b) {
      const int r_b = li[begin + b];
      const Scalar l_b = lx[begin + b];
      acc[b] += l_b * z[lp[r_b]];  // Z(r_b, r_b)
      int found = 0;
      for (int q = lp[r_b] + 1; q < lp[r_b + 1]; ++q) {
        const int c = local[li[q]];
        if (c < 0) continue;
        acc[c] += l_b * z[q];
        acc[b] += lx[begin + c] * z[q];
        ++found;
      }
      if (found != m - 1 - b) closed = false;
    }
    for (int a = 0; a < m; ++a) local[li[begin + a]] = -1;
    if (!closed) return false;
    Scalar sum = 0;
    for (int a = 0; a < m; ++a) {
      z[begin + a] = -acc[a] / l_jj;
      sum += lx[begin + a] * z[begin + a];
    }
    z[lp[j]] = (1 / l_jj - sum) / l_jj;
  }
  return true;
}

// H, its factor and the selected inverse are in extended precision (smoother_covariance.h).
using Real = long double;

// The lower triangle of H = J^T J (compressed columns, rows sorted), J given by compressed rows
// whose column indices are sorted within each row, with explicit zeros at the extra (row >= col)
// positions. Every diagonal entry is present.
struct LowerInformation {
  std::vector<int> outer, inner;
  std::vector<Real> values;
};

LowerInformation AssembleLowerInformation(int num_rows, int num_cols, const std::vector<int>& rows,
                                          const std::vector<int>& cols,
                                          const std::vector<double>& values,
                                          std::vector<std::pair<int, int>> extra /* (col, row) */) {
  // Column access to J: for each entry, its position in the row storage (the row's entries after
  // it are its columns to the right).
  const int nnz = static_cast<int>(cols.size());
  std::vector<int> col_start(num_cols + 1, 0);
  for (int q = 0; q < nnz; ++q) ++col_start[cols[q] + 1];
  std::partial_sum(col_start.begin(), col_start.end(), col_start.begin());
  std::vector<int> by_col_position(nnz), by_col_row(nnz);
  {
    std::vector<int> next(col_start.begin(), col_start.end() - 1);
    for (int r = 0; r < num_rows; ++r)
      for (int q = rows[r]; q < rows[r + 1]; ++q) {
        const int slot = next[cols[q]]++;
        by_col_position[slot] = q;
        by_col_row[slot] = r;
      }
  }
  std::sort(extra.begin(), extra.end());

  LowerInformation h;
  h.outer.assign(num_cols + 1, 0);
  std::vector<int> mark(num_cols, -1);
  std::vector<Real> work(num_cols, Real(0));
  std::vector<int> pattern;
  size_t e = 0;
  for (int c = 0; c < num_cols; ++c) {
    pattern.clear();
    mark[c] = c;
    pattern.push_back(c);
    for (int slot = col_start[c]; slot < col_start[c + 1]; ++slot) {
      const int q0 = by_col_position[slot];
      const int row_end = rows[by_col_row[slot] + 1];
      const Real v = values[q0];
      for (int q = q0; q < row_end; ++q) {
        const int c2 = cols[q];
        if (mark[c2] != c) {
          mark[c2] = c;
          pattern.push_back(c2);
        }
        work[c2] += v * Real(values[q]);
      }
    }
    for (; e < extra.size() && extra[e].first == c; ++e) {
      const int r = extra[e].second;
      if (mark[r] != c) {
        mark[r] = c;
        pattern.push_back(r);
      }
    }
    std::sort(pattern.begin(), pattern.end());
    for (const int r : pattern) {
      h.inner.push_back(r);
      h.values.push_back(work[r]);
      work[r] = Real(0);
    }
    h.outer[c + 1] = static_cast<int>(h.inner.size());
  }
  return h;
}

// The stored entry (row, col), row >= col, of a compressed-column lower triangle.
template <typename Scalar>
Scalar LowerEntry(const Eigen::SparseMatrix<Scalar>& m, int row, int col) {
  const int* begin = m.innerIndexPtr() + m.outerIndexPtr()[col];
  const int* end = m.innerIndexPtr() + m.outerIndexPtr()[col + 1];
  const int* it = std::lower_bound(begin, end, row);
  if (it == end || *it != row) return std::numeric_limits<Scalar>::quiet_NaN();
  return m.valuePtr()[it - m.innerIndexPtr()];
}

}  // namespace smoother_covariance_internal

bool SelectedInverse(const Eigen::SparseMatrix<double>& L, Eigen::SparseMatrix<double>* Z) {
  if (L.rows() != L.cols() || !L.isCompressed()) return false;
  Eigen::SparseMatrix<double> result = L;
  if (!smoother_covariance_internal::TakahashiInverse(static_cast<int>(L.cols()), L.outerIndexPtr(),
                                                      L.innerIndexPtr(), L.valuePtr(),
                                                      result.valuePtr()))
    return false;
  *Z = std::move(result);
  return true;
}

SmootherCovariance::SmootherCovariance(const SmootherCovarianceOptions& options)
    : options_(options) {}

bool SmootherCovariance::Compute(
    const SmootherCovarianceLayout& layout,
    const std::vector<std::pair<const double*, const double*>>& covariance_blocks,
    ceres::Problem* problem, const std::vector<ceres::ResidualBlockId>* group) {
  using namespace smoother_covariance_internal;
  valid_ = false;
  message_.clear();
  statistics_ = SmootherCovarianceStatistics{};
  group_fit_ = ResidualGroupFit{};
  blocks_.clear();
  for (const auto& [a, b] : covariance_blocks) {
    if (!problem->HasParameterBlock(a) || !problem->HasParameterBlock(b)) {
      message_ = "a requested covariance block is not a parameter block of the problem";
      return false;
    }
  }

  // 1. Which blocks are columns (not constant, in a residual: ceres::Covariance's set), and each
  // one's last keyframe.
  auto t0 = std::chrono::steady_clock::now();
  std::unordered_map<const double*, int> keyframe_of;
  for (size_t k = 0; k < layout.keyframes.size(); ++k)
    for (const double* block : layout.keyframes[k]) keyframe_of[block] = static_cast<int>(k);
  std::unordered_map<const double*, int> last_keyframe;  // blocks in at least one residual
  {
    std::vector<ceres::ResidualBlockId> residual_blocks;
    problem->GetResidualBlocks(&residual_blocks);
    std::vector<double*> parameters;
    for (const ceres::ResidualBlockId id : residual_blocks) {
      problem->GetParameterBlocksForResidualBlock(id, &parameters);
      int latest = -1;
      for (const double* block : parameters) {
        auto it = keyframe_of.find(block);
        if (it != keyframe_of.end()) latest = std::max(latest, it->second);
      }
      for (const double* block : parameters) {
        auto [it, inserted] = last_keyframe.emplace(block, latest);
        if (!inserted) it->second = std::max(it->second, latest);
      }
    }
  }
  auto is_column = [&](const double* block) {
    return problem->HasParameterBlock(block) && last_keyframe.count(block) > 0 &&
           !problem->IsParameterBlockConstant(block);
  };

  // 2. The order: keyframe k's blocks, then the other blocks whose last keyframe is k; the blocks
  // no keyframe residual touches at the end.
  const int n_keyframes = static_cast<int>(layout.keyframes.size());
  std::vector<std::vector<const double*>> after(n_keyframes + 1);  // [n_keyframes]: the end
  std::unordered_set<const double*> placed;
  auto place_other = [&](const double* block) {
    if (!placed.insert(block).second || !is_column(block)) return;
    const int k = last_keyframe.at(block);
    after[k < 0 ? n_keyframes : k].push_back(block);
  };
  for (const auto& keyframe : layout.keyframes)
    for (const double* block : keyframe) placed.insert(block);
  for (const double* block : layout.others) place_other(block);
  {
    std::vector<double*> all;
    problem->GetParameterBlocks(&all);
    std::sort(all.begin(), all.end());
    for (const double* block : all) place_other(block);
  }
  std::vector<double*> ordered;
  for (int k = 0; k <= n_keyframes; ++k) {
    if (k < n_keyframes)
      for (const double* block : layout.keyframes[k])
        if (is_column(block)) ordered.push_back(const_cast<double*>(block));
    for (const double* block : after[k]) ordered.push_back(const_cast<double*>(block));
  }
  std::unordered_map<const double*, int> offset;
  int dimension = 0;
  for (const double* block : ordered) {
    if (!offset.emplace(block, dimension).second) {
      message_ = "a parameter block is listed twice in the covariance layout";
      return false;
    }
    dimension += problem->ParameterBlockTangentSize(block);
  }
  statistics_.dimension = dimension;

  // The requested blocks that are columns, and the (col, row) positions they need in H's pattern.
  std::vector<std::pair<int, int>> extra;
  for (const auto& [a, b] : covariance_blocks) {
    if (!offset.count(a) || !offset.count(b)) continue;
    const int oa = offset.at(a), ob = offset.at(b);
    const int sa = problem->ParameterBlockTangentSize(a);
    const int sb = problem->ParameterBlockTangentSize(b);
    for (int i = 0; i < sa; ++i)
      for (int j = 0; j < sb; ++j) {
        const int r = std::max(oa + i, ob + j), c = std::min(oa + i, ob + j);
        extra.emplace_back(c, r);
      }
  }
  std::sort(extra.begin(), extra.end());
  extra.erase(std::unique(extra.begin(), extra.end()), extra.end());

  Eigen::SparseMatrix<Real> Z;
  if (dimension > 0) {
    // 3. The Jacobian in the tangent space, in that column order.
    ceres::Problem::EvaluateOptions evaluate_options;
    evaluate_options.parameter_blocks = ordered;
    evaluate_options.apply_loss_function = true;  // as ceres::Covariance::Options' default
    evaluate_options.num_threads = std::max(1, options_.num_threads);
    ceres::CRSMatrix J;
    if (!problem->Evaluate(evaluate_options, nullptr, nullptr, nullptr, &J)) {
      message_ = "the Jacobian could not be evaluated";
      return false;
    }
    statistics_.residuals = J.num_rows;
    statistics_.jacobian_nonzeros = static_cast<long long>(J.values.size());
    // Ceres writes each row's columns in increasing order; sort where a row is not.
    for (int r = 0; r < J.num_rows; ++r) {
      const int b = J.rows[r], e = J.rows[r + 1];
      if (std::is_sorted(J.cols.begin() + b, J.cols.begin() + e)) continue;
      std::vector<std::pair<int, double>> entries;
      for (int q = b; q < e; ++q) entries.emplace_back(J.cols[q], J.values[q]);
      std::sort(entries.begin(), entries.end());
      for (int q = b; q < e; ++q) std::tie(J.cols[q], J.values[q]) = entries[q - b];
    }
    statistics_.jacobian_s = ElapsedSeconds(t0);

    // 4. H = J^T J (lower triangle).
    t0 = std::chrono::steady_clock::now();
    LowerInformation lower = AssembleLowerInformation(J.num_rows, J.num_cols, J.rows, J.cols,
                                                      J.values, std::move(extra));
    const int num_rows = J.num_rows;
    J = ceres::CRSMatrix();  // free it
    const Eigen::Map<const Eigen::SparseMatrix<Real>> H_map(
        dimension, dimension, static_cast<Eigen::Index>(lower.values.size()), lower.outer.data(),
        lower.inner.data(), lower.values.data());
    Eigen::SparseMatrix<Real> H = H_map;
    lower = LowerInformation();
    if (options_.regularization > 0.0) {
      for (int j = 0; j < dimension; ++j) {
        Real& h_jj = H.valuePtr()[H.outerIndexPtr()[j]];
        h_jj = h_jj > 0 ? h_jj * (1.0L + static_cast<Real>(options_.regularization)) : 1.0L;
      }
    }
    statistics_.information_nonzeros = H.nonZeros();
    Real max_diagonal = 0;
    std::vector<Real> diagonal(dimension);
    for (int j = 0; j < dimension; ++j) {
      diagonal[j] = H.valuePtr()[H.outerIndexPtr()[j]];  // the first entry of a lower column
      max_diagonal = std::max(max_diagonal, diagonal[j]);
    }
    statistics_.assembly_s = ElapsedSeconds(t0);

    // 5. H = L L^T in the given order.
    t0 = std::chrono::steady_clock::now();
    Eigen::SimplicialLLT<Eigen::SparseMatrix<Real>, Eigen::Lower, Eigen::NaturalOrdering<int>> llt;
    llt.compute(H);
    statistics_.factorization_s = ElapsedSeconds(t0);
    if (llt.info() != Eigen::Success) {
      message_ = "the information matrix is rank deficient (a pivot <= 0)";
      return false;
    }
    const Eigen::SparseMatrix<Real>& L = llt.matrixL().nestedExpression();
    statistics_.factor_nonzeros = L.nonZeros();
    // SuiteSparseQR's default rank tolerance (ceres::Covariance): 20 (m + n) eps max column norm.
    const Real qr_tolerance = 20.0L * (static_cast<Real>(num_rows) + dimension) *
                              std::numeric_limits<double>::epsilon() * std::sqrt(max_diagonal);
    statistics_.min_relative_pivot = std::numeric_limits<double>::infinity();
    int dependent = -1;
    for (int j = 0; j < dimension; ++j) {
      const Real l_jj = L.valuePtr()[L.outerIndexPtr()[j]];
      const double relative = static_cast<double>(l_jj * l_jj / diagonal[j]);
      if (relative < statistics_.min_relative_pivot) {
        statistics_.min_relative_pivot = relative;
        statistics_.weakest_column = j;
      }
      if (dependent < 0 && (l_jj <= qr_tolerance || relative <= options_.min_relative_pivot))
        dependent = j;
    }
    if (dependent >= 0 && options_.regularization <= 0.0) {
      message_ = "the Jacobian is rank deficient (column " + std::to_string(dependent) + " of " +
                 std::to_string(dimension) + " depends on the earlier ones)";
      return false;
    }

    // 6. Z = H^-1 on the pattern of L.
    t0 = std::chrono::steady_clock::now();
    Z = L;
    if (!TakahashiInverse(dimension, L.outerIndexPtr(), L.innerIndexPtr(), L.valuePtr(),
                          Z.valuePtr())) {
      message_ = "selected inversion failed (pattern not closed)";
      return false;
    }
    if (group && !FitGroup(*group, ordered, Z, problem)) return false;
  } else {
    t0 = std::chrono::steady_clock::now();
  }

  // 7. The requested blocks.
  for (const auto& [a, b] : covariance_blocks) {
    const int sa = problem->ParameterBlockTangentSize(a);
    const int sb = problem->ParameterBlockTangentSize(b);
    Eigen::MatrixXd block = Eigen::MatrixXd::Zero(sa, sb);
    if (offset.count(a) && offset.count(b)) {
      const int oa = offset.at(a), ob = offset.at(b);
      for (int i = 0; i < sa; ++i)
        for (int j = 0; j < sb; ++j)
          block(i, j) = static_cast<double>(
              LowerEntry(Z, std::max(oa + i, ob + j), std::min(oa + i, ob + j)));
    }
    blocks_[{a, b}] = std::move(block);
  }
  statistics_.inversion_s = ElapsedSeconds(t0);
  valid_ = true;
  return true;
}

// The group's chi2 and redundancy (ResidualGroupFit): per residual block, the entries of Z = H^-1
// on the columns its rows touch, and tr(Z_b J_b^T J_b) = sum over its rows of j^T Z_b j.
bool SmootherCovariance::FitGroup(const std::vector<ceres::ResidualBlockId>& group,
                                  const std::vector<double*>& ordered,
                                  const Eigen::SparseMatrix<long double>& Z,
                                  ceres::Problem* problem) {
  using namespace smoother_covariance_internal;
  ceres::Problem::EvaluateOptions evaluate_options;
  evaluate_options.parameter_blocks = ordered;
  evaluate_options.residual_blocks = group;
  evaluate_options.apply_loss_function = true;
  evaluate_options.num_threads = std::max(1, options_.num_threads);
  std::vector<double> residuals;
  ceres::CRSMatrix J;
  if (!problem->Evaluate(evaluate_options, nullptr, &residuals, nullptr, &J)) {
    message_ = "the Jacobian of the residual group could not be evaluated";
    return false;
  }
  long double trace = 0;
  int row = 0;
  std::vector<int> columns;
  for (const ceres::ResidualBlockId id : group) {
    const int rows = problem->GetCostFunctionForResidualBlock(id)->num_residuals();
    columns.clear();
    for (int r = row; r < row + rows; ++r)
      columns.insert(columns.end(), J.cols.begin() + J.rows[r], J.cols.begin() + J.rows[r + 1]);
    std::sort(columns.begin(), columns.end());
    columns.erase(std::unique(columns.begin(), columns.end()), columns.end());
    const int m = static_cast<int>(columns.size());
    Eigen::Matrix<long double, Eigen::Dynamic, Eigen::Dynamic> Z_b(m, m);
    for (int a = 0; a < m; ++a)
      for (int b = 0; b <= a; ++b) {
        const long double z = LowerEntry(Z, columns[a], columns[b]);  // columns sorted: a >= b
        if (std::isnan(static_cast<double>(z))) {
          message_ = "a residual of the group couples columns off the factor's pattern";
          return false;
        }
        Z_b(a, b) = Z_b(b, a) = z;
      }
    Eigen::Matrix<long double, Eigen::Dynamic, 1> j(m);
    for (int r = row; r < row + rows; ++r) {
      j.setZero();
      for (int q = J.rows[r]; q < J.rows[r + 1]; ++q) {
        const int a = static_cast<int>(std::lower_bound(columns.begin(), columns.end(), J.cols[q]) -
                                       columns.begin());
        j(a) = J.values[q];
      }
      trace += j.dot(Z_b * j);
      group_fit_.chi2 += residuals[r] * residuals[r];
    }
    row += rows;
  }
  group_fit_.residuals = row;
  group_fit_.redundancy = static_cast<double>(row - trace);
  return true;
}

bool SmootherCovariance::GetCovarianceBlockInTangentSpace(const double* a, const double* b,
                                                          double* block) const {
  if (!valid_) return false;
  auto it = blocks_.find({a, b});
  bool transpose = false;
  if (it == blocks_.end()) {
    it = blocks_.find({b, a});
    transpose = true;
    if (it == blocks_.end()) return false;
  }
  const Eigen::MatrixXd& m = it->second;
  const Eigen::Index rows = transpose ? m.cols() : m.rows();
  const Eigen::Index cols = transpose ? m.rows() : m.cols();
  Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> out(
      block, rows, cols);
  if (transpose)
    out = m.transpose();
  else
    out = m;
  return true;
}

}  // namespace mavloc
